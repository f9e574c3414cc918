"""The voice's pitch (F0) and loudness over time, measured from the speech's own samples.

The pitch tracker is YIN (de Cheveigné and Kawahara 2002) written here in numpy rather than taken from a
library: the well-kept trackers that ship wheels (praat-parselmouth, pyworld) would add 10-30 MB to every
platform's extension zip and librosa's pYIN needs scipy and numba, which Blender cannot load from an
extension; YIN on 2 kHz audio is some sixty lines, runs at several thousand times real time and is checked
against Praat's own tracker in the tests (tests/core/test_motion_living_prosody.py). Head motion needs the
contour, not the last semitone: it is smoothed and its octave jumps removed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...speech.audio import decibels_under_loud

ANALYSIS_RATE = 2000  # Hz: the voice's first harmonics, which carry its periodicity
FRAME_RATE = 25.0  # analysis frames a second: syllables last 100-250 ms (2-6 frames), the head follows slower
WINDOW_SECONDS = 0.030  # integration window: two periods of the lowest voice
F0_RANGE = (70.0, 420.0)  # Hz: men's creak to children's and raised voices
YIN_THRESHOLD = 0.15  # cumulative mean normalised difference below this is a period
VOICING_THRESHOLD = 0.35  # frames whose best dip stays above this are unvoiced
SILENCE_DB = -45.0  # frames this far below the loudest 5 % are silence
_BLOCK = 2048  # frames analysed at once (bounds memory on long takes)
_DECIMATION_STRETCH = (
    1 << 16
)  # output samples decimated at once: their input (1.4 MB as int16) stays in cache


@dataclass(frozen=True, eq=False)
class Prosody:
    """Pitch and loudness at FRAME_RATE frames a second from the audio's start."""

    f0: np.ndarray  # Hz, NaN where unvoiced
    energy: np.ndarray  # dB relative to the loud end of the take (0 at its 95th percentile)
    rate: float = FRAME_RATE

    @property
    def times(self) -> np.ndarray:
        return np.arange(self.f0.size) / self.rate

    def semitones(self) -> np.ndarray:
        """F0 in semitones above the speaker's median (NaN where unvoiced)."""
        voiced = np.isfinite(self.f0)
        if not voiced.any():
            return np.full(self.f0.size, np.nan)
        return 12.0 * np.log2(self.f0 / np.median(self.f0[voiced]))

    def at(self, times: np.ndarray, values: np.ndarray) -> np.ndarray:
        """values (one per analysis frame) at the given times, linear between frames, NaN kept as NaN."""
        position = np.clip(np.asarray(times, np.float64) * self.rate, 0, max(values.size - 1, 0))
        low = np.floor(position).astype(int)
        high = np.minimum(low + 1, values.size - 1)
        share = position - low
        return values[low] * (1 - share) + values[high] * share

    def silent(self) -> np.ndarray:
        return self.energy < SILENCE_DB


