"""A user's own recording of the text: read it, align the synthetic rendition to it, warp the events.

The recording is read (WAV through the stdlib, FLAC/OGG and float WAV through soundfile), mixed to
mono and resampled to the synthesis rate. Both signals are trimmed to their speech, described by
MFCCs (numpy only) and aligned by dynamic time warping. The DTW is multi-resolution (solve at half the
frame rate, then refine in a band around that path, as FastDTW does) so its memory grows with the
length of the audio, not with its square: 10 minutes take about 20 MB instead of some 30 GB.
No DTW library is used: the ones that install cleanly either hold the full cost matrix (dtw-python)
or bring numba and librosa into a Blender extension; the recurrence below is 40 lines of numpy.
"""

from __future__ import annotations

import struct
import wave
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..errors import AudioError
from .base import Synthesis

MAX_LENGTH_RATIO = 3.0  # recordings this many times longer or shorter than the synthetic speech are refused
FRAME_SECONDS = 0.025
HOP_SECONDS = 0.010
MEL_BANDS = 40
MEL_TOP_HERTZ = 7600.0
CEPSTRA = 13  # MFCC 1..12 are used (c0, the loudness, differs between voices)
SILENCE_DB = 35.0  # frames this far below the loud frames count as silence at the ends
DTW_RADIUS = 12  # frames of slack around the coarse path at each resolution
DTW_FULL_CELLS = 250_000  # below this many cells the DTW is solved without a band
_RESAMPLE_HALF_TAPS = 16
_FEATURE_BLOCK = 4096  # frames per block when computing features (bounds the spectrogram's memory)


@dataclass(frozen=True, eq=False)
class TimeWarp:
    """Synthetic time (seconds) to recording time: piecewise linear through matched frame times."""

    synthetic: np.ndarray  # increasing knot times in the synthetic speech
    recorded: np.ndarray  # non-decreasing knot times in the recording
    recording_duration: float

    def __call__(self, times: np.ndarray | float) -> np.ndarray:
        times = np.asarray(times, dtype=np.float64)
        warped = np.interp(times, self.synthetic, self.recorded)
        # Outside the speech the two signals run at the same speed (silence before and after).
        before = times < self.synthetic[0]
        after = times > self.synthetic[-1]
        warped = np.where(before, self.recorded[0] - (self.synthetic[0] - times), warped)
        warped = np.where(after, self.recorded[-1] + (times - self.synthetic[-1]), warped)
        return np.clip(warped, 0.0, self.recording_duration)


def read_audio(path: str | Path) -> tuple[np.ndarray, int]:
    """Mono float32 samples in [-1, 1] and the sample rate of a WAV, FLAC or OGG file."""
    path = Path(path)
    if not path.is_file():
        raise AudioError(f"recording {path} does not exist; give the path of a WAV, FLAC or OGG file")
    samples, rate = None, 0
    if path.suffix.lower() == ".wav":
        try:
            samples, rate = _read_pcm_wav(path)
        except (wave.Error, EOFError, ValueError, RuntimeError, struct.error):
            samples = None  # not plain PCM (float, extensible, ...) or damaged: soundfile may still read it
        except OSError as error:
            raise AudioError(
                f"cannot open the recording {path} ({error}); check the file's permissions"
            ) from None
    if samples is None:
        samples, rate = _read_with_soundfile(path)
    if samples.shape[0] == 0 or rate <= 0:
        raise AudioError(f"recording {path} holds no audio; record the text again")
    mono = samples.mean(axis=1, dtype=np.float32) if samples.ndim == 2 else samples.astype(np.float32)
    if not np.isfinite(mono).all():
        raise AudioError(
            f"recording {path} contains invalid samples (NaN or infinite); export it again as WAV"
        )
    return mono, rate


def _read_pcm_wav(path: Path) -> tuple[np.ndarray, int]:
    with wave.open(str(path), "rb") as handle:
        channels, width, rate = handle.getnchannels(), handle.getsampwidth(), handle.getframerate()
        data = handle.readframes(handle.getnframes())
    if width == 1:
        samples = (np.frombuffer(data, np.uint8).astype(np.float32) - 128) / 128
    elif width == 2:
        samples = np.frombuffer(data, "<i2").astype(np.float32) / 32768
    elif width == 3:
        raw = np.frombuffer(data, np.uint8).reshape(-1, 3).astype(np.int32)
        value = raw[:, 0] | (raw[:, 1] << 8) | (raw[:, 2] << 16)
        samples = (np.where(value >= 1 << 23, value - (1 << 24), value) / float(1 << 23)).astype(np.float32)
    elif width == 4:
        samples = (np.frombuffer(data, "<i4") / float(1 << 31)).astype(np.float32)
    else:
        raise ValueError(f"unsupported sample width {width}")
    usable = samples.size - samples.size % channels
    return samples[:usable].reshape(-1, channels), rate


