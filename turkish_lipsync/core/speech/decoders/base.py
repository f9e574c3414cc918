"""What a decoder is: it reads one kind of recording (or many) into mono float32 samples and their rate."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...base.registry import Registry
from .formats import AudioFormat

READ_BLOCK_FRAMES = 1 << 20  # frames resampled and searched for clipping at a time (speech/audio.py)
DECODE_BLOCK_FRAMES = 1 << 18  # frames decoded and mixed to mono at a time: a long take never held in stereo
GROWTH_MARGIN_SECONDS = 1.0  # room beyond a decoder's estimate of the length, before the buffer must grow
ESTIMATE_LIMIT_SECONDS = 4 * 3600  # an estimate longer than this is not believed (a broken header's length)


class DecodeFailed(Exception):
    """This decoder cannot read the file; the next one may. Its text says why, for the user's message."""


class AudioDecoder:
    """One way of reading recordings. `order` ranks decoders (the first that reads a file wins)."""

    name: str = ""
    label: str = ""  # in messages: "soundfile (libsndfile)"
    order: int = 0
    ffmpeg: bool = False  # reads what FFmpeg reads: AAC, the sound tracks of videos

    def claims(self, audio_format: AudioFormat) -> bool:
        """Whether to try this decoder on a file of this kind."""
        return True

    def missing(self) -> str:
        """Why this decoder cannot run here ("PyAV is not installed"), or "" where it can."""
        return ""

    def decode(self, path: Path, audio_format: AudioFormat) -> tuple[np.ndarray, int]:
        """Mono float32 samples (the channels' mean) and the sample rate; DecodeFailed where it cannot."""
        raise NotImplementedError


class MonoBuffer:
    """Mono blocks gathered in one float32 array, sized from the decoder's estimate of the length: a long
    take is held once, never as a list of blocks to join nor in all its channels."""

    def __init__(self, expected_frames: int, rate: int) -> None:
        self._margin = int(GROWTH_MARGIN_SECONDS * max(rate, 1))
        believed = int(expected_frames) if 0 < expected_frames <= ESTIMATE_LIMIT_SECONDS * rate else 0
        self._data = np.empty(believed + self._margin, np.float32)
        self.size = 0

    def append(self, block: np.ndarray) -> None:
        end = self.size + block.size
        if end > self._data.size:
            grown = np.empty(max(end + self._margin, self._data.size + self._data.size // 2), np.float32)
            grown[: self.size] = self._data[: self.size]
            self._data = grown
        self._data[self.size : end] = block
        self.size = end

    def samples(self, limit: int | None = None) -> np.ndarray:
        """What was gathered (at most limit frames); copied only where the estimate left much unused."""
        size = self.size if limit is None else max(0, min(self.size, limit))
        if size < self._data.size - 2 * self._margin:
            return self._data[:size].copy()
        return self._data[:size]


def mono(block: np.ndarray) -> np.ndarray:
    """The mean of a [frames, channels] block's channels, as float32."""
    if block.ndim == 1:
        return block.astype(np.float32, copy=False)
    if block.shape[1] == 1:
        return block[:, 0].astype(np.float32, copy=False)
    return block.mean(axis=1, dtype=np.float32)


DECODERS: Registry[AudioDecoder] = Registry("audio decoder", __package__, Path(__file__).parent)
