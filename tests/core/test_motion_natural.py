"""The default motion model on held-out Turkish sentences: table and engine timing, 24-60 fps, emotions."""

from __future__ import annotations

import numpy as np
import pytest

from turkish_lipsync.core.base.model import (
    EMOTIONS,
    emotion_key_name,
    emotion_release_key_name,
    viseme_key_name,
)
from turkish_lipsync.core.base.visemes import BILABIAL_VISEMES, LABIODENTAL_VISEMES
from turkish_lipsync.core.motion.frames import sampled_weights
from turkish_lipsync.core.motion.natural import natural_weight_tracks
from turkish_lipsync.core.motion.quality import quality_report
from turkish_lipsync.core.speech.timing import table_timeline
from turkish_lipsync.core.text.utterance import build_utterance

# Sentences the parameters were not tuned on: many m, b, p, f, v, and rounded vowels after consonants.
HELD_OUT = (
    "Mehmet bey bu sabah erkenden vapura binip boğazı geçti.",
    "Pembe bulutlar mavi gökyüzünde yavaşça süzülüyordu.",
    "Fırtınada büyük ağaçlar devrildi, ama kimse yaralanmadı.",
)
RATES = {"slow": "60%", "normal": "100%", "fast": "180%"}
FRAME_RATES = (24, 30, 60)


def timeline_of(text: str, rate: str = "100%", emotion: str | None = None):
    source = f'<PROS RATE="{rate}">{text}</PROS>'
    if emotion:
        source = f"<{emotion.upper()}>{source}</{emotion.upper()}>"
    return table_timeline(build_utterance(source))


def viseme_matrix(tracks):
    names, values = sampled_weights(tracks)
    columns = [i for i, n in enumerate(names) if n.startswith("TR_viseme_")]
    return [names[i].removeprefix("TR_viseme_") for i in columns], values[:, columns]


@pytest.mark.parametrize("emotion", (None, *EMOTIONS))
@pytest.mark.parametrize("fps", FRAME_RATES)
@pytest.mark.parametrize("rate", RATES.values(), ids=RATES.keys())
def test_every_closure_is_reached_the_weights_fit_and_no_shape_flashes(rate, fps, emotion):
    for text in HELD_OUT:
        timeline = timeline_of(text, rate, emotion)
        tracks = natural_weight_tracks(timeline, fps)
        report = quality_report(timeline, tracks)
        assert report["bilabial_closure_share"] == 1.0, text
        assert report["labiodental_contact_share"] == 1.0, text
        assert report["max_weight_sum"] <= 1.0 + 1e-9
        assert report["min_hold_frames"] >= 2
        # Between the keys too: half frames are linear mixes of whole ones, so they cannot exceed 1 either.
        halves = tracks.sample(np.arange(tracks.frame_count - 1) + 0.5)
        viseme_columns = [i for i, n in enumerate(halves[0]) if n.startswith("TR_viseme_")]
        assert halves[1][:, viseme_columns].sum(axis=1).max() <= 1.0 + 1e-9


def test_each_hard_target_holds_its_own_viseme_at_full_weight_on_its_own_frame():
    timeline = timeline_of("Mehmet bey bu sabah erkenden vapura binip boğazı geçti.", "180%", "happy")
    tracks = natural_weight_tracks(timeline, 24)
    visemes, weights = viseme_matrix(tracks)
    closures = dict(tracks.extra["closure_frames"])
    hard = [p for p in timeline.phones if p.viseme in BILABIAL_VISEMES | LABIODENTAL_VISEMES]
    assert sorted(closures) == sorted(p.letter_index for p in hard)
    assert len(set(closures.values())) == len(closures)  # no two closures share a frame
    for phone in hard:
        frame = closures[phone.letter_index]
        assert weights[frame, visemes.index(phone.viseme)] == pytest.approx(1.0)
        assert abs(frame / 24 - (phone.start + phone.end) / 2) <= 1.5 / 24


def test_lips_anticipate_a_rounded_vowel_across_the_consonants_before_it():
    """In "estu" the u already shows during the t; in "esti" the i shows less there (minimal pair)."""
    rounded = natural_weight_tracks(timeline_of("estu"), 60)
    spread = natural_weight_tracks(timeline_of("estu".replace("u", "i")), 60)
    shares = []
    for tracks, vowel in ((rounded, "u"), (spread, "Ii")):
        timeline = timeline_of("estu" if vowel == "u" else "esti")
        t_phone = next(p for p in timeline.phones if p.letter == "t")
        frame = round((t_phone.start + t_phone.end) / 2 * 60)
        visemes, weights = viseme_matrix(tracks)
        shares.append(weights[frame, visemes.index(vowel)])
    assert shares[0] > 0.25
    assert shares[0] > shares[1] + 0.1


def test_long_phones_hold_and_short_ones_blend():
    slow = timeline_of("Aaa, mavi!", "60%")
    tracks = natural_weight_tracks(slow, 60)
    visemes, weights = viseme_matrix(tracks)
    for phone in slow.phones:
        if phone.letter in "ai" and phone.end - phone.start > 0.08:
            frames = np.arange(round(phone.start * 60), round(phone.end * 60))
            assert (weights[frames, visemes.index(phone.viseme)] >= 0.8).sum() >= 2, phone
    fast = timeline_of("Pembe bulutlar mavi gökyüzünde yavaşça süzülüyordu.", "180%")
    report = quality_report(fast, natural_weight_tracks(fast, 24))
    assert report["min_hold_frames"] >= 2
    assert report["vowel_peak_mean"] > 0.3  # blended, but the vowels are still seen


