"""Frame helpers below both motion models and the quality report: sparse tracks, shapes shown per frame."""

from __future__ import annotations

import numpy as np

from ..base.model import Track, WeightTracks


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
    always kept. Each pass drops every other key whose value its neighbours reproduce."""
    values = np.asarray(values, np.float64)
    keep = np.arange(values.size)
    for _ in range(passes):
        if keep.size <= 2:
            break
        candidates = np.arange(1, keep.size - 1, 2)
        before, here, after = keep[candidates - 1], keep[candidates], keep[candidates + 1]
        share = (here - before) / (after - before)
        between = values[before] + (values[after] - values[before]) * share
        # The frames between the outer keys must also stay close once the middle key is gone.
        fits = np.abs(values[here] - between) <= tolerance
        fits &= _spans_fit(values, before, after, tolerance)
        if not fits.any():
            break
        drop = np.zeros(keep.size, bool)
        drop[candidates[fits]] = True
        keep = keep[~drop]
    return keep


def _spans_fit(values: np.ndarray, first: np.ndarray, last: np.ndarray, tolerance: float) -> np.ndarray:
    """For each span first..last, whether the line between its ends stays within tolerance of every frame."""
    lengths = last - first + 1
    owner = np.repeat(np.arange(first.size), lengths)
    frames = np.repeat(first, lengths) + (
        np.arange(owner.size) - np.repeat(np.cumsum(lengths) - lengths, lengths)
    )
    share = (frames - first[owner]) / np.maximum(last[owner] - first[owner], 1)
    line = values[first[owner]] + (values[last[owner]] - values[first[owner]]) * share
    error = np.abs(values[frames] - line) > tolerance
    return ~np.bincount(owner, weights=error, minlength=first.size).astype(bool)
