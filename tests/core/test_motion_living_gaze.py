"""Gaze while talking and head motion from the voice (core/motion/living): Lee, Badler and Badler's
statistics, the main sequence, eyes that keep their target while the head moves, seeds."""

from __future__ import annotations

import numpy as np
import pytest

from turkish_lipsync.core.base.model import look_key_name
from turkish_lipsync.core.base.rotations import direction, eye_matrices, head_matrices
from turkish_lipsync.core.faces.eyes import ARKIT_LOOK_UNITS, sphere_fit, turn_degrees
from turkish_lipsync.core.motion.living import GazeSetup, LivingOptions, living_tracks
from turkish_lipsync.core.motion.living.gaze import plan_gaze
from turkish_lipsync.core.motion.living.parameters import living_parameters
from turkish_lipsync.core.motion.living.phrases import SpeechStructure
from turkish_lipsync.core.motion.living.prosody import measure_prosody
from turkish_lipsync.core.pipeline import LipSyncOptions, lip_sync

CORPUS_LINES = 40


@pytest.fixture(scope="module")
def spoken():
    from pathlib import Path

    corpus = Path(__file__).resolve().parents[2] / "examples" / "corpus_tr.txt"
    text = " ".join(corpus.read_text(encoding="utf-8").splitlines()[:CORPUS_LINES])
    return lip_sync(text, LipSyncOptions(fps=60))


def test_saccades_follow_eyes_alive_and_the_main_sequence(spoken):
    saccades = spoken.tracks.extra["saccades"]
    minutes = spoken.timeline.duration / 60
    amplitudes = np.array([a for _s, _d, a in saccades])
    durations = np.array([d for _s, d, _a in saccades])
    assert 6 <= len(saccades) / minutes <= 90
    assert (amplitudes < 15).mean() >= 0.8
    assert durations == pytest.approx((25 + 2.4 * amplitudes) / 1000)
    # Exponential amplitudes: the mean of those under 15 degrees sits near the model's 6.9 scale's.
    assert 3 < amplitudes[amplitudes < 15].mean() < 8


def test_eye_contact_about_forty_percent_and_look_aways_near_the_target(spoken):
    motion = spoken.tracks.head_and_eyes
    head, left = motion.head, motion.left_eye
    setup = GazeSetup()
    world = np.einsum("nij,njk->nik", head_matrices(head), eye_matrices(left))[:, :, 2]
    eye = head_matrices(head) @ setup.eye_positions()[0]
    to_target = setup.target_point() - eye
    off = np.degrees(
        np.arccos(
            np.clip(
                np.einsum("ij,ij->i", world, to_target / np.linalg.norm(to_target, axis=1)[:, None]), -1, 1
            )
        )
    )
    contact = off < 0.5  # the eyes keep the target exactly while the head moves under them
    assert 0.25 <= contact.mean() <= 0.6
    assert np.percentile(off, 95) >= 3
    assert np.percentile(off, 99) < 30


def test_both_eyes_converge_on_a_near_target_and_counter_roll():
    result = lip_sync("Merhaba, benim adım Erdem.", LipSyncOptions(gaze_setup=GazeSetup(target_distance=0.4)))
    motion = result.tracks.head_and_eyes
    first = 0  # the utterance starts in eye contact
    vergence = motion.left_eye[first, 0] - motion.right_eye[first, 0]
    assert vergence < -5  # the left eye turns right, the right one left: 2 atan(31.5 mm / 400 mm) = 9 deg
    roll = motion.head[:, 2]
    assert np.corrcoef(motion.left_eye[:, 2], roll)[0, 1] < -0.99


def test_head_moves_a_few_degrees_with_the_pitch_and_stills_in_a_long_pause():
    text = 'Bugün hava çok güzel, parka gidelim mi? <BREAK TIME="2.5s"/> Evet, hemen çıkalım, dedi.'
    result = lip_sync(text, LipSyncOptions(fps=50))
    head = result.tracks.head_and_eyes.head
    total = np.linalg.norm(head, axis=1)
    assert 0.7 <= np.sqrt(np.mean(total**2)) <= 6 and total.max() <= 15
    prosody = measure_prosody(result.synthesis.samples, result.synthesis.sample_rate)
    times = np.arange(len(head)) / 50
    f0 = prosody.at(times, prosody.f0)
    voiced = np.isfinite(f0)
    assert np.corrcoef(head[voiced, 1], np.log2(f0[voiced]))[0, 1] >= 0.25
    pause = max(result.tracks.extra["pauses"], key=lambda span: span[1] - span[0])
    inside = (times > pause[0] + 0.6) & (times < pause[1] - 0.3)
    speed = np.abs(np.diff(head, axis=0)).sum(axis=1) * 50
    assert pause[1] - pause[0] > 2 and speed[inside[1:]].max() < 0.5 * np.percentile(speed, 90)


