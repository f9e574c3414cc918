"""Measures of a timeline against its truth: how open the mouth is over time, which bilabials close.

The audio-alone and the people measures (lab/measure) score with them, and so do the tests of the recogniser.
"""

from __future__ import annotations

from functools import cache

import numpy as np

from turkish_lipsync.core.base.model import Timeline
from turkish_lipsync.core.base.visemes import BILABIAL_VISEMES, VOWEL_VISEMES

GRID = 0.01  # seconds


SMOOTHING = 0.06  # seconds


CLOSURE_TOLERANCE = 0.02  # seconds


@cache
def viseme_openings() -> dict[str, float]:
    """Each viseme's opening 0..1: the reference head's midline lip aperture under it over that of a."""
    from turkish_lipsync.core.faces.measure import FaceMeasure
    from turkish_lipsync.core.faces.recipes import key_deltas
    from turkish_lipsync.core.faces.reference import load_reference_head

    head = load_reference_head()
    measure = FaceMeasure(head.vertices, head.polygons, head.landmarks)
    deltas = key_deltas({name: np.asarray(unit) for name, unit in head.units.items()}, len(head.vertices))
    prefix = "TR_viseme_"
    apertures = {
        name.removeprefix(prefix): measure.lip_aperture(delta)
        for name, delta in deltas.items()
        if name.startswith(prefix)
    }
    widest = apertures["a"]
    return {name: float(np.clip(aperture / widest, 0.0, 1.0)) for name, aperture in apertures.items()}


def opening_trajectory(timeline: Timeline, duration: float, offset: float = 0.0) -> np.ndarray:
    """The opening of the viseme spoken at each GRID step (0 where none is), smoothed over SMOOTHING."""
    openings = viseme_openings()
    grid = np.zeros(int(np.ceil(duration / GRID)))
    times = np.arange(grid.size) * GRID
    for phone in timeline.phones:
        first, stop = np.searchsorted(times, (phone.start + offset, phone.end + offset))
        grid[first:stop] = openings[phone.viseme]
    return smoothed(grid)


def smoothed(values: np.ndarray) -> np.ndarray:
    width = int(round(SMOOTHING / GRID))
    return np.convolve(values, np.ones(width) / width, mode="same")


def loudness_envelope(samples: np.ndarray, rate: int, count: int) -> np.ndarray:
    """The take's amplitude per GRID step, smoothed like the trajectories (the baseline)."""
    hop = int(rate * GRID)
    frames = samples[: samples.size // hop * hop].reshape(-1, hop)
    amplitude = np.sqrt(np.mean(frames**2, axis=1))
    return smoothed(np.pad(amplitude, (0, max(0, count - amplitude.size)))[:count])


def correlation(first: np.ndarray, second: np.ndarray) -> float:
    count = min(first.size, second.size)
    return float(np.corrcoef(first[:count], second[:count])[0, 1])


def bilabial_scores(truth: Timeline, found: Timeline, offset: float) -> tuple[int, int, int, int]:
    """(truth's bilabials closed, truth's bilabials, truth's vowels closed, truth's vowels)."""
    closures = np.array(
        [(phone.start, phone.end) for phone in found.phones if phone.viseme in BILABIAL_VISEMES]
    ).reshape(-1, 2)
    closed = bilabials = vowels_closed = vowels = 0
    for phone in truth.phones:
        start, end = phone.start + offset, phone.end + offset
        if phone.viseme in BILABIAL_VISEMES:
            bilabials += 1
            closed += bool(
                np.any(
                    (closures[:, 0] < end + CLOSURE_TOLERANCE) & (closures[:, 1] > start - CLOSURE_TOLERANCE)
                )
            )
        elif phone.viseme in VOWEL_VISEMES:
            vowels += 1
            middle = (start + end) / 2
            vowels_closed += bool(np.any((closures[:, 0] <= middle) & (closures[:, 1] > middle)))
    return closed, bilabials, vowels_closed, vowels
