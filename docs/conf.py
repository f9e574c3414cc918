"""Sphinx configuration of the manual: Markdown pages (MyST), built with warnings as errors.

    .venv/bin/sphinx-build -W --keep-going -n -b html docs build/docs      (make docs)

Broken internal links and anchors, missing pictures and pages outside every toctree are Sphinx's and MyST's
own warnings; _ext/ adds the generated panel reference (panel_reference.py) and a check that every link
to the web is well formed without fetching it (web_links.py): the build never touches the network.
"""

from __future__ import annotations

import sys
import tomllib
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(DOCS / "_ext"))
sys.path.insert(0, str(ROOT))  # turkish_lipsync itself, for the panel reference

_manifest = tomllib.loads((ROOT / "blender_manifest.toml").read_text(encoding="utf-8"))

project = _manifest["name"]
author = _manifest["maintainer"]
release = version = _manifest["version"]
copyright = f"{author}, {_manifest['license'][0].removeprefix('SPDX:')}"

extensions = ["myst_parser", "command_help", "messages", "panel_reference", "toctree_slots", "web_links"]
# Pages added to these folders join the index by themselves (after the pages it names), so the globs may be
# empty until someone adds one.
toctree_slots = ["user/*", "developer/*"]
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_ext", "README.md"]

# [text](page.md#a-heading) links are checked against the headings' anchors down to level 4.
myst_heading_anchors = 4
myst_enable_extensions = ["colon_fence", "deflist"]

html_theme = "furo"
html_title = f"{project} {version}"
html_static_path: list[str] = []
html_show_sourcelink = False

# Nothing on the web is fetched (the build machines have no internet): web_links.py checks the form only.
linkcheck_ignore = [r".*"]