def test_layers_are_seeded_and_thesis_mode_has_none_unless_asked():
    text = "Merhaba, benim adım Erdem. Bugün hava çok güzel."
    still = lip_sync(text, LipSyncOptions(gaze=False, blinks=False, head_motion=False, expression=False))
    samples, rate = still.synthesis.samples, still.synthesis.sample_rate

    def living(seed):
        return living_tracks(still.tracks, still.timeline, LivingOptions(seed=seed), samples, rate)

    first, again, other = living(4), living(4), living(5)
    assert np.array_equal(first.head_and_eyes.head, again.head_and_eyes.head)
    assert first.extra["saccades"] == again.extra["saccades"] != other.extra["saccades"]
    assert first.extra["blinks"] == again.extra["blinks"]
    thesis = lip_sync(text, LipSyncOptions(motion="thesis")).tracks
    assert thesis.head_and_eyes is None and thesis.track(look_key_name("left", "left")) is None
    asked = lip_sync(text, LipSyncOptions(motion="thesis", gaze=True)).tracks
    assert asked.head_and_eyes is not None and np.abs(asked.head_and_eyes.head).max() == 0  # head off
    off = lip_sync(text, LipSyncOptions(gaze_amount=0, head_amount=0, blinks=False, expression=False)).tracks
    assert off.head_and_eyes is None


def test_the_arkit_look_calibration_is_the_reference_heads():
    """living.toml's degrees of ARKit's eyeLook units at weight 1 are what faceunits01's units turn the
    reference's eyeballs (a rotation fitted to them)."""
    from turkish_lipsync.core.faces.reference import load_reference_head

    reference = load_reference_head()
    frame = np.column_stack([[1.0, 0, 0], [0, 0, 1.0], [0, -1.0, 0]])  # left, up, forward: the head faces -Y
    degrees = living_parameters()["eyes"]["arkit_degrees"]
    for (eye, way), unit in ARKIT_LOOK_UNITS.items():
        indices = reference.parts[f"{eye}_eye"]
        points = reference.vertices[indices] @ frame
        centre = sphere_fit(points)[0]
        turned = turn_degrees(points, reference.units[unit][indices].astype(float) @ frame, centre, way)
        kind = way if way in ("up", "down") else ("out" if way == eye else "in")
        assert turned == pytest.approx(degrees[kind], abs=0.1)


def test_directions_and_rotations_share_one_convention():
    forward = np.array([0.0, 0.0, 1.0])
    assert head_matrices(np.array([[10.0, 0, 0]]))[0] @ forward == pytest.approx(direction(10.0, 0.0))
    assert head_matrices(np.array([[0, 10.0, 0]]))[0] @ forward == pytest.approx(direction(0.0, 10.0))
    assert (head_matrices(np.array([[0, 0, 10.0]]))[0] @ np.array([1.0, 0, 0]))[1] > 0  # left ear up


def test_a_living_table_without_an_entry_is_refused_naming_the_file(monkeypatch):
    from turkish_lipsync.core.base import data
    from turkish_lipsync.core.base.errors import DataError
    from turkish_lipsync.core.motion.living import parameters

    table = data.load_table("living")
    damaged = {**table, "head": {k: v for k, v in table["head"].items() if k != "nod"}}
    monkeypatch.setattr(parameters, "load_table", lambda name: damaged)
    parameters.living_parameters.cache_clear()
    try:
        with pytest.raises(DataError, match=r"living\.toml.*\[head\] lacks nod"):
            parameters.living_parameters()
    finally:
        parameters.living_parameters.cache_clear()


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_eyes_look_away_up_and_aside_through_a_hesitation_said_aloud(seed):
    """A speaker searching for the next word ("ııı") looks away from the listener, up and to a side, and
    back as the word comes; nothing else moves the eyes meanwhile."""
    settings = living_parameters()["gaze"]
    phrases = ((0.3, 4.0), (4.6, 9.0))
    structure = SpeechStructure(10.0, ((0.0, 0.3), (4.0, 4.6), (9.0, 10.0)), phrases, (), None, ((2.0, 2.9),))
    times = np.arange(0, 10.0, 1 / 50)
    plan = plan_gaze(structure, times, np.random.default_rng(seed), settings, 1.0)
    held = (times > 2.0 + settings["thinking_lead"] + 0.1) & (times < 2.9)
    yaw, pitch = plan.offsets[held].T
    assert np.allclose(np.abs(yaw), settings["thinking_yaw"]) and np.allclose(
        pitch, settings["thinking_pitch"]
    )
    back = next(saccade for saccade in plan.saccades if saccade.start >= 2.9)
    assert back.start == pytest.approx(2.9) and back.to_contact
    # Without the hesitation the same seed's eyes do something else there.
    plain = plan_gaze(
        SpeechStructure(10.0, structure.pauses, phrases, (), None),
        times,
        np.random.default_rng(seed),
        settings,
        1.0,
    )
    assert not np.allclose(plain.offsets[held], plan.offsets[held])
