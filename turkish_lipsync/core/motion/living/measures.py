"""Measures of a living face as a viewer sees it: rotations fitted to moving vertices, saccades and blinks
found in what the scene shows, pauses in the speech's own audio. Used by lab/measure/living.py and the
tests, on vertices sampled from the evaluated scene frame by frame; nothing here reads the keys."""

from __future__ import annotations

import numpy as np

from ...base.rotations import angles_of
from ...speech.audio import levels_under_loud
from ...speech.voice_activity import runs

SACCADE_SPEED = 20.0  # degrees a second of gaze that count as a saccade, not a fixation
BLINK_CLOSED = 0.9  # share of the lids' closure that counts as shut
BLINK_OPEN = 0.1  # ... and as open


def fit_rotation(rest: np.ndarray, moved: np.ndarray) -> np.ndarray:
    """The rotation (3, 3) of the best rigid fit taking rest points to moved ones (Kabsch)."""
    a = np.asarray(rest, np.float64) - np.mean(rest, axis=0)
    b = np.asarray(moved, np.float64) - np.mean(moved, axis=0)
    u, _s, vt = np.linalg.svd(a.T @ b)
    d = np.sign(np.linalg.det(vt.T @ u.T))
    return vt.T @ np.diag([1.0, 1.0, d]) @ u.T


def head_angles_of(rotations: np.ndarray, frame: np.ndarray) -> np.ndarray:
    """(N, 3) yaw, pitch, roll in degrees of world rotations (N, 3, 3), in the head's frame (columns of
    frame: left, up, forward): the inverse of rotations.head_matrices."""
    local = frame.T @ np.asarray(rotations) @ frame
    forward = local[:, :, 2]
    yaw_pitch = angles_of(forward)
    yaw, pitch = np.radians(yaw_pitch[:, 0]), np.radians(yaw_pitch[:, 1])
    # The left axis after yaw and pitch alone; roll is how far the actual left axis turned about forward.
    cy, sy, cp, sp = np.cos(yaw), np.sin(yaw), np.cos(pitch), np.sin(pitch)
    left = np.stack([cy, np.zeros_like(cy), -sy], axis=1)
    up = np.stack([-sy * sp, cp, -cy * sp], axis=1)
    actual = local[:, :, 0]
    roll = np.degrees(np.arctan2(np.einsum("ij,ij->i", actual, up), np.einsum("ij,ij->i", actual, left)))
    return np.column_stack([yaw_pitch, roll])


def angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    a = a / np.linalg.norm(a, axis=-1, keepdims=True)
    b = b / np.linalg.norm(b, axis=-1, keepdims=True)
    return np.degrees(np.arccos(np.clip(np.einsum("...i,...i->...", a, b), -1.0, 1.0)))


def saccades(gaze: np.ndarray, fps: float) -> list[tuple[int, int, float]]:
    """(first frame, frames it lasts, amplitude in degrees) of each run of fast gaze (N, 3 directions)."""
    step = angle_between(gaze[1:], gaze[:-1])
    fast = step * fps > SACCADE_SPEED
    return [
        (int(start), int(stop - start), float(angle_between(gaze[stop], gaze[start])))
        for start, stop in runs(fast)
    ]


def blinks(closure: np.ndarray, fps: float) -> list[dict]:
    """Each blink in a closure signal (0 open .. 1 shut): when it starts closing, how long it takes to shut
    and to open again (seconds, from 10 % to 90 % of its travel and back). The lids may rest lower while the
    eyes look down, so each blink's travel is measured from where its rise begins."""
    shut = closure >= BLINK_CLOSED
    found = []
    resume = 0  # a run of shut frames inside the last blink's fall belongs to it
    for index, stop in runs(shut):
        if index < resume:
            continue
        last = stop - 1
        peak = float(closure[index : last + 1].max())
        rise = index
        while rise > 0 and closure[rise - 1] < closure[rise]:
            rise -= 1
        fall = last
        while fall + 1 < closure.size and closure[fall + 1] < closure[fall]:
            fall += 1
        before, after = closure[rise], closure[fall]
        closing_from = rise + np.argmax(closure[rise : index + 1] > before + BLINK_OPEN * (peak - before))
        closed_at = rise + np.argmax(closure[rise : index + 1] >= before + BLINK_CLOSED * (peak - before))
        backwards = closure[rise : last + 1][::-1]
        opening_from = last - np.argmax(backwards >= after + BLINK_CLOSED * (peak - after))
        tail = closure[last : fall + 1] <= after + BLINK_OPEN * (peak - after)
        opened_at = last + (np.argmax(tail) if tail.any() else fall - last)
        found.append(
            {
                "start": (closing_from - 1) / fps,
                "closing": max(closed_at - closing_from + 1, 1) / fps,
                "opening": max(opened_at - opening_from, 1) / fps,
            }
        )
        resume = max(fall, last) + 1
    return found


def audio_pauses(samples: np.ndarray, sample_rate: int, shortest: float = 0.2) -> list[tuple[float, float]]:
    """Silences of the audio at least `shortest` long: 10 ms frames 35 dB under its loud end."""
    hop = max(1, int(sample_rate * 0.01))
    quiet = levels_under_loud(np.asarray(samples), hop) < -35.0
    count = quiet.size
    pauses, index = [], 0
    while index < count:
        if not quiet[index]:
            index += 1
            continue
        end = index
        while end + 1 < count and quiet[end + 1]:
            end += 1
        if (end + 1 - index) * 0.01 >= shortest:
            pauses.append((index * 0.01, (end + 1) * 0.01))
        index = end + 1
    return pauses


def distance_to_spans(time: float, spans: list[tuple[float, float]]) -> float:
    """Seconds from a time to the nearest span (0 inside one)."""
    if not spans:
        return np.inf
    return float(min(max(start - time, time - end, 0.0) for start, end in spans))


NOD_DEPTH = 2.0  # degrees a head dips below its running level that count as a nod


def nods(pitch: np.ndarray, fps: float, depth: float = NOD_DEPTH) -> list[float]:
    """Times (seconds) of the lowest point of each nod in a head's pitch (degrees, up positive): dips of at
    least `depth` below the median of the 1.5 s around them; dips within 0.7 s of one (a double nod) are
    one nod."""
    pitch = np.asarray(pitch, np.float64)
    if pitch.size < 3:
        return []
    half = max(int(0.75 * fps), 1)
    padded = np.pad(pitch, half, mode="edge")
    level = np.median(np.lib.stride_tricks.sliding_window_view(padded, 2 * half + 1), axis=1)[: pitch.size]
    below = level - pitch
    found: list[int] = []
    for start, stop in runs(below >= depth):
        lowest = start + int(np.argmax(below[start:stop]))
        if found and (lowest - found[-1]) / fps < 0.7:
            continue
        found.append(lowest)
    return [index / fps for index in found]
