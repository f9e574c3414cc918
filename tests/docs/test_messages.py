"""Every message a user can meet is read from the code for the troubleshooting page (docs/_ext/messages.py):
none is missed, and a message in a file no group covers is found."""

import re
import sys
from pathlib import Path

import pytest

pytest.importorskip("sphinx")
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "docs" / "_ext"))

import messages  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def test_every_raise_of_the_error_family_is_collected():
    """Read independently of the collector: each `raise SomeError(` line of the family in the sources."""
    internal = "|".join(messages.INTERNAL_ERRORS)
    collected = {(message.path, message.line) for message in messages.collect_messages()}
    missed = []
    for path in messages.source_files():
        relative = path.relative_to(ROOT).as_posix()
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
            # a raise of messages made (and collected) elsewhere, gathered or passed on, holds none of its own
            gathered = re.search(r"raise [\w.]*Error\((sorted\(|str\()?[a-z_.]+[,)]", line)
            if re.search(r"raise [\w.]*Error\(", line) and not re.search(rf"raise ({internal})\(", line):
                if gathered:
                    continue
                # the message starts on this line or within the next three (a call broken over lines)
                if not any((relative, number + offset) in collected for offset in range(4)):
                    missed.append(f"{relative}:{number}: {line.strip()}")
    assert missed == []


def test_known_messages_of_every_kind_are_found():
    found = {(message.kind, message.template) for message in messages.collect_messages()}
    assert ("error", "recording {name} is silent (no speech found); record the text again") in found
    assert ("disabled", "Switch to Object Mode first") in found
    assert any(
        kind == "warning" and text.startswith("the recording seems not to say") for kind, text in found
    )
    assert any(
        kind == "error" and text.startswith("--out {arguments.out} must end in .mp4") for kind, text in found
    )


def test_an_episodes_gathered_problems_and_checks_are_errors():
    found = {(message.kind, message.template) for message in messages.collect_messages()}
    assert ("error", "{name} does not fit scene {path.stem}: it is {kind}") in found  # manifest.problem(...)
    assert ("error", "the scene's file is empty") in found  # manifest.problem_at(...)
    assert ("error", "must be true or false") in found  # a check returning a Problem
    assert not any(kind == "disabled" and "episode" in path for kind, _, path in _kinds_and_paths())


def _kinds_and_paths():
    return {(message.kind, message.template, message.path) for message in messages.collect_messages()}


def test_every_file_with_messages_is_in_a_group():
    assert [
        message for message in messages.collect_messages() if messages.group_of(message.path) is None
    ] == []


def test_a_message_in_a_new_file_is_in_no_group_until_one_covers_it(tmp_path):
    package = tmp_path / "turkish_lipsync" / "core" / "faces"
    package.mkdir(parents=True)
    (package / "errors.py").write_text(
        "class LipSyncError(Exception): ...\nclass HeadError(LipSyncError): ...\n"
    )
    (package / "new_stage.py").write_text(
        "from .errors import HeadError\n\n"
        "def check(head):\n"
        "    warnings = []\n"
        "    warnings.append(f'{head} looks odd')\n"
        "    raise HeadError(f'No face on {head.name!r}; place the markers.')\n"
    )
    (tmp_path / "scripts").mkdir()
    (tmp_path / "scripts" / "render.py").write_text("")  # an entry point without messages
    found = messages.collect_messages(tmp_path)
    assert [(m.kind, m.template, m.path) for m in found] == [
        ("warning", "{head} looks odd", "turkish_lipsync/core/faces/new_stage.py"),
        ("error", "No face on {head.name}; place the markers.", "turkish_lipsync/core/faces/new_stage.py"),
    ]
    assert messages.group_of("turkish_lipsync/core/faces/new_stage.py") == "heads"
    assert messages.group_of("turkish_lipsync/core/conversation/turns.py") is None
