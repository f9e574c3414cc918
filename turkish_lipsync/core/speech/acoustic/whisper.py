"""A hearing that has met many people: Whisper tiny's encoder and a letter classifier over its frames.

Whisper (OpenAI, MIT licence) learnt its encoder from 680,000 hours of many thousands of speakers in
many languages; its tiny model's encoder (4 transformer layers 384 wide, 8.2 M weights) is run here with
numpy alone, on windows of 80 log mel bands as Whisper computes them (log_mel; windows). A small
classifier (HEAD_DILATIONS: three 'same' convolutions over its 20 ms frames, 256 wide) turns them into the
recogniser's classes (labels.py) at the recogniser's 10 ms frames. The encoder's weights are stored as
int8 with a scale per output row (dequantised once per process); both the encoder's and the
classifier's weights ship beside this file and are made by lab/train/whisper_head.py.

The audio-only recogniser averages this hearing's scaled likelihoods with the shipped network's
(recognition/recogniser.py): alone the network has heard few people, this hearing few synthetic voices.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np

from ...base.errors import DataError
from ..features import ANALYSIS_RATE, HOP, WINDOW, frame_count
from ..voice_activity import runs
from .labels import CLASSES
from .network import convolve, matrix_of_taps, stored_weights

WEIGHTS_FILE = Path(__file__).with_name("whisper_hearing.npz")
# The encoder hears a take of up to 30 s in one window, padded with silence to 30 s as Whisper was trained
# (the classifier learnt such windows: a short take padded less is heard otherwise). A longer take is heard
# in windows of at most 10 s, padded to 10 s: the same letters heard in three quarters of the time (the
# attention's cost grows with the square of the window; docs: audio alone, speed). Each of them ends at the
# quietest 100 ms of its last 2 s: in a pause where there is one.
WINDOW_SAMPLES = 30 * ANALYSIS_RATE
LONG_TAKE_WINDOW = 10 * ANALYSIS_RATE
CUT_SEARCH = 2 * ANALYSIS_RATE
CUT_SMOOTHING = 5  # encoder frames (100 ms)
# A long take is heard this far either side of the speech the detector finds in it (speech_spans); a
# break, or the silence between lines, is not heard by the encoder at all.
SPEECH_MARGIN = 3 * ANALYSIS_RATE // 10
MEL_BANDS = 80
FFT_SIZE = 400  # 25 ms
MEL_HOP = 160  # 10 ms
ENCODER_HOP = 2 * MEL_HOP  # the encoder's second convolution halves the frame rate: 20 ms
# Each of our frames takes the encoder frame nearest its centre less ENCODER_LEAD samples, as the classifier
# learnt (Whisper's encoder frame j is centred on sample 320 j: each frame hears the one about 15 ms before).
ENCODER_LEAD = 240
HEAD_KERNEL = 5
HEAD_DILATIONS = (1, 2, 4)
ATTENTION_ROWS = 500  # the encoder's queries scored at a time (their scores: 3 MB a head)
HEAD_BLOCK_FRAMES = 8192  # the classifier's frames at a time (about 80 s)


def log_mel(samples: np.ndarray, window: int = WINDOW_SAMPLES) -> np.ndarray:
    """Whisper's input for up to `window` 16 kHz samples: (window / 160 x 80) log10 mel power, padded with
    silence to the window, floored 8 below its maximum and scaled as (x + 4) / 4."""
    if len(samples) > window:
        raise ValueError(f"log_mel takes at most {window} samples, not {len(samples)}")
    padded = np.zeros(window + FFT_SIZE, np.float32)
    half = FFT_SIZE // 2
    padded[half : half + len(samples)] = samples
    if len(samples) > half:  # centred frames: the start reflected, as torch.stft(center=True) pads
        padded[:half] = samples[half:0:-1]
    frames = np.lib.stride_tricks.sliding_window_view(padded, FFT_SIZE)[::MEL_HOP][: window // MEL_HOP]
    power = np.abs(np.fft.rfft(frames * _hann(), axis=1)) ** 2
    mel = np.log10(np.maximum(power.astype(np.float32) @ _mel_filters(), 1e-10))
    mel = np.maximum(mel, mel.max() - 8.0)
    return (mel + 4.0) / 4.0


@cache
def _hann() -> np.ndarray:
    """The periodic Hann window Whisper's STFT uses."""
    return (0.5 - 0.5 * np.cos(2 * np.pi * np.arange(FFT_SIZE) / FFT_SIZE)).astype(np.float32)


