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


CLOSURE_STRETCH = 3.0  # a recorded closure lasts at most this many times the synthetic one ...
LONGEST_CLOSURE = 0.15  # ... and at most this long (seconds)
JUMP = 1e-6  # seconds between the two knots of a jump (ends of events are warped this much before them)
PAUSE_BEFORE_CLOSURE = 0.01  # seconds of a jump of the warp right before a stop: a pause its closure lies in


def warp_synthesis(synthesis: Synthesis, warp: TimeWarp, samples: np.ndarray) -> Synthesis:
    """The synthesis's events moved onto the recording's time, holding the recording's samples."""
    phones = synthesis.phone_events
    synthetic_starts = np.array([event.start for event in phones])
    synthetic_ends = np.array([event.end for event in phones])
    starts = warp(synthetic_starts)
    ends = warp(synthetic_ends - JUMP)  # a pause after a phone follows its end
    # A closure lasts as long as its part of the phone before it does in the recording (a pause between
    # the two is a jump of the warp, which it does not take), but no longer than a person's closures go.
    # Where that phone is drawn out past them (a vowel holding a hesitation said aloud that the alignment
    # took for its own), the closure is as much longer or shorter than eSpeak NG's as the stop and the
    # phone after it are, and no longer than a pause before the stop.
    synthetic_closures = np.array([event.closure for event in phones])
    longest = np.minimum(CLOSURE_STRETCH * synthetic_closures, LONGEST_CLOSURE)
    just_before = warp(synthetic_starts - JUMP)
    before = just_before - warp(synthetic_starts - synthetic_closures)
    own_end = np.append(synthetic_ends[1:], synthetic_ends[-1:])
    own = own_end - synthetic_starts
    tempo = np.divide(warp(own_end - JUMP) - starts, own, out=np.ones_like(own), where=own > 0)
    paused = starts - just_before
    at_own_pace = np.minimum(
        synthetic_closures * tempo, np.where(paused > PAUSE_BEFORE_CLOSURE, paused, np.inf)
    )
    closures = np.minimum(np.where(before > longest, at_own_pace, before), longest)
    closures = np.where(synthetic_closures > 0, np.maximum(closures, 0.0), 0.0)
    words = synthesis.word_events
    word_starts = warp(np.array([event.start for event in words]))
    return Synthesis(
        samples=samples,
        sample_rate=synthesis.sample_rate,
        phone_events=tuple(
            replace(event, start=float(start), end=float(end), closure=float(closure))
            for event, start, end, closure in zip(phones, starts, ends, closures, strict=True)
        ),
        word_events=tuple(
            replace(event, start=float(start)) for event, start in zip(words, word_starts, strict=True)
        ),
        engine="recording",
    )


def with_closures(synthesis: Synthesis) -> Synthesis:
    """The synthesis with each phone started at its closure (PhoneEvent.closure), which it takes from the
    end of the phone before: the lips of a p are shut, and a t or k held, while its closure is silent."""
    events = list(synthesis.phone_events)
    for number, event in enumerate(events):
        if event.closure <= 0:
            continue
        start = event.start - event.closure
        if number:
            before = events[number - 1]
            start = max(start, before.start)
            events[number - 1] = replace(before, end=min(before.end, start))
        events[number] = replace(event, start=start, closure=0.0)
    return replace(synthesis, phone_events=tuple(events))
