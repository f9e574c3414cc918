"""The manual's build fails on each kind of problem the Makefile promises to catch: a broken link, a broken
anchor, a missing picture, a page in no toctree, a malformed web link; an open toctree slot (a glob no page
matches yet) does not. Built as `make docs` builds (sphinx-build -E -W --keep-going -n) on a small project
with the manual's own link settings and extensions."""

import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("sphinx")
pytest.importorskip("myst_parser")

EXTENSIONS = Path(__file__).resolve().parents[2] / "docs" / "_ext"
CONF = f"""
import sys
sys.path.insert(0, {str(EXTENSIONS)!r})
extensions = ["myst_parser", "toctree_slots", "web_links"]
source_suffix = {{".md": "markdown"}}
myst_heading_anchors = 4
toctree_slots = ["user/*"]
"""
INDEX = """# Manual

```{toctree}
:glob:

user/first
user/*
```
"""
FIRST = "# First\n\n## A heading\n\nText.\n"


def build(tmp_path: Path, page: str, extra: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    source = tmp_path / "docs"
    (source / "user").mkdir(parents=True)
    (source / "conf.py").write_text(CONF)
    (source / "index.md").write_text(INDEX)
    (source / "user" / "first.md").write_text(FIRST + page)
    for name, text in (extra or {}).items():
        (source / name).write_text(text)
    return subprocess.run(
        [sys.executable, "-m", "sphinx", "-E", "-W", "--keep-going", "-n", "-q", "-b", "html", str(source),
         str(tmp_path / "html")],
        capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip


def test_a_sound_manual_with_an_empty_slot_builds(tmp_path):
    run = build(
        tmp_path, "[the heading](#a-heading), [the index](../index.md), [web](https://example.org/x)\n"
    )
    assert run.returncode == 0, run.stderr


@pytest.mark.parametrize(
    ("page", "extra", "says"),
    [
        ("[gone](gone.md)\n", None, "cross-reference target not found"),
        ("[gone](../index.md#no-such-heading)\n", None, "local id not found"),
        ("![a picture](../images/none.png)\n", None, "image file not readable"),
        ("Text.\n", {"orphan.md": "# Orphan\n"}, "document isn't included in any toctree"),
        ("[web](http:/example.org)\n", None, "malformed web link"),
    ],
    ids=["broken link", "broken anchor", "missing picture", "page in no toctree", "malformed web link"],
)
def test_the_build_fails_on(tmp_path, page, extra, says):
    run = build(tmp_path, page, extra)
    assert run.returncode != 0
    assert says in run.stderr