def _slaney_mel(hz: np.ndarray) -> np.ndarray:
    """Slaney's mel scale (linear to 1 kHz, logarithmic above), as Whisper's filters are laid on."""
    linear = hz / (200.0 / 3)
    step = np.log(6.4) / 27.0
    return np.where(hz >= 1000.0, 15.0 + np.log(np.maximum(hz, 1e-10) / 1000.0) / step, linear)


def _slaney_hz(mel: np.ndarray) -> np.ndarray:
    step = np.log(6.4) / 27.0
    return np.where(mel >= 15.0, 1000.0 * np.exp(step * (mel - 15.0)), mel * 200.0 / 3)


@cache
def _mel_filters() -> np.ndarray:
    """(FFT bins x 80) triangular filters from 0 to 8 kHz, each scaled to unit area (Slaney's norm)."""
    bins = np.linspace(0, ANALYSIS_RATE / 2, FFT_SIZE // 2 + 1)
    edges = _slaney_hz(
        np.linspace(_slaney_mel(np.array(0.0)), _slaney_mel(np.array(ANALYSIS_RATE / 2)), MEL_BANDS + 2)
    )
    widths = np.diff(edges)
    rising = (bins[None, :] - edges[:-2, None]) / widths[:-1, None]
    falling = (edges[2:, None] - bins[None, :]) / widths[1:, None]
    filters = np.maximum(0, np.minimum(rising, falling)) * (2.0 / (edges[2:] - edges[:-2]))[:, None]
    return np.ascontiguousarray(filters.T.astype(np.float32))


@dataclass(frozen=True, eq=False)
class WhisperHearing:
    """Whisper tiny's encoder and the classifier over it; priors: the classifier's training frames'."""

    encoder: dict[str, np.ndarray]
    head: dict[str, np.ndarray]
    heads: int  # attention heads per layer
    layers: int
    priors: np.ndarray
    metadata: dict

    def log_posteriors(self, samples: np.ndarray, speech: np.ndarray | None = None) -> np.ndarray:
        """(frames x classes) float32 natural-log posteriors at the recogniser's frames (features.py's
        frame_count of them, frame i centred on sample i * HOP + WINDOW / 2) of 16 kHz float samples.
        speech: where a speech detector hears speech, per frame. A long take is then heard only around
        its speech (speech_spans: the spans joined end to end and heard as one take, which the encoder's
        windows fill); frames outside them are NaN, without the encoder's or the classifier's time."""
        if speech is None or len(samples) <= WINDOW_SAMPLES:
            return self._heard(samples)
        count = frame_count(len(samples))
        out = np.full((count, len(CLASSES)), np.nan, np.float32)
        spans = speech_spans(speech, len(samples))
        if not spans:
            return out
        heard = self._heard(np.concatenate([samples[begin:stop] for begin, stop in spans]))
        joined = 0  # where the span begins in the joined samples (on the encoder's grid, as it does here)
        for begin, stop in spans:
            shift = (begin - joined) // HOP  # our frame i is the joined take's frame i - shift
            # our frames centred within the span (that the joined take has)
            first = max(shift, -(-(begin - WINDOW // 2) // HOP))
            last = min(count, len(heard) + shift, -(-(stop - WINDOW // 2) // HOP))
            out[first:last] = heard[first - shift : last - shift]
            joined += stop - begin
        return out

    def _heard(self, samples: np.ndarray) -> np.ndarray:
        """log_posteriors of the whole of `samples`, its encoder windows' frames joined (windows)."""
        count = frame_count(len(samples))
        pieces = []  # each window's encoder frames (float16: a 30-minute take's are 70 MB)
        window = WINDOW_SAMPLES if len(samples) <= WINDOW_SAMPLES else LONG_TAKE_WINDOW
        for begin, stop in windows(samples):
            chunk = samples[begin:stop]
            heard = max(1, -(-len(chunk) // ENCODER_HOP))
            pieces.append(self.encode(log_mel(chunk, window))[:heard].astype(np.float16))
        encoded = np.concatenate(pieces)
        nearest = encoder_frames_of(np.arange(count) * HOP + WINDOW / 2, len(encoded))
        out = np.empty((count, len(CLASSES)), np.float32)
        radius = (HEAD_KERNEL // 2) * sum(HEAD_DILATIONS)
        for begin in range(0, count, HEAD_BLOCK_FRAMES):  # blocks overlapping by what the classifier hears
            stop = min(begin + HEAD_BLOCK_FRAMES, count)
            first, last = max(0, begin - radius), min(count, stop + radius)
            low, high = nearest[first], nearest[last - 1] + 1
            frames = (encoded[low:high].astype(np.float32) - self.head["mean"]) * self.head["inverse_std"]
            logits = self._classified(frames, nearest[first:last] - low)
            out[begin:stop] = logits[begin - first : stop - first]
        out -= out.max(axis=1, keepdims=True)
        out -= np.log(np.exp(out).sum(axis=1, keepdims=True))
        return out

    def encode(self, mel: np.ndarray) -> np.ndarray:
        """(window / 320 x 384) encoder frames, one every 20 ms, of a window's log mel (window / 160 x 80)."""
        w = self.encoder
        x = _gelu(convolve(mel, w["conv1.weight"], w["conv1.bias"], 1))
        x = _gelu(_halving_convolution(x, w["conv2.weight"], w["conv2.bias"]))
        x += _positions(len(x), x.shape[1])
        for n in range(self.layers):
            name = f"layer{n}."
            h = _normalised(x, w[name + "attention_norm.gamma"], w[name + "attention_norm.beta"])
            attended = _attended(h @ w[name + "qkv.weight"] + w[name + "qkv.bias"], self.heads)
            x += attended @ w[name + "out.weight"] + w[name + "out.bias"]
            h = _normalised(x, w[name + "ffn_norm.gamma"], w[name + "ffn_norm.beta"])
            x += _gelu(h @ w[name + "ffn_in.weight"] + w[name + "ffn_in.bias"]) @ w[name + "ffn_out.weight"]
            x += w[name + "ffn_out.bias"]
        return _normalised(x, w["norm.gamma"], w["norm.beta"])

    def _classified(self, encoded: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """The classifier's logits over the frames encoded[rows] (each encoder frame serves two of ours)."""
        head = self.head
        first = convolve_repeated(encoded, rows, head["conv0.weight"], head["conv0.bias"], HEAD_DILATIONS[0])
        h = np.maximum(first, 0)
        for n, dilation in enumerate(HEAD_DILATIONS[1:], 1):
            h = h + np.maximum(convolve(h, head[f"conv{n}.weight"], head[f"conv{n}.bias"], dilation), 0)
        return h @ head["out.weight"] + head["out.bias"]


def convolve_repeated(
    x: np.ndarray, rows: np.ndarray, weight: np.ndarray, bias: np.ndarray, dilation: int
) -> np.ndarray:
    """network.convolve over the frames x[rows] without making them: each tap's product is taken once per
    row of x and gathered (x's rows repeat: the encoder's 20 ms frames at our 10 ms, half the products)."""
    width = x.shape[1]
    taps = weight.shape[0] // width
    middle = taps // 2
    side_by_side = weight.reshape(taps, width, -1).transpose(1, 0, 2).reshape(width, -1)
    products = (x @ side_by_side).reshape(len(x), taps, -1)
    out = products[rows, middle] + bias
    for tap in range(taps):
        shift = (tap - middle) * dilation
        if shift == 0 or abs(shift) >= len(rows):
            continue
        if shift < 0:
            out[-shift:] += products[rows[:shift], tap]
        else:
            out[:-shift] += products[rows[shift:], tap]
    return out


def _attended(qkv: np.ndarray, heads: int) -> np.ndarray:
    """Softmax attention of (frames x 3 width) queries, keys and values, head by head, ATTENTION_ROWS
    queries at a time (their scores stay in the cache), each row's sum dividing its head-wide result
    rather than its scores."""
    frames, width = qkv.shape[0], qkv.shape[1] // 3
    size = width // heads
    scale = np.float32(size**-0.5)
    out = np.empty((frames, width), np.float32)
    for head in range(heads):
        columns = slice(head * size, (head + 1) * size)
        queries = qkv[:, columns] * scale
        keys = np.ascontiguousarray(qkv[:, width:][:, columns].T)
        values = np.ascontiguousarray(qkv[:, 2 * width :][:, columns])
        for begin in range(0, frames, ATTENTION_ROWS):
            rows = slice(begin, begin + ATTENTION_ROWS)
            scores = queries[rows] @ keys
            scores -= scores.max(axis=1, keepdims=True)
            np.exp(scores, out=scores)
            out[rows, columns] = (scores @ values) / scores.sum(axis=1, keepdims=True)
    return out


def windows(samples: np.ndarray) -> list[tuple[int, int]]:
    """(begin, stop) of the encoder's windows over a take, one after the other: the whole take if it fits
    WINDOW_SAMPLES, else pieces of at most LONG_TAKE_WINDOW, each but the last a whole number of encoder
    frames long (so that the windows' frames fall on the take's ENCODER_HOP grid) and ending in the middle
    of the quietest CUT_SMOOTHING frames of its last CUT_SEARCH samples (a pause where there is one: few
    sounds are cut in two)."""
    if len(samples) <= WINDOW_SAMPLES:
        return [(0, len(samples))]
    found, begin = [], 0
    while len(samples) - begin > LONG_TAKE_WINDOW:
        first = begin + LONG_TAKE_WINDOW - CUT_SEARCH
        frames = samples[first : begin + LONG_TAKE_WINDOW].reshape(-1, ENCODER_HOP).astype(np.float64)
        energy = np.convolve((frames**2).sum(axis=1), np.ones(CUT_SMOOTHING), "same")
        stop = first + ENCODER_HOP * (int(np.argmin(energy)) + 1)
        found.append((begin, stop))
        begin = stop
    found.append((begin, len(samples)))
    return found


def speech_spans(speech: np.ndarray, sample_count: int) -> list[tuple[int, int]]:
    """(begin, stop) samples around a long take's speech (speech: per frame of ours), SPEECH_MARGIN either
    side of each run of it, joined where they meet, each on the encoder's grid (the last may end with the
    take): what log_posteriors hears of the take."""
    found: list[tuple[int, int]] = []
    for first, stop in runs(np.asarray(speech, bool)):
        begin = max(0, first * HOP - SPEECH_MARGIN) // ENCODER_HOP * ENCODER_HOP
        end = min(sample_count, -(-((stop - 1) * HOP + WINDOW + SPEECH_MARGIN) // ENCODER_HOP) * ENCODER_HOP)
        if found and begin <= found[-1][1]:
            found[-1] = (found[-1][0], max(found[-1][1], end))
        elif begin < end:
            found.append((begin, end))
    return found


def encoder_frames_of(centres: np.ndarray, available: int) -> np.ndarray:
    """The encoder frame each of our frames takes (its centre in samples; ENCODER_LEAD), of `available`."""
    nearest = np.round((np.asarray(centres) - ENCODER_LEAD) / ENCODER_HOP).astype(np.int64)
    return np.clip(nearest, 0, available - 1)


def _halving_convolution(x: np.ndarray, weight: np.ndarray, bias: np.ndarray) -> np.ndarray:
    """A 3-tap convolution with stride 2 and zero padding 1 (weight: 3 * in x out, as matrix_of_taps
    makes it): output j hears input frames 2j - 1, 2j and 2j + 1."""
    width = x.shape[1]
    before, middle, after = (weight[tap * width : (tap + 1) * width] for tap in range(3))
    out = x[0::2] @ middle + bias
    out[1:] += x[1:-1:2] @ before
    out += x[1::2] @ after
    return out


def _gelu(x: np.ndarray) -> np.ndarray:
    """GELU in its tanh form (within 1e-3 of the exact one Whisper was trained with), in one new array:
    0.5 x (1 + tanh(z)) computed as x / (1 + exp(-2 z)), z = sqrt(2 / pi) (x + 0.044715 x^3), with an
    exponential rather than numpy's slower tanh (a large negative x gives exp = inf and GELU = -0)."""
    out = x * x
    out *= np.float32(-2 * 0.7978845608 * 0.044715)
    out += np.float32(-2 * 0.7978845608)
    out *= x
    with np.errstate(over="ignore"):
        np.exp(out, out=out)
    out += 1
    np.divide(x, out, out=out)
    return out


def _normalised(x: np.ndarray, gamma: np.ndarray, beta: np.ndarray) -> np.ndarray:
    mean = x.mean(axis=-1, keepdims=True)
    centred = x - mean
    variance = (centred**2).mean(axis=-1, keepdims=True)
    return centred / np.sqrt(variance + np.float32(1e-5)) * gamma + beta


@cache
def _positions(length: int, width: int) -> np.ndarray:
    """Whisper's sinusoidal positions of the encoder's frames."""
    increment = np.log(10000) / (width // 2 - 1)
    scaled = np.arange(length)[:, None] * np.exp(-increment * np.arange(width // 2))[None, :]
    return np.concatenate([np.sin(scaled), np.cos(scaled)], axis=1).astype(np.float32)


@cache
def load_whisper_hearing(path: Path = WEIGHTS_FILE) -> WhisperHearing:
    """The shipped encoder and classifier (read once per process), checked against this module's layout."""
    stored, metadata = stored_weights(path, "lab/train/whisper_head.py")
    try:
        hearing = whisper_hearing(stored, int(metadata["heads"]), stored.pop("priors"), metadata)
    except (KeyError, ValueError) as error:
        raise DataError(
            f"the recogniser's weights {path} do not fit its hearing ({error}); retrain them"
        ) from None
    if tuple(metadata.get("classes", ())) != CLASSES or hearing.head["out.bias"].shape != (len(CLASSES),):
        raise DataError(f"the recogniser's weights {path} were trained on other classes; retrain them")
    return hearing


def whisper_hearing(
    stored: dict[str, np.ndarray], heads: int, priors: np.ndarray, metadata: dict
) -> WhisperHearing:
    """The hearing of stored weights: "encoder/NAME" and "head/NAME" in PyTorch's layouts (Linear: out x
    in, Conv1d: out x in x taps), int8 ones with a "NAME.scale" per output row."""
    encoder, head = {}, {}
    for key, value in stored.items():
        part, _, name = key.partition("/")
        if name.endswith(".scale"):
            continue
        if value.dtype == np.int8:
            scale = stored[key + ".scale"].astype(np.float32)
            value = value.astype(np.float32) * scale.reshape(-1, *(1,) * (value.ndim - 1))
        value = value.astype(np.float32)
        if value.ndim == 3:  # Conv1d as the matrix convolve multiplies
            value = matrix_of_taps(value)
        elif value.ndim == 2:  # Linear as x @ weight
            value = np.ascontiguousarray(value.T)
        (encoder if part == "encoder" else head)[name] = value
    if "std" in head:
        head["inverse_std"] = (1.0 / head.pop("std")).astype(np.float32)
    layers = sum(1 for name in encoder if name.endswith(".qkv.bias"))
    return WhisperHearing(encoder, head, heads, layers, np.asarray(priors, np.float64), metadata)
