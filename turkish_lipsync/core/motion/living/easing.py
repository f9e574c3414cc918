"""The easing curves the living layers move by: 0 before x = 0, 1 after x = 1, smooth between."""

from __future__ import annotations

import numpy as np


def smoothstep(x: np.ndarray) -> np.ndarray:
    """3x^2 - 2x^3: no velocity at either end (postures, brows)."""
    x = np.minimum(np.maximum(x, 0.0), 1.0)  # np.clip's dispatch costs more than the work on short spans
    return x * x * (3.0 - 2.0 * x)


def minimum_jerk(x: np.ndarray) -> np.ndarray:
    """10x^3 - 15x^4 + 6x^5: no velocity or acceleration at either end (saccades, Flash and Hogan 1985)."""
    x = np.minimum(np.maximum(x, 0.0), 1.0)
    return x**3 * (10 - 15 * x + 6 * x * x)
