"""Frame helpers below both motion models and the quality report: sparse tracks, shapes shown per frame."""

from __future__ import annotations

import math

import numpy as np

from ..base.model import Track, WeightTracks


def frame_count_for(duration: float, fps: float) -> int:
    """Frames an utterance of duration seconds covers at fps: its start, its end and every frame between.

    The motion is computed over these, so that a key may fall on the frame after the last sound; a scene,
    a video and the per-frame exports show shown_frame_count of them."""
    return math.ceil(duration * fps) + 1


def shown_frame_count(duration: float, fps: float) -> int:
    """Frames that show an utterance: the nearest whole count, so video and audio (with the AAC encoder's
    padding) both end within a frame of the speech. The scene's frame range after Generate, the rendered
    video and the rows of the Live Link Face CSV."""
    return max(1, round(duration * fps))


def sparse_track(name: str, frames: np.ndarray, values: np.ndarray) -> Track:
    """A track without the keys linear interpolation between their neighbours reproduces exactly.

    Keys at the same frame keep the last value, so frames are strictly increasing.
    """
    frames = np.asarray(frames, dtype=np.float64)
    values = np.asarray(values, dtype=np.float64)
    unique_last = np.append(frames[1:] != frames[:-1], True)
    frames, values = frames[unique_last], values[unique_last]
    if frames.size > 2:
        share = (frames[1:-1] - frames[:-2]) / (frames[2:] - frames[:-2])
        between = values[:-2] + (values[2:] - values[:-2]) * share
        keep = np.ones(frames.size, dtype=bool)
        keep[1:-1] = np.abs(values[1:-1] - between) > 1e-9
        frames, values = frames[keep], values[keep]
    return Track(name=name, frames=frames, values=values)


def shown_shapes(weights: np.ndarray) -> np.ndarray:
    """Per frame, the column of the viseme holding at least half of the frame's viseme weight; -1: a blend."""
    weights = np.asarray(weights, dtype=np.float64)
    if weights.shape[1] == 0:
        return np.full(weights.shape[0], -1)
    best = weights.argmax(axis=1)
    top = weights[np.arange(weights.shape[0]), best]
    total = weights.sum(axis=1)
    return np.where((total > 0) & (top >= 0.5 * total), best, -1)


def shape_runs(labels: np.ndarray) -> list[tuple[int, int, int]]:
    """(label, first frame, length) of every run of frames showing the same shape (blends left out)."""
    runs = []
    start = 0
    for frame in range(1, len(labels) + 1):
        if frame == len(labels) or labels[frame] != labels[start]:
            if labels[start] >= 0:
                runs.append((int(labels[start]), start, frame - start))
            start = frame
    return runs


def sampled_weights(tracks: WeightTracks) -> tuple[tuple[str, ...], np.ndarray]:
    """Every track's weight at the integer frames 0 .. frame_count - 1."""
    return tracks.sample(np.arange(tracks.frame_count, dtype=np.float64))


def decimated_keys(values: np.ndarray, tolerance: float, passes: int = 4) -> np.ndarray:
    """Indices of the frames to key so that linear interpolation between them stays within tolerance of
    every frame's value (smooth motion needs a key every few frames, a saccade every one); first and last
    always kept. values (frames,) or (frames, channels): channels keyed together stay each within tolerance.
    Each pass drops every other key whose neighbours' line stays within tolerance of every frame between
    them."""
    values = np.asarray(values, np.float64)
    columns = values.reshape(values.shape[0], -1).T
    keep = np.arange(values.shape[0])
    frames = np.arange(values.shape[0])
    for _ in range(passes):
        if keep.size <= 2:
            break
        # The candidates are the keys at odd positions; the others (anchors) stay, and the spans between
        # neighbouring anchors, one around each candidate, cover the frames without overlapping.
        anchors = keep[::2] if keep.size % 2 else np.append(keep[::2], keep[-1])
        missed = np.zeros(frames.size, bool)
        for column in columns:
            missed |= np.abs(column - np.interp(frames, anchors, column[anchors])) > tolerance
        # Frames off the line so far; a span between anchors fits where none of its frames is off.
        off = np.cumsum(missed, dtype=np.int32)
        candidates = np.arange(1, keep.size - 1, 2)
        fits = (off[anchors[1:]] - off[anchors[:-1]])[: candidates.size] == 0
        if not fits.any():
            break
        drop = np.zeros(keep.size, bool)
        drop[candidates[fits]] = True
        keep = keep[~drop]
    return keep