def _read_with_soundfile(path: Path) -> tuple[np.ndarray, int]:
    try:
        import soundfile
    except ImportError:
        raise AudioError(
            f"cannot read {path}: FLAC, OGG and float WAV need the Python package soundfile "
            "(`pip install soundfile`); or export the recording as 16-bit PCM WAV"
        ) from None
    try:
        samples, rate = soundfile.read(str(path), dtype="float32", always_2d=True)
    except Exception as error:  # soundfile raises its own error types, varying by version
        raise AudioError(
            f"cannot read the recording {path} ({error}); export it as a WAV, FLAC or OGG file"
        ) from None
    return samples, int(rate)


def resample(samples: np.ndarray, source_rate: int, target_rate: int) -> np.ndarray:
    """Band-limited resampling (Hann-windowed sinc), in blocks so memory stays proportional to the audio."""
    if source_rate == target_rate or samples.size == 0:
        return samples.astype(np.float32, copy=False)
    ratio = target_rate / source_rate
    cutoff = 0.95 * min(1.0, ratio)  # of the source's Nyquist frequency
    half = int(np.ceil(_RESAMPLE_HALF_TAPS / cutoff))
    offsets = np.arange(-half + 1, half + 1)
    count = int(round(samples.size * ratio))
    output = np.empty(count, np.float32)
    padded = np.concatenate(
        (np.zeros(half, np.float32), samples.astype(np.float32), np.zeros(half + 1, np.float32))
    )
    block = max(1, 2**20 // offsets.size)
    for begin in range(0, count, block):
        positions = np.arange(begin, min(begin + block, count)) / ratio  # in source samples
        base = np.floor(positions).astype(np.int64)
        taps = base[:, None] + offsets[None, :]
        distance = positions[:, None] - taps
        weights = cutoff * np.sinc(cutoff * distance) * (0.5 + 0.5 * np.cos(np.pi * distance / half))
        output[begin : begin + positions.size] = (padded[taps + half] * weights).sum(axis=1)
    return output


def speech_range(samples: np.ndarray, rate: int) -> tuple[int, int]:
    """First and last sample of the speech: the ends quieter than SILENCE_DB below the loud frames are cut."""
    frame = max(1, int(rate * 0.02))
    count = samples.size // frame
    if count == 0:
        return 0, samples.size
    blocks = samples[: count * frame].reshape(count, frame)
    energy = np.sqrt(np.einsum("ij,ij->i", blocks, blocks) / frame)
    loud = np.percentile(energy, 95)
    voiced = np.flatnonzero(energy > max(loud * 10 ** (-SILENCE_DB / 20), 1e-4))
    if voiced.size == 0:
        return 0, 0
    margin = frame  # keep a frame of the silence so onsets are not cut
    return max(0, voiced[0] * frame - margin), min(samples.size, (voiced[-1] + 1) * frame + margin)


def speech_features(
    samples: np.ndarray, rate: int, top_hertz: float = MEL_TOP_HERTZ
) -> tuple[np.ndarray, np.ndarray]:
    """MFCC 1..12 per 10 ms frame (each normalised over the signal) and whether each frame is voiced.

    top_hertz: highest frequency described; both signals of an alignment must use the same one.
    """
    window, hop = frame_sizes(rate)
    size = 1 << int(np.ceil(np.log2(window)))
    filters = _mel_filters(rate, size, top_hertz)
    transform = _dct_matrix(MEL_BANDS, CEPSTRA)[1:]
    taper = np.hanning(window)
    count = max(1, 1 + (samples.size - 1) // hop)
    features = np.empty((count, CEPSTRA - 1))
    energy = np.empty(count)
    for begin in range(0, count, _FEATURE_BLOCK):
        frames = np.arange(begin, min(begin + _FEATURE_BLOCK, count))
        # Only this block's samples are copied (zero-padded past the end), not the whole signal.
        piece = samples[begin * hop : frames[-1] * hop + window].astype(np.float64)
        piece = np.pad(piece, (0, (frames.size - 1) * hop + window - piece.size))
        rows = piece[(frames - begin)[:, None] * hop + np.arange(window)[None, :]] * taper
        power = np.abs(np.fft.rfft(rows, size, axis=1)) ** 2
        features[frames] = np.log(power @ filters.T + 1e-10) @ transform.T
        energy[frames] = np.sqrt(np.mean(rows**2, axis=1))
    features -= features.mean(axis=0)
    features /= features.std(axis=0) + 1e-8
    voiced = energy > max(np.percentile(energy, 95) * 10 ** (-SILENCE_DB / 20), 1e-4)
    return features, voiced


def frame_sizes(rate: int) -> tuple[int, int]:
    """Samples per analysis window and per hop (the hop is whole samples, so its seconds are hop / rate)."""
    return int(round(FRAME_SECONDS * rate)), int(round(HOP_SECONDS * rate))


def _mel_filters(rate: int, size: int, top_hertz: float) -> np.ndarray:
    def to_mel(hertz):
        return 2595 * np.log10(1 + np.asarray(hertz) / 700)

    def to_hertz(mel):
        return 700 * (10 ** (np.asarray(mel) / 2595) - 1)

    edges = to_hertz(np.linspace(to_mel(60.0), to_mel(min(top_hertz, 0.45 * rate)), MEL_BANDS + 2))
    bins = np.fft.rfftfreq(size, 1 / rate)
    lower, centre, upper = edges[:-2, None], edges[1:-1, None], edges[2:, None]
    rising = (bins[None, :] - lower) / (centre - lower)
    falling = (upper - bins[None, :]) / (upper - centre)
    return np.clip(np.minimum(rising, falling), 0, None)


def _dct_matrix(inputs: int, outputs: int) -> np.ndarray:
    n = np.arange(inputs)
    return np.cos(np.pi / inputs * (n[None, :] + 0.5) * np.arange(outputs)[:, None])


def dtw_path(x: np.ndarray, y: np.ndarray, radius: int = DTW_RADIUS) -> tuple[np.ndarray, np.ndarray]:
    """The cheapest monotone path from (0, 0) to (len(x)-1, len(y)-1) through the frame distances."""
    n, m = len(x), len(y)
    if n * m <= DTW_FULL_CELLS or min(n, m) <= 4 * radius:
        return _band_dtw(x, y, np.zeros(n, np.int64), np.full(n, m, np.int64))
    coarse_i, coarse_j = dtw_path(_halve(x), _halve(y), radius)
    low = np.full(n, m, np.int64)
    high = np.zeros(n, np.int64)
    for row_offset in (0, 1):
        rows = np.minimum(2 * coarse_i + row_offset, n - 1)
        np.minimum.at(low, rows, 2 * coarse_j)
        np.maximum.at(high, rows, np.minimum(2 * coarse_j + 2, m))
    low = np.minimum.accumulate(low[::-1])[::-1]  # rows the projection missed borrow from their neighbours
    high = np.maximum.accumulate(high)
    grown_low, grown_high = low.copy(), high.copy()
    for shift in range(1, radius + 1):
        grown_low[shift:] = np.minimum(grown_low[shift:], low[:-shift])
        grown_high[:-shift] = np.maximum(grown_high[:-shift], high[shift:])
    grown_low = np.clip(grown_low - radius, 0, m)
    grown_high = np.clip(grown_high + radius, 0, m)
    grown_low[0], grown_high[-1] = 0, m
    return _band_dtw(x, y, grown_low, grown_high)


def _halve(features: np.ndarray) -> np.ndarray:
    if len(features) % 2:
        features = np.concatenate((features, features[-1:]))
    return 0.5 * (features[0::2] + features[1::2])


def _band_dtw(
    x: np.ndarray, y: np.ndarray, low: np.ndarray, high: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """DTW (symmetric steps, diagonal weighted twice) with row i restricted to columns low[i]:high[i].

    Each row is solved at once: vertical and diagonal steps come from the row before, and the horizontal
    steps are a running minimum of (cost so far - cumulative distance), so no Python loop runs over cells.
    """
    moves: list[np.ndarray] = []  # per row: 0 diagonal, 1 from above, 2 from the left
    previous = np.empty(0)
    previous_low = 0
    for i in range(len(x)):
        begin, end = int(low[i]), int(high[i])
        distance = np.sqrt(((y[begin:end] - x[i]) ** 2).sum(axis=1))
        if i == 0:
            cost = np.cumsum(distance)
            move = np.full(end - begin, 2, np.int8)
        else:
            above = np.full(end - begin, np.inf)
            diagonal = np.full(end - begin, np.inf)
            _copy_overlap(above, begin, previous, previous_low)
            _copy_overlap(diagonal, begin - 1, previous, previous_low)
            from_above = above + distance
            from_diagonal = diagonal + 2 * distance
            arrive = np.minimum(from_diagonal, from_above)
            move = np.where(from_diagonal <= from_above, 0, 1).astype(np.int8)
            cumulative = np.cumsum(distance)
            relative = arrive - cumulative
            best = np.minimum.accumulate(relative)
            cost = best + cumulative
            move[best < relative] = 2
        moves.append(move)
        previous, previous_low = cost, begin
    path_i, path_j = [], []
    i, j = len(x) - 1, len(y) - 1
    while True:
        path_i.append(i)
        path_j.append(j)
        if i == 0 and j == 0:
            break
        move = moves[i][j - int(low[i])]
        if move == 0:
            i, j = i - 1, j - 1
        elif move == 1:
            i -= 1
        else:
            j -= 1
    return np.array(path_i[::-1]), np.array(path_j[::-1])


def _copy_overlap(target: np.ndarray, target_low: int, source: np.ndarray, source_low: int) -> None:
    """target[k] = source[k + target_low - source_low] where both exist."""
    begin = max(target_low, source_low)
    end = min(target_low + target.size, source_low + source.size)
    if end > begin:
        target[begin - target_low : end - target_low] = source[begin - source_low : end - source_low]


def align_recording(synthesis: Synthesis, path: str | Path) -> tuple[TimeWarp, Synthesis]:
    """The warp from synthetic to recorded time, and the recording as a Synthesis with warped events."""
    path = Path(path)
    recorded, recorded_rate = read_audio(path)
    recorded = resample(recorded, recorded_rate, synthesis.sample_rate)
    rate = synthesis.sample_rate
    # A telephone-quality recording has nothing above its Nyquist frequency: describe both up to there.
    top_hertz = min(MEL_TOP_HERTZ, 0.45 * recorded_rate)
    synthetic = synthesis.samples.astype(np.float32) / 32768
    recorded_begin, recorded_end = speech_range(recorded, rate)
    synthetic_begin, synthetic_end = speech_range(synthetic, rate)
    if recorded_end - recorded_begin < int(0.1 * rate):
        raise AudioError(f"recording {path} is silent (no speech found); record the text again")
    if synthetic_end <= synthetic_begin:
        raise AudioError("the synthetic speech is silent, so there is nothing to align the recording to")
    ratio = (recorded_end - recorded_begin) / (synthetic_end - synthetic_begin)
    if not 1 / MAX_LENGTH_RATIO <= ratio <= MAX_LENGTH_RATIO:
        raise AudioError(
            f"recording {path} has {(recorded_end - recorded_begin) / rate:.1f} s of speech but the text "
            f"takes about {(synthetic_end - synthetic_begin) / rate:.1f} s to say (more than "
            f"{MAX_LENGTH_RATIO:g} times apart); check that the recording reads exactly this text"
        )
    x, x_voiced = speech_features(synthetic[synthetic_begin:synthetic_end], rate, top_hertz)
    y, y_voiced = speech_features(recorded[recorded_begin:recorded_end], rate, top_hertz)
    path_x, path_y = dtw_path(x, y)
    # Silence matches silence at no cost, so the path through a pause is arbitrary: only matches of voiced
    # frames become knots of the warp, each synthetic frame taking the mean recording frame matched to it,
    # and pauses are crossed linearly.
    both = x_voiced[path_x] & y_voiced[path_y]
    if both.sum() < 2:
        both[:] = True
    weights = np.bincount(path_x[both], minlength=len(x))
    knots = np.flatnonzero(weights)
    matched = np.bincount(path_x[both], weights=path_y[both], minlength=len(x))[knots] / weights[knots]
    knots = np.concatenate(([0], knots, [len(x) - 1]))
    matched = np.maximum.accumulate(np.concatenate(([0.0], matched, [len(y) - 1.0])))
    window, hop = frame_sizes(rate)
    warp = TimeWarp(
        synthetic=(synthetic_begin + window / 2 + hop * knots) / rate,
        recorded=(recorded_begin + window / 2 + hop * matched) / rate,
        recording_duration=recorded.size / rate,
    )
    samples = np.clip(np.round(recorded * 32767), -32768, 32767).astype(np.int16)
    return warp, warp_synthesis(synthesis, warp, samples)


def warp_synthesis(synthesis: Synthesis, warp: TimeWarp, samples: np.ndarray) -> Synthesis:
    """The synthesis's events moved onto the recording's time, holding the recording's samples."""
    phones = synthesis.phone_events
    starts = warp(np.array([event.start for event in phones]))
    ends = warp(np.array([event.end for event in phones]))
    words = synthesis.word_events
    word_starts = warp(np.array([event.start for event in words]))
    return Synthesis(
        samples=samples,
        sample_rate=synthesis.sample_rate,
        phone_events=tuple(
            replace(event, start=float(start), end=float(end))
            for event, start, end in zip(phones, starts, ends, strict=True)
        ),
        word_events=tuple(
            replace(event, start=float(start)) for event, start in zip(words, word_starts, strict=True)
        ),
        engine="recording",
    )
