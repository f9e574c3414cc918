"""A room's late reverberation taken out of a recording's mel energies, its RT60 estimated from the take.

A live room keeps each sound ringing into the next: onsets come late and pauses fill up. The late
part of the reverberation is estimated from the energy the take had a moment before, decayed as the
room decays (Lebart, Boucher and Denbigh 2001: an exponential decay at the room's RT60), and
subtracted, never below a floor of the energy itself. Lebart lets the late part start 50 ms after
the direct sound; for alignment 20 ms is better (live room of RT60 0.3 s at 0 dB direct-to-reverberant,
tuning takes: word onsets median / p90 10 / 27 ms without, 9 / 22 at 50 ms, 6 / 18 at 20 ms), since what
matters is where the next sound begins, and the early reflections blur that as much as the tail.

The RT60 is read from the take itself: a room can make a sound die away no faster than it decays,
so the fastest free decays of the loud frames (speech offsets falling steadily for 100 ms) tell the
room's decay. On the tuning takes: a dry take reads 0.1-0.2 s (eSpeak's offsets are not instant), a
room of RT60 0.3 s reads 0.25-0.33 s, 0.4 s 0.33-0.38 s.
"""

from __future__ import annotations

import numpy as np

from .features import HOP
from .voice_activity import frame_levels

FRAME_SECONDS = HOP / 16_000
LATE_FRAMES = 2  # the late reverberation is taken as what follows the direct sound by 20 ms
DECAY_FRAMES = 10  # a free decay is followed over 100 ms
DECAY_FALL_DB = 10.0  # ... falling at least this much, never rising more than RISE_DB a frame
RISE_DB = 0.5
ABOVE_DB = 25.0  # decays start this far above the noise floor, and no further below the loudest frames
FASTEST_SHARE = 90  # percentile of the decay rates taken for the room's (the fastest tenth)
SUBTRACTED_FLOOR = 0.1  # a band keeps at least this share of its energy (-10 dB)
# A dry take reads 0.15-0.2 s (eSpeak's own offsets, a fast voice's): what a room adds to that is taken
# out, sqrt(rt60^2 - DRY_DECAY^2), so a dry take keeps its energies (word onsets of a 4-minute dry take:
# p90 10 ms when its 0.17 s is taken for a room, 6 ms without).
DRY_DECAY = 0.18
LONGEST_ROOM = 1.5


def estimate_rt60(samples: np.ndarray) -> float:
    """The room's RT60 (seconds) as the take's fastest steady decays show it; 0 when none is found."""
    levels = np.convolve(frame_levels(samples), np.ones(3) / 3, "same")
    if levels.size <= DECAY_FRAMES:
        return 0.0
    floor, loud = np.percentile(levels, 10), np.percentile(levels, 95)
    windows = np.lib.stride_tricks.sliding_window_view(levels, DECAY_FRAMES)
    starts = windows[:, 0]
    steady = (np.diff(windows, axis=1) < RISE_DB).all(axis=1)
    falling = starts - windows[:, -1] > DECAY_FALL_DB
    chosen = windows[steady & falling & (starts > floor + ABOVE_DB) & (starts > loud - ABOVE_DB)]
    if chosen.shape[0] < 5:
        return 0.0
    time = (np.arange(DECAY_FRAMES) - (DECAY_FRAMES - 1) / 2) * FRAME_SECONDS
    rates = -(chosen - chosen.mean(axis=1, keepdims=True)) @ time / (time @ time)  # dB per second
    fastest = np.percentile(rates, FASTEST_SHARE)
    return float(np.clip(60.0 / fastest, 0.0, LONGEST_ROOM)) if fastest > 0 else 0.0


def dereverberate(energies: np.ndarray, rt60: float) -> np.ndarray:
    """Mel energies (frames x bands) less the late reverberation of a room with this RT60."""
    room = np.sqrt(max(rt60**2 - DRY_DECAY**2, 0.0))
    if room < 0.05 or len(energies) <= LATE_FRAMES:
        return energies
    decay = 10 ** (-6.0 * LATE_FRAMES * FRAME_SECONDS / room)  # power left LATE_FRAMES on
    # Three frames' mean steadies the estimate (the ends repeated); made with as few copies of the
    # energies as can be (a long take's are tens of megabytes: 30 minutes' peak 695 -> 663 MB).
    local = energies.copy()
    local[1:] += energies[:-1]
    local[:-1] += energies[1:]
    local[[0, -1]] += energies[[0, -1]]
    local *= decay / 3
    result = energies.copy()
    result[LATE_FRAMES:] -= local[:-LATE_FRAMES]
    del local
    return np.maximum(result, SUBTRACTED_FLOOR * energies, out=result)
