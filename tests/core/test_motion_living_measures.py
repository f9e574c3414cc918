"""The measures lab/measure/living.py reads off the evaluated scene, on signals whose answer is known."""

import numpy as np
import pytest

from turkish_lipsync.core.motion.living import measures


def _direction(yaw_degrees: np.ndarray) -> np.ndarray:
    yaw = np.radians(yaw_degrees)
    return np.stack([np.sin(yaw), np.zeros_like(yaw), np.cos(yaw)], axis=1)


def test_saccades_are_the_fast_runs_of_gaze_with_their_amplitude():
    fps = 60.0
    yaw = np.zeros(120)
    yaw[30:33] = [3.0, 6.0, 9.0]  # 9 degrees in three frames (180 degrees a second)
    yaw[33:] = 9.0
    yaw[80:] = 9.0 - 4.0  # a 4-degree jump in one frame
    found = measures.saccades(_direction(yaw), fps)
    assert [(start, length) for start, length, _ in found] == [(29, 3), (79, 1)]
    assert [amplitude for _, _, amplitude in found] == pytest.approx([9.0, 4.0], abs=1e-6)
    assert measures.saccades(_direction(np.linspace(0.0, 5.0, 120)), fps) == []  # 2.5 degrees a second


def test_a_blink_is_timed_from_ten_to_ninety_percent_of_its_travel():
    fps = 100.0
    closure = np.zeros(100)
    closure[20:28] = np.linspace(0.125, 1.0, 8)  # closing over 8 frames
    closure[28:31] = 1.0
    closure[31:47] = np.linspace(15 / 16, 0.0, 16)  # opening over 16
    (blink,) = measures.blinks(closure, fps)
    assert blink["start"] == pytest.approx(0.19)
    assert blink["closing"] == pytest.approx(0.08)  # frames 20 (past 10 %) to 27 (past 90 %), inclusive
    assert blink["opening"] == pytest.approx(0.14)  # from frame 31 (the last shut) to 45 (under 10 %)
    twice = np.concatenate([closure, closure])
    assert len(measures.blinks(twice, fps)) == 2
    assert measures.blinks(np.full(50, 0.5), fps) == []  # lids resting half down are no blink
