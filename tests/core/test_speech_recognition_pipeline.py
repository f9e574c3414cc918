"""A recording without its text goes through every stage: the timing source, lip_sync, the command line."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from lab.kit.corpus import held_out_sentences
from lab.kit.voices import TEST_VOICES, make_take
from turkish_lipsync.core.base.model import viseme_key_name
from turkish_lipsync.core.base.visemes import BILABIAL_VISEMES
from turkish_lipsync.core.pipeline import LipSyncOptions, lip_sync
from turkish_lipsync.core.speech.sources import SpeechRequest, timing_source_for

REPOSITORY = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def take(tmp_path_factory):
    """A held-out sentence with b, m and p in a held-out voice, 30 dB room noise after 1 s of noise."""
    text = next(line for line in held_out_sentences() if sum(line.count(c) for c in "bmp") >= 4)
    folder = tmp_path_factory.mktemp("take")
    path, truth, lead, _ = make_take(
        text, TEST_VOICES["Andrea"], "30 dB, leading noise", folder, np.random.default_rng(8)
    )
    return path.rename(folder / "kayit.wav"), truth, lead


def test_a_recording_without_text_is_recognised_and_with_text_aligned(take):
    path, *_ = take
    assert timing_source_for(SpeechRequest(text="", recording=path)).name == "recognised"
    assert timing_source_for(SpeechRequest(text="  \n", recording=path)).name == "recognised"
    assert timing_source_for(SpeechRequest(text="merhaba", recording=path)).name == "recording"
    assert timing_source_for(SpeechRequest(text="", recording=path, cues=path)).name == "cues"


def test_lip_sync_keys_the_heard_closures(take):
    path, truth, lead = take
    result = lip_sync("", LipSyncOptions(recording=path, fps=25))
    assert result.timeline.timing == "recognised" and result.synthesis.engine == "recording"
    assert result.timeline.emotions == () and result.tracks.fps == 25
    closures = [phone for phone in result.timeline.phones if phone.viseme in BILABIAL_VISEMES]
    assert closures
    for phone in closures:  # the mouth shuts on each heard bilabial: its key reaches full weight
        track = result.tracks.track(viseme_key_name(phone.viseme))
        frames = np.arange(np.floor(phone.start * 25), np.ceil(phone.end * 25) + 1)
        assert np.interp(frames, track.frames, track.values).max() > 0.99


def test_the_command_line_prints_the_timeline_of_a_recording_alone(take, tmp_path):
    path, truth, lead = take
    result = subprocess.run(
        [sys.executable, "-m", "turkish_lipsync", "timeline", "--audio", str(path), "--format", "json"],
        capture_output=True, text=True, cwd=REPOSITORY, timeout=300, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    assert data["timing"] == "recognised" and data["emotions"] == []
    assert len(data["phones"]) > 20 and data["tracks"]["keys"]
    assert data["phones"][0]["start"] > lead - 0.15
    tsv = subprocess.run(
        [sys.executable, "-m", "turkish_lipsync", "timeline", "--audio", str(path)],
        capture_output=True, text=True, cwd=REPOSITORY, timeout=300, check=False,
    )  # fmt: skip
    assert tsv.returncode == 0 and tsv.stdout.startswith("# timing recognised")
    cues = tmp_path / "cues.json"
    exported = subprocess.run(
        [sys.executable, "-m", "turkish_lipsync", "export", "--audio", str(path), "--format", "rhubarb-json",
         "--out", str(cues)],
        capture_output=True, text=True, cwd=REPOSITORY, timeout=300, check=False,
    )  # fmt: skip
    assert exported.returncode == 0, exported.stderr
    shapes = [cue["value"] for cue in json.loads(cues.read_text())["mouthCues"]]
    assert "A" in shapes and shapes[0] == "X"  # closed lips (A) heard, rest before the first word


def test_a_silent_recording_is_one_clear_error(tmp_path):
    from lab.kit.takes import write_wav

    silent = write_wav(tmp_path / "sessiz.wav", np.zeros(32_000), 16_000)
    result = subprocess.run(
        [sys.executable, "-m", "turkish_lipsync", "timeline", "--audio", str(silent)],
        capture_output=True, text=True, cwd=REPOSITORY, timeout=300, check=False,
    )  # fmt: skip
    assert result.returncode == 2
    assert result.stderr.strip().count("\n") == 0 and "no speech found" in result.stderr
    assert "Traceback" not in result.stderr
