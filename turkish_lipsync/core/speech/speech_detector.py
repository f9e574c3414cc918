"""Where people speak: Silero VAD's network (trained on people's speech in many languages), run with numpy.

Every other acoustic decision of the product was learnt from eSpeak NG's voice; this one was learnt from
people, so a person's short word in a quiet or hissing room is speech, and noise and music are not.
The network (Silero VAD 6, MIT licence, about 310,000 weights) reads 16 kHz audio in chunks of 512
samples (32 ms), each with the 64 samples before it as context: a short-time Fourier transform done as a
convolution (256-sample windows, 128 apart), four 1-D convolutions, one LSTM cell whose state runs from
chunk to chunk, and a 1x1 convolution with a sigmoid give each chunk a speech probability. Everything
before the LSTM depends on the audio alone, so it is computed for all the chunks of a take at once; only
the recurrence runs chunk by chunk, one matrix product each.

The weights are read from Silero's own 16 kHz ONNX file (its initializers; no ONNX runtime), the copy
the extension zip ships (`silero_vad_data/` at its root) or the installed `silero-vad` package's (a
development checkout, `pip install --no-deps silero-vad`; its code, which needs torch, is never
imported). Nothing is downloaded.
"""

from __future__ import annotations

import importlib.metadata
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np

from ..base.errors import DataError
from .features import ANALYSIS_RATE, HOP, WINDOW, frame_count
from .voice_activity import runs

