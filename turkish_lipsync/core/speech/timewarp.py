"""The map from synthetic time to a recording's time, and the synthetic events moved by it."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .base import Synthesis


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


JUMP = 1e-6  # seconds between the two knots of a jump (ends of events are warped this much before them)


def warp_synthesis(synthesis: Synthesis, warp: TimeWarp, samples: np.ndarray) -> Synthesis:
    """The synthesis's events moved onto the recording's time, holding the recording's samples."""
    phones = synthesis.phone_events
    starts = warp(np.array([event.start for event in phones]))
    ends = warp(np.array([event.end for event in phones]) - JUMP)  # a pause after a phone follows its end
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
