"""Writing speech audio as a 16-bit PCM WAV (stdlib wave: no dependency, plays everywhere)."""

from __future__ import annotations

import wave
from pathlib import Path

import numpy as np

from ..base.errors import AudioError
from .base import Synthesis


def write_wav(path: str | Path, synthesis: Synthesis) -> Path:
    """Write the synthesis's samples as mono 16-bit PCM; returns the path written."""
    path = Path(path)
    samples = np.asarray(synthesis.samples, dtype="<i2")
    try:
        with wave.open(str(path), "wb") as handle:
            handle.setnchannels(1)
            handle.setsampwidth(2)
            handle.setframerate(int(synthesis.sample_rate))
            handle.writeframes(samples.tobytes())
    except OSError as error:
        raise AudioError(
            f"cannot write the speech audio to {path}: {error}; choose a writable file path"
        ) from None
    return path
