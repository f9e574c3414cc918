"""Brow raises: on emphasised words (EMP) and on the strongest pitch accents (Cavé et al. 1996 find brow
raises come mostly with F0 rises), a little before the accent and settling after it."""

from __future__ import annotations

import numpy as np

from .easing import smoothstep
from .phrases import SpeechStructure


def brow_curve(
    emphases: tuple[tuple[float, float], ...],
    structure: SpeechStructure,
    times: np.ndarray,
    settings: dict,
    amount: float,
) -> np.ndarray:
    """The brow raise's weight over the frame times (0..1); amount scales the accents' raises."""
    curve = np.zeros(times.size)
    raises = [(start, end, settings["weight"]) for start, end in emphases]
    last = -np.inf
    for accent in structure.accents:
        if accent.rise < settings["accent_rise"] or accent.time - last < settings["accent_gap"]:
            continue
        raises.append((accent.time, accent.time, amount * settings["accent_weight"] * accent.strength))
        last = accent.time
    for start, end, weight in raises:
        near = slice(*np.searchsorted(times, [start - settings["lead"], end + settings["fall"]]))
        local = times[near]
        rising = smoothstep((local - (start - settings["lead"])) / max(settings["rise"], 1e-6))
        falling = 1.0 - smoothstep((local - end) / max(settings["fall"], 1e-6))
        curve[near] = np.maximum(curve[near], weight * np.minimum(rising, falling))
    return np.clip(curve, 0.0, 1.0)
