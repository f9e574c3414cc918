"""The map from synthetic time to a recording's time, made from a DTW path, and the events moved by it."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .base import Synthesis
from .features import ANALYSIS_RATE, HOP, frame_seconds


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
    recorded_pause: np.ndarray,
    lead: int,
    recording_duration: float,
    word_onsets: np.ndarray,
) -> TimeWarp:
    """Knots where speech meets speech, each synthetic frame at the mean recording frame matched to it.

    Silence matches silence at no cost, so the path through a pause is arbitrary: pauses both make are
    crossed linearly between the words around them. A pause only the recording makes (a hesitation)
    is put before the word whose onset the path holds through it (held_pauses).
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
    synthetic, recorded = frame_seconds(knots[unique], lead), frame_seconds(matched[unique])
    holds = held_pauses(path_x, path_y, synthetic_speech, recorded_pause, lead, word_onsets)
    for onset, pause_start, pause_end in holds:
        synthetic, recorded = _jump(synthetic, recorded, onset, pause_start, pause_end)
    return TimeWarp(synthetic=synthetic, recorded=recorded, recording_duration=recording_duration)


HELD_PAUSE_FRAMES = 10  # a recorded stretch this long (100 ms) held by synthetic speech is a hesitation
HELD_REACH = 2  # frames of synthetic speech a hold may move through
ONSET_REACH = 0.06  # seconds from the held synthetic frame to the word onset the pause is put before
HALF_HOP = HOP / ANALYSIS_RATE / 2
JUMP = 1e-6  # seconds between the two knots of a jump (ends of events are warped this much before them)


def held_pauses(
    path_x: np.ndarray,
    path_y: np.ndarray,
    synthetic_speech: np.ndarray,
    recorded_pause: np.ndarray,
    lead: int,
    word_onsets: np.ndarray,
) -> list[tuple[float, float, float]]:
    """(synthetic word onset, recorded pause start, end) of each pause the recording alone makes.

    Such a pause is where the path holds synthetic speech (within HELD_REACH frames) next to a word
    onset while the recording goes on for HELD_PAUSE_FRAMES or more, mostly through its pauses
    (recorded_pause: silence, or a stretch near the noise floor). A slow speaker's long vowel is held
    too, but through speech.
    """
    change = np.flatnonzero(np.diff(path_x)) + 1
    starts = np.concatenate(([0], change))
    stops = np.concatenate((change, [path_x.size]))
    found = []
    group = None  # [first path index, last path index] of the hold being followed
    for first, stop in zip(starts, stops, strict=True):
        if group is not None and path_x[first] - path_x[group[0]] <= HELD_REACH and stop - first > 1:
            group[1] = stop - 1
            continue
        if group is not None:
            found.extend(_held(group, path_x, path_y, synthetic_speech, recorded_pause, lead, word_onsets))
        group = [first, stop - 1] if stop - first > 1 else None
    if group is not None:
        found.extend(_held(group, path_x, path_y, synthetic_speech, recorded_pause, lead, word_onsets))
    return found


def _held(
    group, path_x, path_y, synthetic_speech, recorded_pause, lead, word_onsets
) -> list[tuple[float, float, float]]:
    first, last = group
    begin, end = int(path_y[first]), int(path_y[last])
    held = path_x[first : last + 1]
    if end - begin + 1 < HELD_PAUSE_FRAMES or begin == 0 or end == int(path_y[-1]):
        return []
    if synthetic_speech[held].mean() < 0.5 or word_onsets.size == 0:
        return []  # the synthetic speech pauses here too
    if recorded_pause[begin : end + 1].mean() < 0.5:
        return []  # speech said slowly, not a pause
    at = float(frame_seconds(np.median(held), lead))
    nearest = int(np.argmin(np.abs(word_onsets - at)))
    if abs(word_onsets[nearest] - at) > ONSET_REACH:
        return []
    # Knots sit at frame centres: the pause lies between the centres of its first and last frames.
    pause_start = float(frame_seconds(begin)) - HALF_HOP
    pause_end = float(frame_seconds(end + 1)) - HALF_HOP
    return [(float(word_onsets[nearest]), pause_start, pause_end)]


def _jump(
    synthetic: np.ndarray, recorded: np.ndarray, onset: float, pause_start: float, pause_end: float
) -> tuple[np.ndarray, np.ndarray]:
    """The knots with the recording's pause put just before the synthetic onset.

    Knots inside the pause or on the wrong side of it (a frame matched to speech on both sides has the
    mean of the two) are dropped; the word before keeps its synthetic pace up to
    the onset, the word after from it, and neither crosses into the pause beyond what the knots allow.
    """
    keep = ((synthetic < onset) & (recorded <= pause_start)) | (
        (synthetic >= onset) & (recorded >= pause_end)
    )
    synthetic, recorded = synthetic[keep], recorded[keep]
    split = int(np.searchsorted(synthetic, onset))
    if split == 0 or split == synthetic.size:
        return synthetic, recorded
    s0, r0, s1, r1 = synthetic[split - 1], recorded[split - 1], synthetic[split], recorded[split]
    after = float(np.clip(r1 - (s1 - onset), pause_start, r1))
    before = float(np.clip(r0 + (onset - s0), r0, min(pause_start, after)))
    synthetic = np.concatenate((synthetic[:split], [onset - JUMP, onset], synthetic[split:]))
    recorded = np.concatenate((recorded[:split], [before, after], recorded[split:]))
    return synthetic, recorded


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