def measure_prosody(samples: np.ndarray, sample_rate: int) -> Prosody:
    """F0 and energy of mono speech samples (int16 or float)."""
    audio = np.asarray(samples)
    factor = max(1, round(sample_rate / ANALYSIS_RATE))
    rate = sample_rate / factor
    audio = _decimated(audio, factor)
    hop = rate / FRAME_RATE
    count = max(1, int(np.ceil(audio.size / hop)))
    window = round(WINDOW_SECONDS * rate)
    longest = int(np.ceil(rate / F0_RANGE[0]))
    shortest = int(np.floor(rate / F0_RANGE[1]))
    span = window + longest + 1
    padded = np.concatenate([np.zeros(span // 2, np.float32), audio, np.zeros(span + int(hop), np.float32)])
    starts = np.round(np.arange(count) * hop).astype(np.int64)
    spans = np.lib.stride_tricks.sliding_window_view(padded, span)  # the frame starting at each sample
    power = np.empty(count)
    for first in range(0, count, _BLOCK):
        windows = spans[starts[first : first + _BLOCK], :window]
        power[first : first + _BLOCK] = np.einsum("ij,ij->i", windows, windows) / window
    energy = decibels_under_loud(power)
    f0 = np.full(count, np.nan)
    audible = np.flatnonzero(energy >= SILENCE_DB + 10.0)  # silence has no pitch: not analysed
    lags = np.arange(longest + 2)
    for first in range(0, audible.size, _BLOCK):
        rows = audible[first : first + _BLOCK]
        frames = spans[starts[rows]]
        # Energy of the window shifted by each lag: the first window's, then each lag's sample in and the
        # one before it out.
        squares = np.square(frames, dtype=np.float64)
        steps = np.empty((rows.size, lags.size))
        steps[:, 0] = squares[:, :window].sum(axis=1)
        steps[:, 1:] = squares[:, window : window + lags.size - 1] - squares[:, : lags.size - 1]
        shifted = np.cumsum(steps, axis=1)
        f0[rows] = _yin(frames, shifted, window, shortest, longest, rate)
    return Prosody(f0=_without_octave_jumps(f0), energy=energy, rate=FRAME_RATE)


def _decimated(audio: np.ndarray, factor: int) -> np.ndarray:
    """Float samples at 1/factor the rate, each the mean of factor samples (int16 scaled to -1..1).

    Averaging blocks decimates with a gentle low-pass that keeps the voice's first harmonics, all YIN needs,
    at a tenth of a band-limited resampler's cost. A stretch at a time is cast to float32 while it is in the
    cache, then its blocks summed by einsum, which (unlike a matrix product) wakes no BLAS threads that
    spin on the other cores: twice as fast as casting while summing, and no copy of the whole take.
    """
    count = audio.size // factor
    blocks = audio[: count * factor].reshape(count, factor)
    scale = np.float32(1.0 / (32768.0 * factor if audio.dtype.kind == "i" else float(factor)))
    decimated = np.empty(count, np.float32)
    for first in range(0, count, _DECIMATION_STRETCH):
        stretch = blocks[first : first + _DECIMATION_STRETCH].astype(np.float32)
        np.einsum("ij->i", stretch, out=decimated[first : first + _DECIMATION_STRETCH])
    decimated *= scale
    return decimated


def _yin(
    frames: np.ndarray, shifted: np.ndarray, window: int, shortest: int, longest: int, rate: float
) -> np.ndarray:
    """F0 (Hz, NaN unvoiced) of each row: YIN's difference function through FFT correlation.

    shifted[:, lag] is the energy of the row's window moved lag samples on.
    """
    # The window's product with itself shifted by each lag: a direct sum over a strided view of the frame,
    # several times faster than FFT correlation for these short frames.
    shifts = np.lib.stride_tricks.sliding_window_view(frames, window, axis=1)[:, : longest + 2]
    correlation = np.einsum("nj,nlj->nl", frames[:, :window], shifts)
    difference = shifted[:, :1] + shifted - 2.0 * correlation
    difference[:, 0] = 0.0
    cumulative = np.cumsum(difference[:, 1:], axis=1) / np.arange(1, longest + 2)
    normalised = np.ones_like(difference)
    normalised[:, 1:] = difference[:, 1:] / np.maximum(cumulative, 1e-12)
    band = normalised[:, shortest : longest + 1]
    below = band < YIN_THRESHOLD
    # The first dip under the threshold, at its local minimum; else the deepest dip of the band.
    first = np.where(below.any(axis=1), below.argmax(axis=1), band.argmin(axis=1))
    rows = np.arange(band.shape[0])
    for _ in range(3):
        step = np.minimum(first + 1, band.shape[1] - 1)
        further = band[rows, step] < band[rows, first]
        first = np.where(further, step, first)
    lag = first + shortest
    left = normalised[rows, np.maximum(lag - 1, 1)]
    centre = normalised[rows, lag]
    right = normalised[rows, np.minimum(lag + 1, longest + 1)]
    curvature = left - 2 * centre + right
    shift = np.where(
        np.abs(curvature) > 1e-12, 0.5 * (left - right) / np.where(curvature == 0, 1, curvature), 0
    )
    period = lag + np.clip(shift, -1, 1)
    f0 = rate / period
    f0[centre > VOICING_THRESHOLD] = np.nan
    return f0


def _without_octave_jumps(f0: np.ndarray) -> np.ndarray:
    """Frames an octave off the running median folded back, single voiced frames dropped."""
    f0 = f0.copy()
    voiced = np.isfinite(f0)
    if voiced.sum() < 5:
        return np.full(f0.size, np.nan)
    reference = _running_median(f0, 2 * round(0.15 * FRAME_RATE) + 1)  # 0.3 s around each frame
    ratio = f0 / reference
    f0[ratio > 1.7] /= 2.0
    f0[ratio < 0.6] *= 2.0
    isolated = voiced & ~np.roll(voiced, 1) & ~np.roll(voiced, -1)
    f0[isolated] = np.nan
    return f0


def _running_median(values: np.ndarray, width: int) -> np.ndarray:
    """The median of the finite values around each frame (the take's median where none is near)."""
    finite = np.isfinite(values)
    overall = float(np.median(values[finite]))
    padded = np.pad(values, width // 2, constant_values=np.nan)
    # Sorted, each window's NaNs come last: its median sits in the middle of its finite values.
    ordered = np.sort(np.lib.stride_tricks.sliding_window_view(padded, width), axis=1)[: values.size]
    count = np.isfinite(ordered).sum(axis=1)
    rows = np.arange(ordered.shape[0])
    low = ordered[rows, np.maximum(count - 1, 0) // 2]
    high = ordered[rows, np.minimum(count // 2, width - 1)]
    return np.where(count > 0, (low + high) / 2, overall)
