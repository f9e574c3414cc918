"""python -m turkish_lipsync export and --cues: the exports from the command line, and cue files read back."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from turkish_lipsync.core.interchange import export_formats
from turkish_lipsync.core.interchange.arkit_csv import read_arkit_csv
from turkish_lipsync.core.speech.cues import read_cue_file

ROOT = Path(__file__).resolve().parents[2]
TEXT = "Merhaba, benim adım Erdem."


def run(*args):
    return subprocess.run(
        [sys.executable, "-m", "turkish_lipsync", *args],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
    )


def _timeline(*args):
    result = run("timeline", *args, "--format", "json")
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


@pytest.mark.parametrize("export_format", [f for f in export_formats() if f != "arkit-csv"])
def test_each_cue_format_times_the_text_as_the_timeline_does(tmp_path, export_format):
    out = tmp_path / f"speech{export_formats()[export_format].suffix}"
    result = run("export", "--text", TEXT, "--timing", "table", "--format", export_format, "--out", str(out))
    assert result.returncode == 0, result.stderr
    timeline = _timeline("--text", TEXT, "--timing", "table")
    cues = read_cue_file(out, fps=25).cues
    # every word starts, within a frame, where a cue starts
    for word in timeline["words"]:
        assert min(abs(cue.start - word["start"]) for cue in cues) <= 1 / 25, word
    reread = _timeline("--text", TEXT, "--cues", str(out))
    assert reread["timing"] == "cues"
    for original, word in zip(timeline["words"], reread["words"], strict=True):
        assert abs(original["start"] - word["start"]) <= 1 / 25


def test_arkit_csv_has_a_row_per_frame(tmp_path):
    out = tmp_path / "speech.csv"
    result = run(
        "export",
        "--text",
        TEXT,
        "--timing",
        "table",
        "--fps",
        "30",
        "--format",
        "arkit-csv",
        "--out",
        str(out),
    )
    assert result.returncode == 0, result.stderr
    frames, weights = read_arkit_csv(out, 30)
    duration = _timeline("--text", TEXT, "--timing", "table")["duration"]
    assert len(frames) == round(duration * 30) and weights.shape[1] == 52  # the frames a video of it shows


def test_the_pgo_brings_its_text_and_sound(tmp_path):
    pgo, wav = tmp_path / "speech.pgo", tmp_path / "speech.wav"
    result = run("export", "--text", TEXT, "--format", "papagayo-pgo", "--out", str(pgo), "--wav", str(wav))
    assert result.returncode == 0, result.stderr
    assert pgo.read_text(encoding="utf-8").splitlines()[1] == "speech.wav"
    again = tmp_path / "again.wav"
    result = run("timeline", "--cues", str(pgo), "--wav", str(again))  # no text: the project's own
    assert result.returncode == 0, result.stderr
    assert again.read_bytes()[44:] == wav.read_bytes()[44:]


def test_rhubarb_cues_need_the_text(tmp_path):
    out = tmp_path / "speech.tsv"
    assert (
        run(
            "export", "--text", TEXT, "--timing", "table", "--format", "rhubarb-tsv", "--out", str(out)
        ).returncode
        == 0
    )
    result = run("timeline", "--cues", str(out))
    assert result.returncode == 2 and "holds no text" in result.stderr


def test_an_output_that_is_an_input_is_refused_and_nothing_changes(tmp_path):
    script = tmp_path / "speech.jsml"
    script.write_text("Merhaba, benim adım Erdem.", encoding="utf-8")
    take = tmp_path / "take.wav"
    assert run("timeline", str(script), "--wav", str(take)).returncode == 0
    before = {path: path.read_bytes() for path in (script, take)}
    cases = [
        (("export", str(script), "--audio", str(take), "--wav", str(take)), "--wav"),
        (
            ("export", str(script), "--out", str(tmp_path / "x"), "--wav", str(tmp_path / "x")),
            "another output",
        ),
        (("export", str(script), "--out", str(script)), "--out"),
        (("timeline", str(script), "--wav", str(script)), "same file as FILE"),
    ]
    for arguments, message in cases:
        result = run(*arguments, "--format", "rhubarb-tsv" if arguments[0] == "export" else "tsv")
        assert result.returncode == 2 and message in result.stderr, result.stderr
        assert len(result.stderr.strip().splitlines()) == 1
    assert {path: path.read_bytes() for path in (script, take)} == before
