"""The recogniser's network, run with numpy alone: frames of features in, log posteriors of the classes out.

A convolution over FIRST_KERNEL frames, residual blocks of dilated convolutions (each block: a dilated
convolution, a ReLU, a 1x1 mix added back), then a 1x1 layer to the classes (labels.py) and a softmax.
It hears RECEPTIVE_RADIUS frames each side. The weights come from lab/train/recogniser.py (PyTorch,
outside the extension) and ship beside this file; a take is run in blocks with that radius of overlap,
so its length does not change the memory needed or the result.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np

from ...base.errors import DataError
from .features import FEATURE_COUNT
from .labels import CLASSES

FIRST_KERNEL = 5
KERNEL = 3
DILATIONS = (1, 2, 4, 8, 16)
RECEPTIVE_RADIUS = FIRST_KERNEL // 2 + sum(DILATIONS) * (KERNEL // 2)
WEIGHTS_FILE = Path(__file__).with_name("phone_network.npz")
# The same layout grown wider over the shipped weights and trained on many people's voices too
# (lab/train/many_voices.py): the recording aligner's second hearing of a take it fits loosely.
PEOPLE_WEIGHTS_FILE = Path(__file__).with_name("people_network.npz")
BLOCK_FRAMES = 8192  # frames run at a time (about 80 s of audio)


@dataclass(frozen=True, eq=False)
class PhoneNetwork:
    """The trained weights and what the decoder needs from training: class priors, transitions, durations."""

    layers: dict[str, np.ndarray]
    priors: np.ndarray  # each class's share of the training frames
    transitions: np.ndarray  # counts of class b's run following class a's
    shortest: np.ndarray  # frames: the decoder's minimum duration per class
    metadata: dict

    def log_posteriors(self, features: np.ndarray) -> np.ndarray:
        """(frames x classes) float32 natural-log posteriors of (frames x FEATURE_COUNT) features."""
        count = len(features)
        out = np.empty((count, len(CLASSES)), np.float32)
        radius = RECEPTIVE_RADIUS
        for begin in range(0, count, BLOCK_FRAMES):
            stop = min(begin + BLOCK_FRAMES, count)
            first, last = max(0, begin - radius), min(count, stop + radius)
            logits = self._logits(features[first:last])
            out[begin:stop] = logits[begin - first : begin - first + stop - begin]
        out -= out.max(axis=1, keepdims=True)
        out -= np.log(np.exp(out).sum(axis=1, keepdims=True))
        return out

    def _logits(self, x: np.ndarray) -> np.ndarray:
        layers = self.layers
        x = np.maximum(convolve(x, layers["first.weight"], layers["first.bias"], 1), 0)
        for number, dilation in enumerate(DILATIONS):
            name = f"blocks.{number}"
            hidden = np.maximum(
                convolve(x, layers[f"{name}.dilated.weight"], layers[f"{name}.dilated.bias"], dilation), 0
            )
            x = x + hidden @ layers[f"{name}.mix.weight"] + layers[f"{name}.mix.bias"]
        return np.maximum(x, 0) @ layers["last.weight"] + layers["last.bias"]


def convolve(x: np.ndarray, weight: np.ndarray, bias: np.ndarray, dilation: int) -> np.ndarray:
    """A 'same' 1-D convolution over frames (as PyTorch's Conv1d with zero padding): x is frames x in.

    weight is (taps * in) x out (as matrix_of_taps makes it): each tap's rows meet the frames shifted by
    that tap, one matrix product a tap added into the output (no shifted copy of x is made).
    """
    width = x.shape[1]
    taps = weight.shape[0] // width
    middle = taps // 2
    out = x @ weight[middle * width : (middle + 1) * width]
    out += bias
    for tap in range(taps):
        shift = (tap - middle) * dilation
        if shift == 0 or abs(shift) >= len(x):
            continue
        rows = weight[tap * width : (tap + 1) * width]
        if shift < 0:
            out[-shift:] += x[:shift] @ rows
        else:
            out[:-shift] += x[shift:] @ rows
    return out


def matrix_of_taps(weight: np.ndarray) -> np.ndarray:
    """A Conv1d weight (out x in x taps) as the contiguous (taps * in) x out matrix convolve multiplies."""
    out_channels, in_channels, taps = weight.shape
    return np.ascontiguousarray(weight.transpose(2, 1, 0).reshape(taps * in_channels, out_channels))


def stored_weights(path: Path, made_by: str) -> tuple[dict[str, np.ndarray], dict]:
    """The arrays of a shipped weights file and its metadata, or a DataError saying what to do."""
    if not path.is_file():
        raise DataError(
            f"the recogniser's weights {path} are missing; reinstall the extension, or make them with "
            f"{made_by}"
        )
    try:
        with np.load(path, allow_pickle=False) as data:
            stored = {key: data[key] for key in data.files}
        return stored, json.loads(str(stored.pop("metadata")))
    except (OSError, KeyError, ValueError) as error:
        raise DataError(
            f"the recogniser's weights {path} cannot be read ({error}); reinstall the extension"
        ) from None


@cache
def load_network(path: Path = WEIGHTS_FILE) -> PhoneNetwork:
    """The shipped network (read once per process), checked against the layout this module runs."""
    stored, metadata = stored_weights(path, "lab/train/recogniser.py")
    layers = {
        key.removeprefix("weight/"): value.astype(np.float32)
        for key, value in stored.items()
        if key.startswith("weight/")
    }
    try:
        network = PhoneNetwork(
            layers=layers,
            priors=stored["priors"].astype(np.float64),
            transitions=stored["transitions"].astype(np.float64),
            shortest=stored["shortest"].astype(np.int64),
            metadata=metadata,
        )
    except KeyError as error:
        raise DataError(f"the recogniser's weights {path} lack {error}; reinstall the extension") from None
    channels = len(layers.get("first.weight", ()))  # the width the weights were trained at
    expected = {
        "first.weight": (channels, FEATURE_COUNT, FIRST_KERNEL),
        "last.weight": (len(CLASSES), channels, 1),
        **{f"blocks.{n}.dilated.weight": (channels, channels, KERNEL) for n in range(len(DILATIONS))},
    }
    for name, shape in expected.items():
        if layers.get(name, np.zeros(0)).shape != shape:
            raise DataError(f"the recogniser's weights {path} do not fit its network ({name}); retrain it")
    if tuple(network.metadata.get("classes", ())) != CLASSES:
        raise DataError(f"the recogniser's weights {path} were trained on other classes; retrain it")
    for name, weight in layers.items():
        if weight.ndim == 3:
            layers[name] = matrix_of_taps(weight)
    return network
