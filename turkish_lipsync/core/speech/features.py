"""Spectra of 16 kHz audio in 10 ms frames: the frame grid every analysis of speech shares, mel energies.

The acoustic model (acoustic/features.py) describes its frames from these mel energies; the recording
aligner, the speech detector and the pitch tracker count frames on the same grid.
"""

from __future__ import annotations

import numpy as np

ANALYSIS_RATE = 16_000
HOP = 160  # samples: 10 ms
WINDOW = 400  # samples: 25 ms
FFT_SIZE = 512
_BLOCK = 4096  # frames per block (bounds the spectrogram's memory)


def frame_count(sample_count: int) -> int:
    return max(1, 1 + (sample_count - 1) // HOP)


def frame_seconds(frames: np.ndarray | float, lead: int = 0) -> np.ndarray:
    """Centre time (seconds) of analysis frames, `lead` padding frames before time zero."""
    return ((np.asarray(frames, dtype=np.float64) - lead) * HOP + WINDOW / 2) / ANALYSIS_RATE


def mel_energies(samples: np.ndarray, top_hertz: float, bands: int, low_hertz: float) -> np.ndarray:
    """Mel band energies (frames x bands, float32) of 16 kHz samples, low_hertz to top_hertz."""
    filters = mel_filters(top_hertz, bands, low_hertz).T
    count = frame_count(samples.size)
    energies = np.empty((count, bands), np.float32)
    for begin, power in power_spectra(samples):
        energies[begin : begin + len(power)] = power @ filters
    return energies


def power_spectra(samples: np.ndarray):
    """(first frame, power spectra of a block of frames (frames x FFT_SIZE // 2 + 1, float32)), in order."""
    taper = np.hanning(WINDOW).astype(np.float32)
    count = frame_count(samples.size)
    for begin in range(0, count, _BLOCK):
        frames = np.arange(begin, min(begin + _BLOCK, count))
        piece = samples[begin * HOP : frames[-1] * HOP + WINDOW].astype(np.float32)
        piece = np.pad(piece, (0, (frames.size - 1) * HOP + WINDOW - piece.size))
        rows = piece[(frames - begin)[:, None] * HOP + np.arange(WINDOW)[None, :]] * taper
        spectrum = np.fft.rfft(rows, FFT_SIZE, axis=1)
        yield begin, (spectrum.real**2 + spectrum.imag**2).astype(np.float32)


def mel_filters(top_hertz: float, bands: int, low_hertz: float) -> np.ndarray:
    """Triangular mel filters (bands x FFT_SIZE // 2 + 1), low_hertz to top_hertz."""

    def to_mel(hertz):
        return 2595 * np.log10(1 + np.asarray(hertz) / 700)

    def to_hertz(mel):
        return 700 * (10 ** (np.asarray(mel) / 2595) - 1)

    edges = to_hertz(np.linspace(to_mel(low_hertz), to_mel(top_hertz), bands + 2))
    bins = np.fft.rfftfreq(FFT_SIZE, 1 / ANALYSIS_RATE)
    lower, centre, upper = edges[:-2, None], edges[1:-1, None], edges[2:, None]
    rising = (bins[None, :] - lower) / (centre - lower)
    falling = (upper - bins[None, :]) / (upper - centre)
    return np.clip(np.minimum(rising, falling), 0, None).astype(np.float32)
