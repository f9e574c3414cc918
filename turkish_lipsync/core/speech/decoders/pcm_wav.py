"""Plain PCM WAV (8, 16, 24 and 32 bit) through the standard library: no dependency at all."""

from __future__ import annotations

import struct
import wave
from pathlib import Path

import numpy as np

from .base import DECODE_BLOCK_FRAMES, DECODERS, AudioDecoder, DecodeFailed
from .formats import AudioFormat


@DECODERS.register
class PcmWavDecoder(AudioDecoder):
    name = "pcm-wav"
    label = "Python's wave module"
    order = 10

    def claims(self, audio_format: AudioFormat) -> bool:
        return audio_format.name == "wav"

    def decode(self, path: Path, audio_format: AudioFormat) -> tuple[np.ndarray, int]:
        try:
            return _read_pcm_wav(path)
        except (wave.Error, EOFError, ValueError, RuntimeError, struct.error) as error:
            # Not plain PCM (float, extensible, ...) or damaged: soundfile may still read it.
            raise DecodeFailed(str(error) or type(error).__name__) from None


def _read_pcm_wav(path: Path) -> tuple[np.ndarray, int]:
    with wave.open(str(path), "rb") as handle:
        channels, width, rate = handle.getnchannels(), handle.getsampwidth(), handle.getframerate()
        if width not in (1, 2, 3, 4):
            raise ValueError(f"unsupported sample width {width}")
        mono = np.empty(handle.getnframes(), np.float32)
        filled = 0
        while filled < mono.size:
            data = handle.readframes(DECODE_BLOCK_FRAMES)
            frames = len(data) // (width * channels)
            if frames == 0:
                break
            into = mono[filled : filled + frames]
            if width == 2 and channels == 1:  # the usual take, converted in one pass straight into place
                pcm = np.frombuffer(data, "<i2", frames)
                np.multiply(pcm, np.float32(1 / 32768), out=into, dtype=np.float32)
            else:
                samples = _pcm_to_float(data[: frames * width * channels], width).reshape(frames, channels)
                into[:] = samples.mean(axis=1)
            filled += frames
    return mono[:filled], rate


def _pcm_to_float(data: bytes, width: int) -> np.ndarray:
    if width == 1:
        return (np.frombuffer(data, np.uint8).astype(np.float32) - 128) / 128
    if width == 2:
        return np.frombuffer(data, "<i2").astype(np.float32) / 32768
    if width == 3:
        raw = np.frombuffer(data, np.uint8).reshape(-1, 3).astype(np.int32)
        value = raw[:, 0] | (raw[:, 1] << 8) | (raw[:, 2] << 16)
        return (np.where(value >= 1 << 23, value - (1 << 24), value) / float(1 << 23)).astype(np.float32)
    return (np.frombuffer(data, "<i4") / float(1 << 31)).astype(np.float32)
