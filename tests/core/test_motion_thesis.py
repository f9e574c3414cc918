import dataclasses

import numpy as np
import pytest

from turkish_lipsync.core.base.errors import LipSyncError
from turkish_lipsync.core.base.model import Hesitation, emotion_key_name, viseme_key_name
from turkish_lipsync.core.motion import weight_tracks
from turkish_lipsync.core.motion.frames import sparse_track
from turkish_lipsync.core.motion.thesis import thesis_weight_tracks
from turkish_lipsync.core.speech.timing import table_timeline
from turkish_lipsync.core.text.utterance import build_utterance


def thesis(text, fps=25.0, strength=1.0):
    timeline = table_timeline(build_utterance(text))
    return timeline, thesis_weight_tracks(timeline, fps, strength)


def test_each_letter_onset_shows_its_viseme_at_full_weight_without_emotion():
    timeline, tracks = thesis("Merhaba, benim adım Erdem.")
    names = [t.name for t in tracks.tracks]
    frames = np.array([p.start * 25 for p in timeline.phones])
    _, weights = tracks.sample(frames)
    for phone, row in zip(timeline.phones, weights, strict=True):
        assert row[names.index(viseme_key_name(phone.viseme))] == pytest.approx(1.0)
        assert row.sum() == pytest.approx(1.0)


def test_linear_morph_between_consecutive_letters_eq_5_3():
    timeline, tracks = thesis("ama")
    a, m = timeline.phones[0], timeline.phones[1]
    middle = (a.start + m.start) / 2 * 25
    names, weights = tracks.sample(np.array([middle]))
    row = dict(zip(names, weights[0], strict=True))
    assert row[viseme_key_name("a")] == pytest.approx(0.5)
    assert row[viseme_key_name("ma")] == pytest.approx(0.5)


def test_emotion_takes_weight_from_the_lips_eq_5_3():
    # w = 0.2 (the thesis's constant) x 0.5 (the JSML weight): lips at 1 - w, the empowered emotion
    # (rho = 3 times the emotion key) at w.
    timeline, tracks = thesis("<HAPPY WEIGHT='0.5'>elma</HAPPY>")
    names, weights = tracks.sample(np.array([timeline.phones[2].start * 25]))
    row = dict(zip(names, weights[0], strict=True))
    assert row[viseme_key_name("ma")] == pytest.approx(0.9)
    assert row[emotion_key_name("happy")] == pytest.approx(0.3)


def test_the_thesis_figure_5_1_weights_lips_at_80_percent_under_full_emotion():
    timeline, tracks = thesis("<ANGRY>merhaba</ANGRY>")
    names, weights = tracks.sample(np.array([timeline.phones[0].start * 25]))
    row = dict(zip(names, weights[0], strict=True))
    assert row[viseme_key_name("me")] == pytest.approx(0.8)
    assert row[emotion_key_name("angry")] == pytest.approx(0.6)


def test_emotions_cross_fade_between_words_eq_5_4():
    timeline, tracks = thesis("<HAPPY>iyi</HAPPY> <SAD>kötü</SAD>")
    last_happy = timeline.phones[2].start * 25
    first_sad = timeline.phones[3].start * 25
    names, weights = tracks.sample(np.array([last_happy, (last_happy + first_sad) / 2, first_sad]))
    happy = weights[:, names.index(emotion_key_name("happy"))]
    sad = weights[:, names.index(emotion_key_name("sad"))]
    np.testing.assert_allclose(happy, [0.6, 0.3, 0.0])
    np.testing.assert_allclose(sad, [0.0, 0.3, 0.6])


def test_a_hesitation_said_aloud_is_keyed_as_a_letter_in_the_emotion_before_it():
    timeline = table_timeline(build_utterance("<HAPPY>iyi</HAPPY>, <SAD>kötü</SAD>"))
    pause = (timeline.phones[2].end, timeline.phones[3].start)
    assert pause[1] - pause[0] > 0.1
    eee = Hesitation(pause[0] + 0.02, pause[1] - 0.02, "e", "e")
    tracks = thesis_weight_tracks(dataclasses.replace(timeline, hesitations=(eee,)), 25.0)
    names, weights = tracks.sample(np.array([eee.start * 25]))
    row = dict(zip(names, weights[0], strict=True))
    assert row[viseme_key_name("e")] == pytest.approx(0.8)
    assert row[emotion_key_name("happy")] == pytest.approx(0.6)


def test_starts_and_ends_on_the_neutral_face():
    timeline, tracks = thesis("merhaba")
    names, weights = tracks.sample(np.array([0.0, timeline.duration * 25]))
    neutral = names.index(viseme_key_name("neutral"))
    np.testing.assert_allclose(weights[:, neutral], [1.0, 1.0])
    assert tracks.frame_count >= timeline.duration * 25


def test_sparse_track_keeps_the_curve_and_drops_flat_interiors():
    frames = np.arange(8.0)
    values = np.array([0, 0, 0, 1, 1, 1, 0, 0], dtype=float)
    track = sparse_track("x", frames, values)
    np.testing.assert_allclose(np.interp(frames, track.frames, track.values), values)
    assert track.frames.size < frames.size


def test_unknown_mode_and_bad_fps_are_refused():
    timeline = table_timeline(build_utterance("ev"))
    with pytest.raises(LipSyncError, match="unknown motion model 'wobbly'; choose one of: natural, thesis"):
        weight_tracks(timeline, 25, mode="wobbly")
    with pytest.raises(ValueError, match="frame rate"):
        weight_tracks(timeline, 0)
