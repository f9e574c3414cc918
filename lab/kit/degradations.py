"""Noise, music, rooms and channels: the degradations the acoustic model trains on, also heard by the speech
detector's and the recogniser's measures and tests (16 kHz float samples).
"""

from __future__ import annotations

import numpy as np

from turkish_lipsync.core.speech.audio import resample
from turkish_lipsync.core.speech.features import ANALYSIS_RATE


def coloured_noise(count: int, colour: str, rng: np.random.Generator) -> np.ndarray:
    """Unit-power noise: white, pink (1/f), brown (1/f^2) or babble-like (speech-shaped, pulsing)."""
    white = rng.normal(size=count)
    if colour in ("pink", "brown", "babble"):
        spectrum = np.fft.rfft(white)
        frequency = np.maximum(np.fft.rfftfreq(count, 1 / ANALYSIS_RATE), 20.0)
        if colour == "babble":
            spectrum *= np.exp(-(((np.log(frequency) - np.log(600)) / 1.0) ** 2))
        else:
            spectrum /= frequency ** (0.5 if colour == "pink" else 1.0)
        white = np.fft.irfft(spectrum, count)
        if colour == "babble":
            white *= 1 + 0.6 * np.sin(2 * np.pi * 4 * np.arange(count) / ANALYSIS_RATE + rng.random() * 6)
    return white / np.sqrt(np.mean(white**2) + 1e-20)


def speech_power(samples: np.ndarray) -> float:
    frames = samples[: samples.size // 320 * 320].reshape(-1, 320)
    power = np.mean(frames**2, axis=1)
    return float(np.mean(power[power >= np.median(power)]) + 1e-12)


def room(samples: np.ndarray, seconds: float, rng: np.random.Generator) -> np.ndarray:
    length = int(seconds * ANALYSIS_RATE)
    decay = np.exp(-6.9 * np.arange(length) / length)
    response = rng.uniform(0.2, 0.6) * rng.normal(size=length) * decay * np.sqrt(300 / length)
    response[0] = 1.0
    size = 1 << int(np.ceil(np.log2(samples.size + length)))
    wet = np.fft.irfft(np.fft.rfft(samples, size) * np.fft.rfft(response, size), size)[: samples.size]
    return wet * np.sqrt(speech_power(samples) / speech_power(wet))


def band_limited(samples: np.ndarray, low: float, high: float) -> np.ndarray:
    spectrum = np.fft.rfft(samples)
    frequency = np.fft.rfftfreq(samples.size, 1 / ANALYSIS_RATE)
    gain = 1 / (1 + (low / np.maximum(frequency, 1.0)) ** 4) / (1 + (frequency / high) ** 8)
    return np.fft.irfft(spectrum * gain, samples.size)


def music(count: int, rng: np.random.Generator) -> np.ndarray:
    """Synthetic music: notes of a scale with harmonics and envelopes, chords, and drums."""
    out = np.zeros(count)
    beat = rng.uniform(0.25, 0.7)
    scale = 220 * 2 ** (np.array([0, 2, 4, 5, 7, 9, 11, 12, 14, 16]) / 12) * rng.uniform(0.5, 2.0)
    harmonics = rng.uniform(0.2, 0.9) ** np.arange(1, 9)
    time_index = np.arange(count) / ANALYSIS_RATE
    start = 0.0
    while start < count / ANALYSIS_RATE:
        length = beat * rng.choice([0.5, 1, 1, 2])
        first, stop = int(start * ANALYSIS_RATE), min(count, int((start + length * 1.5) * ANALYSIS_RATE))
        local = time_index[first:stop] - start
        envelope = np.minimum(local / 0.01, 1) * np.exp(-local / rng.uniform(0.1, 0.8))
        for pitch in rng.choice(scale, size=int(rng.integers(1, 4))):
            tone = sum(
                amplitude * np.sin(2 * np.pi * pitch * (h + 1) * local)
                for h, amplitude in enumerate(harmonics)
                if pitch * (h + 1) < 7500
            )
            out[first:stop] += envelope * tone
        if rng.random() < 0.5:
            hit = min(count - first, int(0.15 * ANALYSIS_RATE))
            out[first : first + hit] += (
                rng.uniform(0.5, 2) * rng.normal(size=hit) * np.exp(-np.arange(hit) / (0.02 * ANALYSIS_RATE))
            )
        start += length
    return out / np.sqrt(np.mean(out**2) + 1e-20)


def degrade(samples: np.ndarray, rng: np.random.Generator) -> tuple[np.ndarray, float, float]:
    """A degraded copy, the lead added (seconds) and the time stretch applied."""
    stretch = 1.0
    if rng.random() < 0.5:  # another vocal tract: everything up or down in frequency, shorter or longer
        factor = rng.uniform(0.88, 1.12)
        samples = resample(samples, int(round(ANALYSIS_RATE * factor)), ANALYSIS_RATE)
        stretch = 1 / factor
    lead, tail = rng.uniform(0.05, 1.5), rng.uniform(0.05, 1.0)
    samples = np.concatenate(
        (np.zeros(int(lead * ANALYSIS_RATE)), samples, np.zeros(int(tail * ANALYSIS_RATE)))
    )
    if rng.random() < 0.3:
        samples = room(samples, rng.uniform(0.15, 0.8), rng)
    if rng.random() < 0.25:
        samples = band_limited(samples, rng.uniform(60, 400), rng.uniform(2800, 7500))
    power = speech_power(samples)
    if rng.random() < 0.1:
        samples = samples + music(samples.size, rng) * np.sqrt(power / 10 ** (rng.uniform(5, 25) / 10))
    if rng.random() < 0.8:
        colour = rng.choice(["white", "pink", "brown", "babble"])
        snr = rng.uniform(0, 40)
        samples = samples + coloured_noise(samples.size, colour, rng) * np.sqrt(power / 10 ** (snr / 10))
    gain = 10 ** (rng.uniform(-30, 0) / 20) / max(np.abs(samples).max(), 1e-9)
    return (samples * gain).astype(np.float32), lead, stretch


def non_speech(rng: np.random.Generator) -> np.ndarray:
    count = int(rng.uniform(2, 8) * ANALYSIS_RATE)
    if rng.random() < 0.6:
        samples = music(count, rng)
    else:
        samples = coloured_noise(count, rng.choice(["white", "pink", "brown", "babble"]), rng)
    if rng.random() < 0.3:
        samples = room(samples, rng.uniform(0.15, 0.8), rng)
    return (samples * 10 ** (rng.uniform(-30, -3) / 20) / max(np.abs(samples).max(), 1e-9)).astype(np.float32)
