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


def _naive_pairing(gaps, pauses):
    """The pairing as first written: bridge the shortest rest, or join the shortest pause, one at a time.
    Returns the first original run of each paired run and the first original phrase of each phrase."""
    runs, gaps = [[i] for i in range(len(gaps) + 1)], list(gaps)
    while len(runs) > len(pauses) + 1:
        i = int(np.argmin(gaps))
        runs[i : i + 2] = [runs[i] + runs[i + 1]]
        del gaps[i]
    phrases, pauses = [[i] for i in range(len(pauses) + 1)], list(pauses)
    while len(phrases) > len(runs):
        i = int(np.argmin(pauses))
        phrases[i : i + 2] = [phrases[i] + phrases[i + 1]]
        del pauses[i]
    return [run[0] for run in runs], [phrase[0] for phrase in phrases]


@pytest.mark.parametrize("seed", range(8))
def test_pairing_in_one_pass_pairs_as_the_shortest_first_rule_does(seed):
    """Bridging one rest leaves the other rests as they were, so bridging the k shortest at once pairs the
    same stretches as bridging the shortest k times over (which took quadratic time on a long file)."""
    from turkish_lipsync.core.speech.cue_timing import _pair_stretches
    from turkish_lipsync.core.speech.cues import MouthCue

    rng = np.random.default_rng(seed)
    marks = rng.choice([", ", "; ", ". "], size=int(rng.integers(1, 9)))
    text = "".join(f"ev{mark}" for mark in marks) + "ev."
    utterance = build_utterance(text)
    starts = [w.first_letter for w in utterance.words if w.pause_before > 0 or w.first_letter == 0]
    pauses = [w.pause_before for w in utterance.words[1:] if w.pause_before > 0]
    gaps = rng.choice([0.1, 0.2, 0.3, 0.4, 0.5], size=int(rng.integers(0, 14)))
    runs, time = [], 0.0
    for gap in [0.0, *gaps]:
        time += gap
        runs.append([MouthCue(time, time + 0.1, "B")])
        time += 0.1
    phrases, paired = _pair_stretches(utterance, [list(run) for run in runs])
    first_runs, first_phrases = _naive_pairing(gaps, pauses)
    assert [run[0].start for run in paired] == [runs[i][0].start for i in first_runs]
    assert [phrase.start for phrase in phrases] == [starts[i] for i in first_phrases]


def test_a_file_of_too_many_cues_is_refused_before_it_is_read(tmp_path, monkeypatch):
    from turkish_lipsync.core.speech.cues import common

    monkeypatch.setattr(common, "MAX_CUES", 1000)
    path = tmp_path / "huge.tsv"
    path.write_text("".join(f"{i * 0.05:.2f}\tB\n" for i in range(1001)))
    with pytest.raises(CueFileError, match="1,001 mouth cues are more than the 1,000"):
        read_cue_file(path)


def test_a_cue_file_of_another_length_is_warned_and_of_far_more_cues_refused(tmp_path):
    from turkish_lipsync.core.speech.cue_timing import speech_from_cues

    long = tmp_path / "long.tsv"  # 17 minutes of speech for four words
    long.write_text("0.00\tB\n1020.00\tX\n", encoding="utf-8")
    _, speech = speech_from_cues("merhaba benim adım erdem", long)
    assert any("speaks for 1020.0 s, and the text takes about" in w for w in speech.warnings)
    busy = tmp_path / "busy.tsv"  # 300 mouth changes for 21 letters
    busy.write_text("".join(f"{i * 0.1:.2f}\t{'AB'[i % 2]}\n" for i in range(300)) + "30.00\tX\n")
    with pytest.raises(CueFileError, match="holds 300 mouth changes for a text of 21 letters"):
        speech_from_cues("merhaba benim adım erdem", busy)
