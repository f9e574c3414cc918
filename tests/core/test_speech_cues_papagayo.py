"""Moho switch data and Papagayo projects: written from the timeline, parsed back, checked frame by frame."""

import pytest

from turkish_lipsync.core.speech import synthesize_timeline
from turkish_lipsync.core.speech.cues import CueFileError, cue_formats, mouth_cues, read_cue_file
from turkish_lipsync.core.speech.cues.common import frame_of
from turkish_lipsync.core.speech.cues.papagayo_pgo import read_pgo
from turkish_lipsync.core.speech.cues.shapes import shape_table
from turkish_lipsync.core.text.utterance import build_utterance

FPS = 24.0
TEXT = "Şu köşe yaz köşesi. Mehmet bey bu sabah vapura binip geçti."


@pytest.fixture(scope="module")
def timeline():
    return synthesize_timeline(build_utterance(TEXT), "phone").timeline


def test_moho_dat_has_each_mouth_change_on_its_frame(timeline, tmp_path):
    text = cue_formats()["moho-dat"].write(timeline, FPS)[0]
    lines = text.splitlines()
    assert lines[0] == "MohoSwitch1" and lines[1].startswith("1 ")
    names = set(shape_table().preston_blair.values())
    assert all(line.split()[1] in names for line in lines[1:])
    path = tmp_path / "speech.dat"
    path.write_text(text, encoding="utf-8")
    changes = read_cue_file(path, FPS).cues
    frames = [round(cue.start * FPS) for cue in changes]
    assert frames == sorted(set(frames))
    # Every cue at least a frame long shows on the frame it starts on (shorter ones may lose their frame).
    shown = {round(cue.start * FPS): cue.shape for cue in changes}
    previous = None
    for cue in mouth_cues(timeline):
        if cue.end - cue.start >= 1 / FPS:
            assert shown.get(frame_of(cue.start, FPS)) == cue.shape or previous == cue.shape
        previous = shown.get(frame_of(cue.start, FPS), previous)
    assert changes[0].start == 0.0


def test_pgo_round_trip_keeps_words_text_and_frames(timeline, tmp_path):
    path = tmp_path / "speech.pgo"
    path.write_text(
        cue_formats()["papagayo-pgo"].write(timeline, FPS, sound_file="speech.wav")[0], encoding="utf-8"
    )
    document = read_pgo(path)
    assert document.fps == FPS and document.sound_path == "speech.wav" and document.voice_count == 1
    assert [word.text for word in document.words] == [word.text for word in timeline.words]
    assert document.text.split() == [word.text for word in timeline.words]
    for word, original in zip(document.words, timeline.words, strict=True):
        assert abs(word.start_frame / FPS - original.start) < 1 / FPS
        assert abs((word.end_frame + 1) / FPS - original.end) < 1 / FPS
        assert word.phonemes[0][0] == word.start_frame
        assert all(word.start_frame <= frame <= word.end_frame for frame, _ in word.phonemes)
    # "bey": b closes the lips (MBP -> A) on the word's first frame.
    bey = document.words[[w.text for w in timeline.words].index("bey")]
    assert bey.phonemes[0][1] == "A"


def test_pgo_errors_name_the_line(tmp_path):
    path = tmp_path / "broken.pgo"
    path.write_text("lipsync version 1\nsound.wav\nfast\n", encoding="utf-8")
    with pytest.raises(CueFileError, match="line 3: expected the frame rate"):
        read_pgo(path)
    path.write_text("MohoSwitch1\n1 rest\n", encoding="utf-8")
    with pytest.raises(CueFileError, match="line 1 must be 'lipsync version 1'"):
        read_pgo(path)


def test_pgo_at_a_fractional_rate_says_papagayo_plays_it_off(timeline):
    text, warnings = cue_formats()["papagayo-pgo"].write(timeline, 29.97)
    assert text.splitlines()[2] == "30"
    assert len(warnings) == 1 and "0.1%" in warnings[0]
    assert cue_formats()["papagayo-pgo"].write(timeline, 25.0)[1] == ()


@pytest.mark.parametrize(
    ("lines", "message"),
    [
        ("MohoSwitch1\n1 rest\n12 AI\n8 E\n20 rest\n", "line 4: frame 8 does not come after frame 12"),
        ("MohoSwitch1\n0 AI\n5 rest\n", "line 2: frame 0: Moho counts frames from 1"),
        ("MohoSwitch1\n", "holds no mouth changes"),
    ],
)
def test_moho_data_out_of_order_is_refused_with_its_line(tmp_path, lines, message):
    path = tmp_path / "speech.dat"
    path.write_text(lines, encoding="utf-8")
    with pytest.raises(CueFileError, match=message):
        read_cue_file(path, FPS)
