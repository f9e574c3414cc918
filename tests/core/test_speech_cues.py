"""Rhubarb mouth cues: written as TSV, JSON and XML, parsed back, and checked against the timeline."""

import dataclasses
import json

import pytest

from turkish_lipsync.core.base.model import Hesitation
from turkish_lipsync.core.base.visemes import VISEME_NAMES
from turkish_lipsync.core.speech import synthesize_timeline
from turkish_lipsync.core.speech.cues import CueFileError, cue_formats, mouth_cues, read_cue_file
from turkish_lipsync.core.speech.cues.shapes import SHAPES, shape_for_phoneme, shape_for_viseme
from turkish_lipsync.core.text.utterance import build_utterance

FPS = 25.0
TEXT = "Merhaba, benim adım Erdem. Bu sabah vapura binip karşıya geçti."


@pytest.fixture(scope="module")
def timeline():
    return synthesize_timeline(build_utterance(TEXT), "phone").timeline


def test_every_turkish_viseme_has_a_rhubarb_shape():
    shapes = {viseme: shape_for_viseme(viseme) for viseme in VISEME_NAMES}
    assert set(shapes.values()) <= set(SHAPES)
    assert {shapes[v] for v in ("bpa", "bpe", "bpo", "ma", "me", "mo")} == {"A"}
    assert shapes["a"] == "D" and shapes["u"] == "F" and shapes["fvae"] == "G" and shapes["neutral"] == "X"
    assert shape_for_phoneme("MBP", True) == "A" and shape_for_phoneme("wq", True) == "F"
    assert shape_for_phoneme("E", True) == "C" and shape_for_phoneme("E", False) == "E"
    assert shape_for_phoneme("zz", True) is None and shape_for_phoneme("rest", False) is None


def test_cues_cover_the_whole_timeline_and_rest_in_the_silences(timeline):
    cues = mouth_cues(timeline)
    assert cues[0].start == 0.0 and cues[-1].end == pytest.approx(timeline.duration)
    for previous, cue in zip(cues, cues[1:], strict=False):
        assert cue.start == pytest.approx(previous.end)
        assert cue.shape != previous.shape
    # The pause at the comma after "Merhaba" is a rest, and "benim" opens with closed lips.
    merhaba, benim = timeline.words[0], timeline.words[1]
    assert benim.start - merhaba.end > 0.05
    assert any(c.shape == "X" and c.start <= merhaba.end + 1e-6 and c.end >= benim.start - 1e-6 for c in cues)
    assert next(c for c in cues if c.start <= benim.start + 1e-6 < c.end).shape == "A"


def test_a_hesitation_said_aloud_is_a_shape_in_its_pause(timeline):
    """An "ooo" said in the pause after "Merhaba" is cued as an o, not as a rest."""
    merhaba, benim = timeline.words[0], timeline.words[1]
    hesitation = Hesitation(merhaba.end + 0.01, benim.start - 0.01, "o", "o")
    cues = mouth_cues(dataclasses.replace(timeline, hesitations=(hesitation,)))
    middle = (hesitation.start + hesitation.end) / 2
    assert next(c for c in cues if c.start <= middle < c.end).shape == shape_for_viseme("o") != "X"


@pytest.mark.parametrize("export_format", ["rhubarb-tsv", "rhubarb-json", "rhubarb-xml"])
def test_written_cues_parse_back_within_a_frame_of_the_timeline(timeline, tmp_path, export_format):
    expected = mouth_cues(timeline)
    suffix = export_format.split("-")[1]
    path = tmp_path / f"speech.{suffix}"
    path.write_text(
        cue_formats()[export_format].write(timeline, FPS, sound_file="speech.wav")[0], encoding="utf-8"
    )
    source = read_cue_file(path, FPS)
    cues = source.cues
    if suffix == "tsv":
        assert source.duration == pytest.approx(expected[-1].start, abs=1e-3)
    else:
        assert source.sound_file == "speech.wav"
        assert source.duration == pytest.approx(timeline.duration, abs=1e-3)
    compared = expected if suffix != "tsv" else expected[:-1]  # TSV: the final rest has no end
    assert [c.shape for c in cues[: len(compared)]] == [c.shape for c in compared]
    for cue, original in zip(cues, compared, strict=False):
        assert abs(cue.start - original.start) < 1 / FPS and abs(cue.end - original.end) < 1 / FPS
    # Every phone of the timeline starts, within a frame, at a cue boundary or inside the cue of its shape.
    for phone in timeline.phones:
        shape = shape_for_viseme(phone.viseme)
        covering = [c for c in cues if c.start - 1 / FPS <= phone.start < c.end + 1 / FPS]
        assert shape in {c.shape for c in covering}, (phone, covering)


def test_json_is_rhubarbs_layout(timeline):
    document = json.loads(cue_formats()["rhubarb-json"].write(timeline, FPS)[0])
    assert set(document) == {"metadata", "mouthCues"}
    assert set(document["mouthCues"][0]) == {"start", "end", "value"}


def test_xml_with_entities_is_refused(tmp_path):
    path = tmp_path / "bomb.xml"
    path.write_text(
        '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY a "aaaa">]><rhubarbResult/>', encoding="utf-8"
    )
    with pytest.raises(CueFileError, match="DTD"):
        read_cue_file(path)


def test_a_bad_tsv_line_is_named(tmp_path):
    path = tmp_path / "cues.tsv"
    path.write_text("0.00\tX\n0.10\tQ\n", encoding="utf-8")
    with pytest.raises(CueFileError, match="line 2.*'Q'"):
        read_cue_file(path)
