"""The life of an expression: at its apex an emotion breathes instead of holding flat.

Deng et al. drive expressions with a dynamic expression signal rather than a constant weight; here each
emotion's weight dips a little below its apex and comes back, slowly and irregularly, and less where the
voice is loud (the face is most animated on the stressed words). The emotion's mouth release moves with it
by the same factor, so the lips still close fully on every m, b and p.
"""

from __future__ import annotations

import numpy as np

from .phrases import SpeechStructure


def emotion_life(
    structure: SpeechStructure, times: np.ndarray, rng: np.random.Generator, settings: dict, amount: float
) -> np.ndarray:
    """A factor (0..1, mostly near 1) to multiply an emotion's weight by at each frame."""
    tempo = settings["tempo"]
    wave = np.zeros(times.size)
    for _ in range(3):
        frequency = tempo * rng.uniform(0.6, 1.6)
        wave += np.sin(2 * np.pi * frequency * times + rng.uniform(0, 2 * np.pi))
    wander = 0.5 + wave / 6.0  # 0..1
    if structure.prosody is not None:
        energy = structure.prosody.at(times, structure.prosody.energy)
        quiet = 1.0 - np.clip((energy + 30.0) / 30.0, 0.0, 1.0)
    else:
        quiet = structure.in_pause(times).astype(float)
    share = settings["loudness"]
    dip = (1 - share) * wander + share * quiet
    return 1.0 - np.clip(amount * settings["depth"], 0.0, 1.0) * np.clip(dip, 0.0, 1.0)
