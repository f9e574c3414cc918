"""Cue files as the timing source: our letters' visemes, timed by Rhubarb or Papagayo files."""

import json

import numpy as np
import pytest

from turkish_lipsync.core.speech import synthesize_timeline
from turkish_lipsync.core.speech.cue_timing import timeline_from_cues
from turkish_lipsync.core.speech.cues import CueFileError, cue_formats, read_cue_file
from turkish_lipsync.core.text.utterance import build_utterance

FPS = 25.0
TEXT = "Merhaba, benim adım Erdem. Bu sabah vapura binip karşıya geçti; akşam dönecek."


@pytest.fixture(scope="module")
def timeline():
    return synthesize_timeline(build_utterance(TEXT), "phone").timeline


def _write(tmp_path, timeline, export_format, suffix):
    path = tmp_path / f"cues{suffix}"
    path.write_text(cue_formats()[export_format].write(timeline, FPS)[0], encoding="utf-8")
    return path


@pytest.mark.parametrize(
    "export_format,suffix",
    [("rhubarb-tsv", ".tsv"), ("rhubarb-json", ".json"), ("papagayo-pgo", ".pgo"), ("moho-dat", ".dat")],
)
def test_cues_of_a_timeline_give_its_timing_back(tmp_path, timeline, export_format, suffix):
    source = read_cue_file(_write(tmp_path, timeline, export_format, suffix), fps=FPS)
    imported, warnings = timeline_from_cues(build_utterance(source.text or TEXT), source)
    assert warnings == () and imported.timing == "cues"
    original = np.array([phone.start for phone in timeline.phones])
    starts = np.array([phone.start for phone in imported.phones])
    assert (np.diff(starts) >= 0).all()
    within_a_frame = np.abs(starts - original) <= 1 / FPS
    assert within_a_frame.mean() >= 0.9
    word_error = [abs(a.start - b.start) for a, b in zip(timeline.words, imported.words, strict=True)]
    assert max(word_error) <= 1 / FPS


def test_pgo_text_is_the_source(tmp_path, timeline):
    source = read_cue_file(_write(tmp_path, timeline, "papagayo-pgo", ".pgo"))
    assert source.text.split() == [word.text for word in timeline.words]
    assert source.word_cues and len(source.word_cues) == len(timeline.words)


def test_a_stretched_recording_keeps_the_letters_in_place(tmp_path, timeline):
    """Cues of a slower reading (every time x1.4, plus 0.3 s of lead-in): the letters follow them."""
    path = _write(tmp_path, timeline, "rhubarb-json", ".json")
    document = json.loads(path.read_text(encoding="utf-8"))
    for cue in document["mouthCues"]:
        cue["start"], cue["end"] = (0.3 + 1.4 * cue["start"], 0.3 + 1.4 * cue["end"])
    document["mouthCues"].insert(0, {"start": 0.0, "end": 0.3, "value": "X"})
    document["mouthCues"][1]["start"] = 0.3
    path.write_text(json.dumps(document), encoding="utf-8")
    imported, _ = timeline_from_cues(build_utterance(TEXT), read_cue_file(path))
    for original, word in zip(timeline.words, imported.words, strict=True):
        assert abs(word.start - (0.3 + 1.4 * original.start)) <= 1.4 / FPS


def test_a_pause_the_text_does_not_have_is_bridged(tmp_path, timeline):
    """A rest in the middle of a phrase (the speaker hesitated) does not shift the words after it."""
    path = _write(tmp_path, timeline, "rhubarb-tsv", ".tsv")
    lines = path.read_text(encoding="utf-8").splitlines()
    starts = [float(line.split("\t")[0]) for line in lines]
    vapura = timeline.words[6]
    assert vapura.text == "vapura"
    # shorten the cue before "vapura" starts and rest for 30 ms
    index = max(i for i, start in enumerate(starts) if start < vapura.start - 0.05)
    lines.insert(index + 1, f"{vapura.start - 0.03:.3f}\tX")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    imported, _ = timeline_from_cues(build_utterance(TEXT), read_cue_file(path))
    for original, word in zip(timeline.words, imported.words, strict=True):
        assert abs(word.start - original.start) <= 1 / FPS, word


def test_a_file_without_speech_is_refused(tmp_path):
    path = tmp_path / "silence.tsv"
    path.write_text("0.00\tX\n1.50\tX\n", encoding="utf-8")
    with pytest.raises(CueFileError, match="no speech"):
        timeline_from_cues(build_utterance("merhaba"), read_cue_file(path))


def test_an_unknown_file_type_is_named(tmp_path):
    with pytest.raises(CueFileError, match=r"\.srt"):
        read_cue_file(tmp_path / "speech.srt")


def test_a_stretch_too_long_to_align_asks_for_punctuation(tmp_path):
    text = " ".join(["merhaba benim adım erdem"] * 110)  # 2,420 letters, no pause
    path = tmp_path / "long.tsv"
    path.write_text("".join(f"{i * 0.05:.2f}\t{'ABCD'[i % 4]}\n" for i in range(2000)) + "100.00\tX\n")
    with pytest.raises(CueFileError, match="put punctuation where the speaker pauses"):
        timeline_from_cues(build_utterance(text), read_cue_file(path))
