"""Spectral features for aligning two renditions of a text, made comparable across voices and rooms.

Log mel energies per 10 ms frame of 16 kHz audio, then three normalisations so that what is left is
mostly *what* is said: each band is floored at a common noise floor (the louder of the two signals'
floors, relative to their speech level), so a quiet room and eSpeak's digital silence look alike and
noise does not drown quiet consonants on one side only; the frequency axis of the recording can be
stretched (vocal-tract-length warp) to meet the synthetic voice's formants; and the cepstra are
normalised to zero mean and unit variance over each signal's speech frames (CMVN), which removes the
microphone's and the voice's average colour. Their slopes over five frames join them: onsets, which a
room's reverberation blurs in the spectrum, stay sharp in the slopes (word onsets under RT60 0.4 s: a
median 24 ms late without them, 15 ms with them, on the tuning sentences).
"""

from __future__ import annotations

import numpy as np

ANALYSIS_RATE = 16_000
HOP = 160  # samples: 10 ms
WINDOW = 400  # samples: 25 ms
FFT_SIZE = 512
MEL_BANDS = 32
LOW_HERTZ = 150.0  # below this a high voice shows single harmonics, not the vocal tract
TOP_HERTZ = 7000.0
CEPSTRA = 10  # c1..c9: the envelope, not the pitch; c0 (loudness) differs between voices and rooms
FLOOR_BELOW_SPEECH_DB = 55.0  # the floor of a signal without noise (eSpeak's silence)
DELTA_SPAN = 2  # frames each side of a slope
_BLOCK = 4096  # frames per block (bounds the spectrogram's memory)


def frame_count(sample_count: int) -> int:
    return max(1, 1 + (sample_count - 1) // HOP)


def frame_seconds(frames: np.ndarray | float, lead: int = 0) -> np.ndarray:
    """Centre time (seconds) of analysis frames, `lead` padding frames before time zero."""
    return ((np.asarray(frames, dtype=np.float64) - lead) * HOP + WINDOW / 2) / ANALYSIS_RATE


def mel_energies(
    samples: np.ndarray,
    warp: float = 1.0,
    top_hertz: float = TOP_HERTZ,
    bands: int = MEL_BANDS,
    low_hertz: float = LOW_HERTZ,
) -> np.ndarray:
    """Mel band energies (frames x bands, float32) of 16 kHz samples; warp > 1 lowers the formants.

    top_hertz: highest frequency described (both signals of an alignment must use the same one); the
    recogniser (recognition/acoustics.py) describes more bands from lower down, where nasals murmur.
    """
    filters = mel_filters(warp, top_hertz, bands, low_hertz).T
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


def band_levels(energies: np.ndarray, speech: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per band: the speech level (its loud frames) and the noise level (its quiet frames)."""
    voiced = energies[speech] if speech.sum() >= 10 else energies
    level = np.percentile(voiced, 90, axis=0) + 1e-12
    noise = np.percentile(energies, 10, axis=0) if (~speech).sum() >= 10 else np.zeros(MEL_BANDS)
    return level, noise


def common_floor(
    synthetic: tuple[np.ndarray, np.ndarray], recorded: tuple[np.ndarray, np.ndarray]
) -> np.ndarray:
    """The floor relative to each signal's speech level that both share: the noisier one's."""
    relative = [
        np.maximum(noise / level, 10 ** (-FLOOR_BELOW_SPEECH_DB / 10))
        for level, noise in (synthetic, recorded)
    ]
    return np.maximum(*relative)


def cepstra(energies: np.ndarray, level: np.ndarray, floor: np.ndarray, speech: np.ndarray) -> np.ndarray:
    """c1..c9 of the floored log mel energies and the slopes of c0..c9, normalised over the speech frames.

    The slopes mark where a sound begins, which a room's reverberation blurs in the spectrum itself.
    """
    logs = np.log(np.maximum(energies, level * floor))
    everything = logs @ _dct_matrix().T
    padded = np.pad(everything, ((DELTA_SPAN, DELTA_SPAN), (0, 0)), mode="edge")
    frames = len(everything)
    slopes = sum(
        step
        * (
            padded[DELTA_SPAN + step : DELTA_SPAN + step + frames]
            - padded[DELTA_SPAN - step : DELTA_SPAN - step + frames]
        )
        for step in range(1, DELTA_SPAN + 1)
    )
    features = np.concatenate((everything[:, 1:], slopes), axis=1)
    reference = features[speech] if speech.sum() >= 10 else features
    features -= reference.mean(axis=0)
    features /= reference.std(axis=0) + 1e-6
    return features.astype(np.float32)


def mel_filters(
    warp: float, top_hertz: float, bands: int = MEL_BANDS, low_hertz: float = LOW_HERTZ
) -> np.ndarray:
    """Triangular mel filters (bands x FFT_SIZE // 2 + 1), low_hertz to top_hertz, stretched by warp."""

    def to_mel(hertz):
        return 2595 * np.log10(1 + np.asarray(hertz) / 700)

    def to_hertz(mel):
        return 700 * (10 ** (np.asarray(mel) / 2595) - 1)

    edges = to_hertz(np.linspace(to_mel(low_hertz), to_mel(top_hertz), bands + 2)) * warp
    bins = np.fft.rfftfreq(FFT_SIZE, 1 / ANALYSIS_RATE)
    lower, centre, upper = edges[:-2, None], edges[1:-1, None], edges[2:, None]
    rising = (bins[None, :] - lower) / (centre - lower)
    falling = (upper - bins[None, :]) / (upper - centre)
    return np.clip(np.minimum(rising, falling), 0, None).astype(np.float32)


def _dct_matrix() -> np.ndarray:
    n = np.arange(MEL_BANDS)
    return np.cos(np.pi / MEL_BANDS * (n[None, :] + 0.5) * np.arange(CEPSTRA)[:, None])