CHUNK = 512  # samples (32 ms at 16 kHz) the network gives one probability
CONTEXT = 64  # samples of the chunk before that the network also sees
STFT_WINDOW = 256  # samples of the network's own short-time Fourier transform
STFT_STRIDE = 128
STATE = 128  # the LSTM's width
# Silero's 16 kHz model as ONNX (the same weights as its TorchScript and default ONNX models, v6.2); the
# wheel's silero_vad_16k.safetensors holds another checkpoint, whose probabilities differ from these by up to
# 0.54 (measured on people's syllables; upstream issue snakers4/silero-vad#768), so it is not used.
WEIGHTS_NAME = "silero_vad_16k_op15.onnx"
# At the extension's root, beside head_data/ (tools/release/build_extension.py puts it there).
BUNDLED_FOLDER = "silero_vad_data"
EXTENSION_ROOT = Path(__file__).resolve().parents[3]
BLOCK_CHUNKS = 2048  # chunks (about a minute) whose convolutions are computed at a time: bounds the memory
LAYER_SHAPES = {
    "model.stft.forward_basis_buffer": (2 * (STFT_WINDOW // 2 + 1), 1, STFT_WINDOW),
    "model.encoder.0.reparam_conv.weight": (128, STFT_WINDOW // 2 + 1, 3),
    "model.encoder.0.reparam_conv.bias": (128,),
    "model.encoder.1.reparam_conv.weight": (64, 128, 3),
    "model.encoder.1.reparam_conv.bias": (64,),
    "model.encoder.2.reparam_conv.weight": (64, 64, 3),
    "model.encoder.2.reparam_conv.bias": (64,),
    "model.encoder.3.reparam_conv.weight": (STATE, 64, 3),
    "model.encoder.3.reparam_conv.bias": (STATE,),
    "model.decoder.rnn.weight_ih": (4 * STATE, STATE),
    "model.decoder.rnn.weight_hh": (4 * STATE, STATE),
    "model.decoder.rnn.bias_ih": (4 * STATE,),
    "model.decoder.rnn.bias_hh": (4 * STATE,),
    "model.decoder.decoder.2.weight": (1, STATE, 1),
    "model.decoder.decoder.2.bias": (1,),
}
ONNX_FLOAT = 1  # TensorProto.DataType FLOAT


@dataclass(frozen=True)
class DetectorSettings:
    """Speech and silence, in the spirit of Silero's own get_speech_timestamps: a run starts at a chunk
    whose probability reaches speech_threshold and ends where it falls under silence_threshold, unless the
    speech threshold is reached again within shortest_silence. A run of certain_speech is speech wherever
    it lies; shorter runs (from shortest_word) only when the runs together hold word_energy_share of the
    take's sound above its floor (a short word alone in a quiet or hissing room, not a blip inside music
    or noise). How each was chosen: docs/developer/aligner-settings.md."""

    speech_threshold: float = 0.3
    """A run of speech starts at a chunk whose probability reaches this ..."""
    silence_threshold: float = 0.2
    """... and ends where it falls under this (a stop's closure stays speech) ..."""
    shortest_silence: float = 0.1
    """... for this many seconds (shorter dips are closures and breaths between words)."""
    certain_speech: float = 0.38
    """Seconds: a run this long is speech wherever it lies."""
    shortest_word: float = 0.06
    """Seconds: a shorter run is a click or a blip."""
    word_energy_share: float = 0.5
    """Shorter runs than certain_speech are speech when together they hold this share of the take's sound
    above its floor (its quietest tenth of chunks)."""
    speech_padding: float = 0.03
    """Seconds each side of a run: a word's onset lies in the chunk before it."""
    loud_level_db: float = -5.0
    """Each take's loud chunks (its 95th percentile of chunk energy) are brought to this level (dB full
    scale) before the network hears it ..."""
    most_gain_db: float = 60.0
    """... by this much at most (a take whose loud chunks lie lower holds nothing but its quantisation
    noise)."""


DEFAULT_DETECTOR = DetectorSettings()


class DetectorWeights:
    """Silero VAD's layers, rearranged once for the matrix products this module makes."""

    def __init__(self, layers: dict[str, np.ndarray]) -> None:
        # The Fourier layer's first row (frequency zero) is its window; load_detector checks the rest is
        # that window times the DFT, which the FFT then computes in a fraction of the time.
        self.window = layers["model.stft.forward_basis_buffer"][0, 0].copy()
        encoder = [
            (
                layers[f"model.encoder.{number}.reparam_conv.weight"],
                layers[f"model.encoder.{number}.reparam_conv.bias"],
            )
            for number in range(4)
        ]
        self.convolutions = [(_taps_matrix(weight), bias) for weight, bias in encoder[:3]]
        # The last convolution sees one step padded with zeros on both sides: only its middle tap meets it.
        self.last_convolution = (np.ascontiguousarray(encoder[3][0][:, :, 1].T), encoder[3][1])
        # The gates in the order input, forget, output, cell, the first three halved: one tanh then gives
        # all four, as sigmoid(z) = (1 + tanh(z / 2)) / 2.
        order = np.concatenate([np.arange(STATE) + gate * STATE for gate in (0, 1, 3, 2)])
        scale = np.concatenate((np.full(3 * STATE, 0.5), np.ones(STATE))).astype(np.float32)
        self.input_gates = np.ascontiguousarray(layers["model.decoder.rnn.weight_ih"][order].T * scale)
        # _recurrence keeps twice the hidden state: the weights that meet it are halved.
        self.recurrent_gates = np.ascontiguousarray(
            layers["model.decoder.rnn.weight_hh"][order].T * scale / 2
        )
        bias = layers["model.decoder.rnn.bias_ih"] + layers["model.decoder.rnn.bias_hh"]
        self.gate_bias = bias[order] * scale
        self.output = (
            layers["model.decoder.decoder.2.weight"][0, :, 0] / 2,
            float(layers["model.decoder.decoder.2.bias"][0]),
        )


def read_onnx_weights(path: Path) -> dict[str, np.ndarray]:
    """The float tensors of an ONNX model (its graph's initializers), read from the protobuf wire format.

    Only what a model's weights need: ModelProto field 7 (graph), GraphProto field 5 (initializer),
    TensorProto fields 1 (dims), 2 (data type), 8 (name), 9 (raw little-endian data), 4 (packed floats).
    """
    data = path.read_bytes()
    tensors = {}
    for graph in _fields(data, 7):
        for tensor in _fields(graph, 5):
            fields = _all_fields(tensor)
            dims: list[int] = []
            for value in fields.get(1, []):
                dims.extend(_packed_varints(value) if isinstance(value, bytes) else [value])
            if fields.get(2, [0])[0] != ONNX_FLOAT:
                continue
            name = fields[8][0].decode("utf-8")
            raw = fields[9][0] if 9 in fields else b"".join(fields.get(4, []))
            tensors[name] = np.frombuffer(raw, "<f4").reshape(dims).copy()
    return tensors


def _all_fields(message: bytes) -> dict[int, list]:
    """A protobuf message's fields by number: ints for varints, bytes for everything else."""
    fields: dict[int, list] = {}
    position = 0
    while position < len(message):
        key, position = _varint(message, position)
        number, wire_type = key >> 3, key & 7
        if wire_type == 0:
            value, position = _varint(message, position)
        elif wire_type == 2:
            length, position = _varint(message, position)
            value, position = message[position : position + length], position + length
        elif wire_type in (1, 5):
            size = 8 if wire_type == 1 else 4
            value, position = message[position : position + size], position + size
        else:
            raise ValueError(f"unknown protobuf wire type {wire_type}")
        if position > len(message):
            raise ValueError("a field runs past the end of its message")
        fields.setdefault(number, []).append(value)
    return fields


def _fields(message: bytes, number: int) -> list[bytes]:
    return [value for value in _all_fields(message).get(number, []) if isinstance(value, bytes)]


def _varint(data: bytes, position: int) -> tuple[int, int]:
    value = shift = 0
    while True:
        if position >= len(data):
            raise ValueError("a number runs past the end of the data")
        byte = data[position]
        position += 1
        value |= (byte & 0x7F) << shift
        shift += 7
        if byte < 0x80:
            return value, position


def _packed_varints(data: bytes) -> list[int]:
    values, position = [], 0
    while position < len(data):
        value, position = _varint(data, position)
        values.append(value)
    return values


def weights_path() -> Path:
    """Silero's weights: the extension's own copy, else the installed silero-vad package's."""
    bundled = EXTENSION_ROOT / BUNDLED_FOLDER / WEIGHTS_NAME
    if bundled.is_file():
        return bundled
    try:
        installed = Path(
            str(importlib.metadata.distribution("silero-vad").locate_file(f"silero_vad/data/{WEIGHTS_NAME}"))
        )
    except importlib.metadata.PackageNotFoundError:
        installed = None
    if installed is not None and installed.is_file():
        return installed
    raise DataError(
        f"speech detection needs Silero VAD's weights ({WEIGHTS_NAME}), found neither in {bundled.parent} "
        "nor in an installed silero-vad package; reinstall the extension, or in a development checkout run "
        "`pip install --no-deps silero-vad`"
    )


@cache
def load_detector(path: Path | None = None) -> DetectorWeights:
    """Silero VAD's weights (read once per process), checked against the network this module runs."""
    path = path or weights_path()
    try:
        layers = read_onnx_weights(path)
    except (OSError, ValueError, KeyError, TypeError) as error:
        raise DataError(
            f"Silero VAD's weights {path} cannot be read ({error}); reinstall the extension or silero-vad"
        ) from None
    for name, shape in LAYER_SHAPES.items():
        if name not in layers or layers[name].shape != shape:
            raise DataError(
                f"Silero VAD's weights {path} do not fit its 16 kHz network ({name}); install silero-vad 6"
            )
    if not _is_windowed_fourier(layers["model.stft.forward_basis_buffer"][:, 0, :]):
        raise DataError(f"Silero VAD's weights {path} have a Fourier layer this module does not compute")
    return DetectorWeights(layers)


def _is_windowed_fourier(basis: np.ndarray) -> bool:
    """True when the rows are the real and imaginary DFT of a window (its first row), as rfft computes."""
    window = basis[0].astype(np.float64)
    angles = 2 * np.pi * np.outer(np.arange(STFT_WINDOW // 2 + 1), np.arange(STFT_WINDOW)) / STFT_WINDOW
    expected = np.concatenate((window * np.cos(angles), -window * np.sin(angles)))
    return bool(np.abs(basis - expected).max() < 1e-5)


def chunk_probabilities(samples: np.ndarray, gain: float = 1.0) -> np.ndarray:
    """Silero's speech probability (0..1, float32) of each 512-sample chunk of 16 kHz samples in [-1, 1]
    (times `gain`, as float32).

    The last chunk is completed with zeros, the first has zeros as context: as Silero's own loop does. A
    take is run BLOCK_CHUNKS at a time, the LSTM's state carried over, so its length does not change the
    memory needed beyond its probabilities.
    """
    weights = load_detector()
    count = -(-samples.size // CHUNK)
    probabilities = np.empty(count, np.float32)
    doubled_hidden, cell = np.zeros(STATE, np.float32), np.zeros(STATE, np.float32)
    output_weight, output_bias = weights.output
    for begin in range(0, count, BLOCK_CHUNKS):
        stop = min(begin + BLOCK_CHUNKS, count)
        signal = np.zeros(CONTEXT + (stop - begin) * CHUNK, np.float32)
        first = begin * CHUNK - CONTEXT  # the block's context comes from the chunk before it
        piece = samples[max(0, first) : stop * CHUNK]
        signal[max(0, -first) : max(0, -first) + piece.size] = piece
        if gain != 1.0:
            signal *= np.float32(gain)
        gates = _chunk_features(signal, weights) @ weights.input_gates
        gates += weights.gate_bias
        states = _recurrence(gates, weights.recurrent_gates, doubled_hidden, cell)
        logits = np.maximum(states, 0) @ output_weight + output_bias
        probabilities[begin:stop] = 1 / (1 + np.exp(-logits))
    return probabilities


@dataclass(frozen=True, eq=False)
class SpeechDetection:
    """Where a take speaks, per 10 ms analysis frame (features.py's frames: hop i's window centred at
    i * HOP + WINDOW / 2 samples)."""

    # float32 0..1: Silero's probability for the 32 ms chunk holding the frame's centre
    probabilities: np.ndarray
    speech: np.ndarray  # bool: inside a run of speech (thresholds with hysteresis, shortest runs and gaps)

    @property
    def found(self) -> bool:
        """Whether the take holds any speech at all."""
        return bool(self.speech.any())

    def spans(self) -> np.ndarray:
        """(start, stop) frame pairs of the runs of speech."""
        return runs(self.speech)


def detect_speech(
    samples: np.ndarray, frames: int | None = None, settings: DetectorSettings = DEFAULT_DETECTOR
) -> SpeechDetection:
    """Speech probability and decision for each of `frames` analysis frames of 16 kHz samples in [-1, 1].

    `frames` defaults to features.frame_count(samples.size); frames past the samples are silence. The
    take is brought to loud_level_db first (the probabilities are those of the take at that level).
    """
    frames = frame_count(samples.size) if frames is None else frames
    probabilities, energies = levelled_probabilities(samples, settings)
    speech = speech_chunks(probabilities, energies, settings)
    if probabilities.size == 0:
        return SpeechDetection(np.zeros(frames, np.float32), np.zeros(frames, bool))
    centres = np.arange(frames) * HOP + WINDOW // 2
    chunk = np.minimum(centres // CHUNK, probabilities.size - 1)
    inside = centres < samples.size
    return SpeechDetection(np.where(inside, probabilities[chunk], 0), np.where(inside, speech[chunk], False))


def levelled_probabilities(
    samples: np.ndarray, settings: DetectorSettings = DEFAULT_DETECTOR
) -> tuple[np.ndarray, np.ndarray]:
    """Silero's chunk probabilities of the take brought to loud_level_db, and the chunks' energies."""
    energies = _chunk_energies(samples)
    if not energies.any():  # digital silence (or nothing): no level to bring anywhere
        return chunk_probabilities(samples), energies
    loud = 10 * np.log10(np.percentile(energies, 95) / CHUNK)
    return chunk_probabilities(
        samples, 10 ** (min(settings.most_gain_db, settings.loud_level_db - loud) / 20)
    ), energies


def speech_chunks(
    probabilities: np.ndarray, energies: np.ndarray, settings: DetectorSettings = DEFAULT_DETECTOR
) -> np.ndarray:
    """Which 32 ms chunks are speech, from their probabilities and sound energies (see the constants)."""
    seconds = CHUNK / ANALYSIS_RATE
    padding = int(round(settings.speech_padding / seconds))
    spans = [
        (start, stop)
        for start, stop in _hysteresis_runs(
            probabilities, int(round(settings.shortest_silence / seconds)), settings
        )
        if (stop - start) * seconds >= settings.shortest_word - 1e-9
    ]
    padded = np.zeros(probabilities.size, bool)
    for start, stop in spans:
        padded[max(0, start - padding) : stop + padding] = True
    above_floor = np.maximum(energies - np.percentile(energies, 10), 0) if energies.size else energies
    total = above_floor.sum()  # zero for a sound that never changes: nothing in it stands out as a word
    if total > 0 and above_floor[padded].sum() >= settings.word_energy_share * total:
        return padded
    speech = np.zeros(probabilities.size, bool)
    for start, stop in spans:
        if (stop - start) * seconds >= settings.certain_speech - 1e-9:
            speech[max(0, start - padding) : stop + padding] = True
    return speech


def _hysteresis_runs(
    probabilities: np.ndarray, shortest_silence: int, settings: DetectorSettings
) -> list[tuple[int, int]]:
    """(start, stop) chunk pairs: from a chunk reaching speech_threshold to the first of shortest_silence
    chunks in which it is not reached again, starting under silence_threshold (Silero's state machine)."""
    spans = []
    start = dip = None
    for index, probability in enumerate(probabilities.tolist()):
        if probability >= settings.speech_threshold:
            dip = None
            start = index if start is None else start
        elif start is not None and probability < settings.silence_threshold:
            dip = index if dip is None else dip
            if index - dip >= shortest_silence:
                spans.append((start, dip))
                start = dip = None
    if start is not None:
        spans.append((start, probabilities.size if dip is None else dip))
    return spans


def _chunk_energies(samples: np.ndarray) -> np.ndarray:
    """Sum of squares of each 512-sample chunk (the last completed with zeros), float64."""
    count = -(-samples.size // CHUNK)
    full = samples.size // CHUNK
    energies = np.zeros(count)
    energies[:full] = np.einsum(
        "ij,ij->i",
        samples[: full * CHUNK].reshape(full, CHUNK),
        samples[: full * CHUNK].reshape(full, CHUNK),
        dtype=np.float64,
    )
    energies[full:] = np.sum(samples[full * CHUNK :].astype(np.float64) ** 2)
    return energies


def _chunk_features(signal: np.ndarray, weights: DetectorWeights) -> np.ndarray:
    """The LSTM's input for each chunk of `signal` (the chunks' samples after CONTEXT samples before them).

    Each chunk's 576 samples are padded on the right by reflecting their last 64, which makes four
    Fourier windows: the first three lie in the signal itself, the fourth ends in the reflection.
    """
    count = (signal.size - CONTEXT) // CHUNK
    signal = np.ascontiguousarray(signal)
    step = signal.strides[0]
    framed = np.empty((count, 4, STFT_WINDOW), np.float32)
    framed[:, :3] = np.lib.stride_tricks.as_strided(
        signal, (count, 3, STFT_WINDOW), (CHUNK * step, STFT_STRIDE * step, step), writeable=False
    )
    last = CHUNK + CONTEXT
    reflected = np.concatenate(
        (np.arange(3 * STFT_STRIDE, last), np.arange(last - 2, last - 2 - CONTEXT, -1))
    )
    framed[:, 3] = signal[np.arange(count)[:, None] * CHUNK + reflected]
    framed *= weights.window
    x = np.abs(np.fft.rfft(framed, axis=2)).astype(np.float32)
    for stride, (matrix, bias) in zip((1, 2, 2), weights.convolutions, strict=True):
        x = _convolve_steps(x, matrix, bias, stride)
    matrix, bias = weights.last_convolution
    return np.maximum(x[:, 0] @ matrix + bias, 0)


def _convolve_steps(x: np.ndarray, matrix: np.ndarray, bias: np.ndarray, stride: int) -> np.ndarray:
    """A 3-tap convolution with one zero of padding each side over each chunk's steps, and a ReLU.

    x is chunks x steps x channels; matrix is (3 * channels) x out, as _taps_matrix makes it.
    """
    count, steps, channels = x.shape
    padded = np.zeros((count, steps + 2, channels), np.float32)
    padded[:, 1:-1] = x
    outputs = (steps - 1) // stride + 1
    taps = np.concatenate(
        [padded[:, tap : tap + stride * (outputs - 1) + 1 : stride] for tap in range(3)], axis=2
    )
    # One 2-D product: a 3-D one would be a product per chunk.
    result = taps.reshape(count * outputs, 3 * channels) @ matrix
    result += bias
    return np.maximum(result, 0, out=result).reshape(count, outputs, -1)


def _taps_matrix(weight: np.ndarray) -> np.ndarray:
    """A Conv1d weight (out x in x taps) as the (taps * in) x out matrix that meets the shifted copies."""
    out_channels, in_channels, taps = weight.shape
    return np.ascontiguousarray(weight.transpose(2, 1, 0).reshape(taps * in_channels, out_channels))


def _recurrence(
    gates: np.ndarray, recurrent: np.ndarray, doubled_hidden: np.ndarray, cell: np.ndarray
) -> np.ndarray:
    """Twice the LSTM's hidden state after each chunk, from the chunks' input gates (arranged and halved as
    DetectorWeights does, which also halves the recurrent weights to take the doubled state): one matrix
    product and nine in-place operations a chunk. Starts from, and leaves in, `doubled_hidden` and `cell`."""
    states = np.empty((len(gates) + 1, STATE), np.float32)
    states[0] = doubled_hidden
    squashed = np.empty(4 * STATE, np.float32)
    product = np.empty(STATE, np.float32)
    sigmoids, candidate = squashed[: 3 * STATE], squashed[3 * STATE :]
    input_gate, forget_gate, output_gate = (squashed[gate * STATE : (gate + 1) * STATE] for gate in range(3))
    for index, chunk_gates in enumerate(gates):
        np.dot(states[index], recurrent, out=squashed)
        squashed += chunk_gates
        np.tanh(squashed, out=squashed)
        sigmoids += 1  # twice the sigmoid of the input, forget and output gates
        np.multiply(input_gate, candidate, out=product)
        cell *= forget_gate
        cell += product
        cell *= 0.5
        hidden = states[index + 1]
        np.tanh(cell, out=hidden)
        hidden *= output_gate
    doubled_hidden[:] = states[-1]
    return states[1:]
