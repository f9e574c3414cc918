"""Whisper's weights as the extension stores them: a CTranslate2 model.bin read, its encoder's variables
under acoustic/whisper.py's names, and matrices as int8 with a scale per output row
(lab/train/whisper_head.py writes them; acoustic/whisper.py's whisper_hearing reads them back)."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

CTRANSLATE2_TYPES = {0: np.float32, 1: np.int8, 2: np.int16, 3: np.int32, 4: np.float16}


def read_ctranslate2(path: Path) -> dict[str, np.ndarray]:
    """A CTranslate2 model.bin's variables: a version, the spec's name and revision, a count, then each
    variable's name, rank, shape, type and bytes (little-endian)."""
    data = path.read_bytes()
    at = 0

    def take(layout: str) -> tuple:
        nonlocal at
        values = struct.unpack_from("<" + layout, data, at)
        at += struct.calcsize("<" + layout)
        return values

    def name() -> str:
        nonlocal at
        (length,) = take("H")
        text = data[at : at + length].rstrip(b"\0").decode()
        at += length
        return text

    (version,) = take("I")
    if version < 4:
        raise SystemExit(f"{path}: CTranslate2 model version {version}; this reader takes 4 and later")
    name()  # the spec's name
    take("I")  # its revision
    (count,) = take("I")
    variables = {}
    for _ in range(count):
        key = name()
        (rank,) = take("B")
        shape = take("I" * rank) if rank else ()
        (kind,) = take("B")
        (size,) = take("I")
        variables[key] = np.frombuffer(data[at : at + size], CTRANSLATE2_TYPES[kind]).reshape(shape)
        at += size
    return variables


def encoder_weights(variables: dict[str, np.ndarray]) -> tuple[dict[str, np.ndarray], int]:
    """The encoder's variables under acoustic/whisper.py's names (Linear: out x in, Conv1d: out x in x
    taps, float32), and its attention heads."""
    names = {
        "conv1/weight": "conv1.weight",
        "conv1/bias": "conv1.bias",
        "conv2/weight": "conv2.weight",
        "conv2/bias": "conv2.bias",
        "layer_norm/gamma": "norm.gamma",
        "layer_norm/beta": "norm.beta",
    }
    parts = {
        "self_attention/layer_norm": "attention_norm",
        "self_attention/linear_0": "qkv",
        "self_attention/linear_1": "out",
        "ffn/layer_norm": "ffn_norm",
        "ffn/linear_0": "ffn_in",
        "ffn/linear_1": "ffn_out",
    }
    out = {}
    for key, value in variables.items():
        if not key.startswith("encoder/"):
            continue
        rest = key.removeprefix("encoder/")
        if rest in names:
            out[names[rest]] = value.astype(np.float32)
        elif rest.startswith("layer_"):
            number, _, inner = rest.removeprefix("layer_").partition("/")
            part, _, leaf = inner.rpartition("/")
            out[f"layer{number}.{parts[part]}.{leaf}"] = value.astype(np.float32)
    heads = int(variables.get("encoder/num_heads", np.array(6)))
    return out, heads


def stored_arrays(encoder: dict[str, np.ndarray], head: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Both parts' weights as acoustic/whisper.py's whisper_hearing reads them: matrices as int8 with a
    float32 scale per output row (the row's largest magnitude over 127), vectors as float32."""
    arrays = {}
    for part, weights in (("encoder", encoder), ("head", head)):
        for name, value in weights.items():
            key = f"{part}/{name}"
            if value.ndim < 2:
                arrays[key] = value.astype(np.float32)
                continue
            scale = np.maximum(np.abs(value).reshape(len(value), -1).max(axis=1) / 127.0, 1e-12)
            scale = scale.astype(np.float32)
            arrays[key] = np.round(value / scale.reshape(-1, *(1,) * (value.ndim - 1))).astype(np.int8)
            arrays[key + ".scale"] = scale
    return arrays
