"""lab/kit/whisper_weights.py: reading a CTranslate2 model.bin, Whisper's names as the extension's, and the
int8 weights the extension reads back."""

import struct

import numpy as np

from lab.kit.whisper_weights import encoder_weights, read_ctranslate2, stored_arrays
from turkish_lipsync.core.speech.acoustic.labels import CLASSES
from turkish_lipsync.core.speech.acoustic.whisper import whisper_hearing

CODES = {np.dtype(np.float32): 0, np.dtype(np.int8): 1, np.dtype(np.int32): 3, np.dtype(np.float16): 4}


def _model_bin(path, variables):
    """A model.bin as CTranslate2 writes one (version 6): little-endian counts, names, shapes and data."""

    def name(text):
        raw = text.encode() + b"\0"
        return struct.pack("<H", len(raw)) + raw

    out = (
        struct.pack("<I", 6) + name("WhisperSpec") + struct.pack("<I", 3) + struct.pack("<I", len(variables))
    )
    for key, value in variables.items():
        out += name(key) + struct.pack("<B", value.ndim) + struct.pack(f"<{value.ndim}I", *value.shape)
        out += struct.pack("<B", CODES[value.dtype]) + struct.pack("<I", value.nbytes) + value.tobytes()
    path.write_bytes(out)


def test_a_model_bin_is_read_and_renamed(tmp_path):
    rng = np.random.default_rng(1)
    variables = {
        "encoder/conv1/weight": rng.normal(size=(8, 4, 3)).astype(np.float16),
        "encoder/layer_0/self_attention/linear_0/weight": rng.normal(size=(24, 8)).astype(np.float16),
        "encoder/layer_0/ffn/layer_norm/gamma": np.ones(8, np.float16),
        "encoder/num_heads": np.array(2, np.int32),
        "decoder/embeddings/weight": rng.normal(size=(5, 8)).astype(np.float16),
    }
    _model_bin(tmp_path / "model.bin", variables)
    read = read_ctranslate2(tmp_path / "model.bin")
    assert set(read) == set(variables)
    for key, value in variables.items():
        np.testing.assert_array_equal(read[key], value)
    renamed, heads = encoder_weights(read)
    assert heads == 2
    assert set(renamed) == {"conv1.weight", "layer0.qkv.weight", "layer0.ffn_norm.gamma"}
    assert renamed["layer0.qkv.weight"].dtype == np.float32


def test_int8_weights_come_back_within_half_a_step_of_each_row():
    rng = np.random.default_rng(2)
    encoder = {
        "conv1.weight": rng.normal(size=(6, 4, 3)).astype(np.float32),
        "conv1.bias": rng.normal(size=6).astype(np.float32),
        "layer0.qkv.weight": rng.normal(size=(12, 4)).astype(np.float32) * np.arange(1, 13)[:, None],
        "layer0.qkv.bias": np.zeros(12, np.float32),
    }
    head = {
        "out.weight": rng.normal(size=(len(CLASSES), 5, 1)).astype(np.float32),
        "out.bias": np.zeros(len(CLASSES), np.float32),
        "mean": np.zeros(4, np.float32),
        "std": np.full(4, 2.0, np.float32),
    }
    arrays = stored_arrays(encoder, head)
    assert arrays["encoder/layer0.qkv.weight"].dtype == np.int8
    assert arrays["encoder/conv1.bias"].dtype == np.float32
    hearing = whisper_hearing(arrays, 2, np.full(len(CLASSES), 1 / len(CLASSES)), {})
    step = np.abs(encoder["layer0.qkv.weight"]).max(axis=1) / 127
    # Linear weights come back transposed (x @ weight), each row within half its own step.
    back = hearing.encoder["layer0.qkv.weight"].T
    assert np.all(np.abs(back - encoder["layer0.qkv.weight"]) <= step[:, None] / 2 + 1e-6)
    assert hearing.layers == 1 and hearing.heads == 2
    np.testing.assert_allclose(hearing.head["inverse_std"], 0.5)
