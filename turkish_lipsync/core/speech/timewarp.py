"""The map from synthetic time to a recording's time, made from a DTW path, and the events moved by it."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .base import Synthesis
from .features import frame_seconds


@dataclass(frozen=True, eq=False)
class TimeWarp:
    """Synthetic time (seconds) to recording time: piecewise linear through matched frame times."""

    synthetic: np.ndarray  # increasing knot times in the synthetic speech
    recorded: np.ndarray  # non-decreasing knot times in the recording
    recording_duration: float

    def __call__(self, times: np.ndarray | float) -> np.ndarray:
        times = np.asarray(times, dtype=np.float64)
        warped = np.interp(times, self.synthetic, self.recorded)
        # Outside the speech the two signals run at the same speed (silence before and after).
        before = times < self.synthetic[0]
        after = times > self.synthetic[-1]
        warped = np.where(before, self.recorded[0] - (self.synthetic[0] - times), warped)
        warped = np.where(after, self.recorded[-1] + (times - self.synthetic[-1]), warped)
        return np.clip(warped, 0.0, self.recording_duration)


def warp_from_path(
    path_x: np.ndarray,
    path_y: np.ndarray,
    synthetic_speech: np.ndarray,
    recorded_speech: np.ndarray,
    lead: int,
    recording_duration: float,
) -> TimeWarp:
    """Knots where speech meets speech, each synthetic frame at the mean recording frame matched to it.

    Silence matches silence at no cost, so the path through a pause is arbitrary: pauses are crossed
    linearly between the last and first words around them.
    """
    both = synthetic_speech[path_x] & recorded_speech[path_y]
    if both.sum() < 2:
        both[:] = True
    frames = len(synthetic_speech)
    weights = np.bincount(path_x[both], minlength=frames)
    knots = np.flatnonzero(weights)
    matched = np.bincount(path_x[both], weights=path_y[both], minlength=frames)[knots] / weights[knots]
    knots = np.concatenate(([path_x[0]], knots, [path_x[-1]]))
    matched = np.maximum.accumulate(np.concatenate(([path_y[0]], matched, [path_y[-1]])))
    unique = np.concatenate(([True], np.diff(knots) > 0))
    return TimeWarp(
        synthetic=frame_seconds(knots[unique], lead),
        recorded=frame_seconds(matched[unique]),
        recording_duration=recording_duration,
    )


def warp_synthesis(synthesis: Synthesis, warp: TimeWarp, samples: np.ndarray) -> Synthesis:
    """The synthesis's events moved onto the recording's time, holding the recording's samples."""
    phones = synthesis.phone_events
    starts = warp(np.array([event.start for event in phones]))
    ends = warp(np.array([event.end for event in phones]))
    words = synthesis.word_events
    word_starts = warp(np.array([event.start for event in words]))
    return Synthesis(
        samples=samples,
        sample_rate=synthesis.sample_rate,
        phone_events=tuple(
            replace(event, start=float(start), end=float(end))
            for event, start, end in zip(phones, starts, ends, strict=True)
        ),
        word_events=tuple(
            replace(event, start=float(start)) for event, start in zip(words, word_starts, strict=True)
        ),
        engine="recording",
    )