def test_emotions_are_layered_at_full_strength_and_give_way_only_where_the_lips_close():
    plain = timeline_of("Bu akşam babamla buluşacağım.")
    happy = timeline_of("Bu akşam babamla buluşacağım.", emotion="happy")
    plain_tracks, happy_tracks = natural_weight_tracks(plain, 30), natural_weight_tracks(happy, 30)
    # The lips move exactly as without the emotion: nothing is traded.
    assert np.allclose(viseme_matrix(plain_tracks)[1], viseme_matrix(happy_tracks)[1])

    names, values = sampled_weights(happy_tracks)
    emotion = values[:, names.index(emotion_key_name("happy"))]
    release = values[:, names.index(emotion_release_key_name("happy"))]
    span = happy.emotions[0]
    middle = round((span.start + span.end) / 2 * 30)
    assert emotion[middle] == pytest.approx(1.0)
    assert emotion[0] < 0.5 and emotion[-1] < 1e-6  # onset and offset ramps
    assert np.all(release <= emotion + 1e-12)
    visemes, weights = viseme_matrix(happy_tracks)
    for _, frame in happy_tracks.extra["closure_frames"]:
        assert release[frame] == pytest.approx(emotion[frame])  # the mouth is free for the closure
    lips_busy = weights[:, [visemes.index(v) for v in visemes if v in BILABIAL_VISEMES | LABIODENTAL_VISEMES]]
    open_frames = lips_busy.sum(axis=1) == 0
    assert open_frames.any() and np.all(release[open_frames] == 0)  # elsewhere the smile stays whole


def test_emotion_weight_and_strength_scale_the_emotion_and_neighbouring_words_cross_fade():
    source = "<SAD WEIGHT='0.5'>Bugün yine</SAD> <SURPRISED>mektup gelmedi</SURPRISED> bize."
    timeline = table_timeline(build_utterance(source))
    tracks = natural_weight_tracks(timeline, 60, emotion_strength=0.8)
    names, values = sampled_weights(tracks)
    sad = values[:, names.index(emotion_key_name("sad"))]
    surprised = values[:, names.index(emotion_key_name("surprised"))]
    assert sad.max() == pytest.approx(0.4)
    assert surprised.max() == pytest.approx(0.8)
    boundary = round(timeline.emotions[1].start * 60)
    assert 0 < sad[boundary] < 0.4 and 0 < surprised[boundary] < 0.8  # both on the face at the change
    assert np.abs(np.diff(sad)).max() < 0.05 and np.abs(np.diff(surprised)).max() < 0.1


def test_tracks_are_sparse_integer_frame_keys_that_reproduce_every_frame():
    timeline = timeline_of("Mehmet bey bu sabah erkenden vapura binip boğazı geçti.", emotion="angry")
    tracks = natural_weight_tracks(timeline, 30)
    assert tracks.mode == "natural" and tracks.interpolation == "LINEAR"
    assert tracks.frame_count == int(np.ceil(timeline.duration * 30)) + 1
    total_keys = sum(t.frames.size for t in tracks.tracks)
    assert total_keys < tracks.frame_count * len(tracks.tracks) / 2
    neutral = tracks.track(viseme_key_name("neutral"))
    assert neutral.values[0] > 0.9 and neutral.values[-1] == pytest.approx(1.0)  # from rest, back to rest
    for track in tracks.tracks:
        assert np.all(track.frames == np.round(track.frames)) and np.all(np.diff(track.frames) > 0)
        assert track.values.min() >= 0 and track.values.max() <= 1 + 1e-12
    # Dense recomputation with every key kept equals the sparse tracks sampled at the frames.
    from turkish_lipsync.core.motion.natural import viseme_weights

    visemes, dense, _ = viseme_weights(timeline, 30, tracks.frame_count)
    for column, viseme in enumerate(visemes):
        sampled = np.interp(np.arange(tracks.frame_count), *_keys(tracks.track(viseme_key_name(viseme))))
        assert np.allclose(sampled, dense[:, column], atol=1e-8)


def _keys(track):
    return track.frames, track.values


@pytest.mark.parametrize("rate", ("60%", "100%", "180%"))
def test_real_engine_timelines_keep_every_closure(rate):
    from turkish_lipsync.core.speech import synthesize_timeline

    source = f'<PROS RATE="{rate}">' + " ".join(HELD_OUT) + "</PROS>"
    timeline = synthesize_timeline(build_utterance(source), "phone").timeline
    assert timeline.engine_onsets
    for fps in FRAME_RATES:
        for emotion in (None, "happy", "angry"):
            tracks = natural_weight_tracks(timeline, fps)
            if emotion:
                # The same engine timing under an emotion at full weight over the whole utterance.
                from dataclasses import replace

                from turkish_lipsync.core.base.model import EmotionSpan

                span = EmotionSpan(timeline.phones[0].start, timeline.phones[-1].end, emotion, 1.0)
                tracks = natural_weight_tracks(replace(timeline, emotions=(span,)), fps)
            report = quality_report(timeline, tracks)
            assert report["onset_reference"] == "engine"
            assert report["bilabial_closure_share"] == 1.0
            assert report["labiodental_contact_share"] == 1.0
            assert report["max_weight_sum"] <= 1.0 + 1e-9
            assert report["min_hold_frames"] >= 2


def test_a_timeline_without_phones_rests():
    from turkish_lipsync.core.base.model import Timeline

    tracks = natural_weight_tracks(Timeline((), (), (), (), 1.0, "table"), 24)
    assert [t.name for t in tracks.tracks] == [viseme_key_name("neutral")]
    assert np.all(tracks.tracks[0].values == 1.0)
