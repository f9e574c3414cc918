"""Blinks where people blink, brows on accents, emotions that breathe (core/motion/living)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from turkish_lipsync.core.base.model import (
    BLINK_KEYS,
    BROW_RAISE_KEY,
    emotion_key_name,
    emotion_release_key_name,
)
from turkish_lipsync.core.motion.living.parameters import living_parameters
from turkish_lipsync.core.pipeline import LipSyncOptions, lip_sync

CORPUS = Path(__file__).resolve().parents[2] / "examples" / "corpus_tr.txt"


@pytest.fixture(scope="module")
def spoken():
    text = " ".join(CORPUS.read_text(encoding="utf-8").splitlines()[:40])
    return lip_sync(text, LipSyncOptions(fps=60))


def _distance(time, spans):
    return min(max(start - time, time - end, 0.0) for start, end in spans)


def test_blinks_keep_the_rate_and_shape_and_fall_at_pauses_and_gaze_shifts(spoken):
    settings = living_parameters()["blinks"]
    spans = spoken.tracks.extra["blinks"]
    starts = np.array([start for start, _ in spans])
    minutes = spoken.timeline.duration / 60
    assert 10 <= len(spans) / minutes <= 35
    gaps = np.diff(np.r_[0.0, starts, spoken.timeline.duration])
    assert gaps.max() <= 10 and np.diff(starts).min() >= settings["min_gap"]
    for start, end in spans:
        assert settings["min_duration"] - 1e-9 <= end - start <= settings["max_duration"] + 1e-9
    pauses = spoken.tracks.extra["pauses"]
    shifts = [start for start, _d, amplitude in spoken.tracks.extra["saccades"] if amplitude > 10]
    near = [
        min(_distance(t, pauses), min((abs(t - s) for s in shifts), default=np.inf)) <= 0.25 for t in starts
    ]
    assert np.mean(near) >= 0.5
    names, values = spoken.tracks.sample(np.arange(spoken.tracks.frame_count, dtype=float))
    left, right = values[:, names.index(BLINK_KEYS[0])], values[:, names.index(BLINK_KEYS[1])]
    assert np.array_equal(left, right)
    for start, _end in spans:  # each blink shuts on a frame
        frames = slice(int(start * 60), int(start * 60) + 20)
        assert left[frames].max() == pytest.approx(1.0)


def test_every_large_gaze_shift_brings_a_blink(spoken):
    starts = [start for start, _ in spoken.tracks.extra["blinks"]]
    large = [s for s, _d, a in spoken.tracks.extra["saccades"] if a >= 30]
    for shift in large:
        assert min(abs(np.array(starts) - shift)) < 0.1


def test_no_blinks_while_a_smile_narrows_the_eyes_and_none_when_off():
    text = "<HAPPY>Bugün hava çok güzel, parka gidip biraz yürüyüş yapalım, sonra dondurma yeriz.</HAPPY>"
    tracks = lip_sync(text).tracks
    happy = tracks.track(emotion_key_name("happy"))
    settings = living_parameters()["blinks"]
    for start, end in tracks.extra["blinks"]:  # only as the smile fades at the end
        frames = np.arange(start * tracks.fps, end * tracks.fps)
        closure = settings["eye_closure"]["happy"] * np.interp(frames, happy.frames, happy.values)
        assert closure.max() < settings["blink_suppress_closure"]
    assert all(start > 0.8 * tracks.frame_count / tracks.fps for start, _ in tracks.extra["blinks"])
    assert lip_sync(text, LipSyncOptions(blinks=False)).tracks.track(BLINK_KEYS[0]) is None


def test_brows_rise_on_emphasis_and_on_pitch_accents():
    settings = living_parameters()["brows"]
    emphasised = lip_sync("Bunu <EMP>mutlaka</EMP> bitirmeliyiz, dedi.", LipSyncOptions(timing="table"))
    brow = emphasised.tracks.track(BROW_RAISE_KEY)
    start, end = emphasised.timeline.emphases[0]
    middle = (start + end) / 2 * emphasised.tracks.fps
    assert np.interp(middle, brow.frames, brow.values) == pytest.approx(settings["weight"])
    text = " ".join(CORPUS.read_text(encoding="utf-8").splitlines()[:6])
    accented = lip_sync(text).tracks.track(BROW_RAISE_KEY)
    assert accented is not None and 0 < accented.values.max() <= settings["accent_weight"] + 1e-9
    assert lip_sync(text, LipSyncOptions(expression=False)).tracks.track(BROW_RAISE_KEY) is None


@pytest.mark.parametrize("emotion", ["happy", "sad", "angry", "afraid", "surprised", "disgusted"])
def test_emotions_breathe_at_their_apex_and_the_lips_still_close(emotion):
    tag = emotion.upper()
    text = f"<{tag}>Mehmet bey bu sabah vapura binip boğazı geçti, ama bir şey demedi.</{tag}>"
    result = lip_sync(text, LipSyncOptions(fps=30))
    _TIMELINES[text] = result.timeline
    tracks = result.tracks
    frames = np.arange(tracks.frame_count, dtype=float)
    weight = np.interp(frames, *_arrays(tracks.track(emotion_key_name(emotion))))
    release = np.interp(frames, *_arrays(tracks.track(emotion_release_key_name(emotion))))
    # The same speech without the layer: the plain onset, apex and offset of the natural model.
    from turkish_lipsync.core.motion import weight_tracks

    plain_track = weight_tracks(_timeline(text), 30).track(emotion_key_name(emotion))
    plain = np.interp(frames, *_arrays(plain_track))
    apex = plain > 0.95 * plain.max()
    assert np.ptp(plain[apex]) < 0.06
    life = weight[apex] / plain[apex]
    assert 0.02 < np.ptp(life) <= living_parameters()["expression"]["depth"] + 1e-9  # alive, not flat
    for _phone, frame in tracks.extra["closure_frames"]:
        assert release[frame] == pytest.approx(weight[frame], abs=1e-9)  # the mouth part gives way fully


_TIMELINES: dict = {}


def _timeline(text):
    """The timeline of the last lip_sync of text (eSpeak's durations vary a little from run to run)."""
    return _TIMELINES[text]


def _arrays(track):
    return track.frames, track.values
