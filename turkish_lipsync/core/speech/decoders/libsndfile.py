"""What libsndfile reads, through the soundfile wheel (which carries the library for every platform):
float and extensible WAV, FLAC, OGG Vorbis and Opus, MP3 (with its encoder delay taken off), AIFF."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .base import DECODE_BLOCK_FRAMES, DECODERS, AudioDecoder, DecodeFailed, MonoBuffer, mono
from .formats import AudioFormat


@DECODERS.register
class LibsndfileDecoder(AudioDecoder):
    name = "soundfile"
    label = "soundfile (libsndfile)"
    order = 20

    def claims(self, audio_format: AudioFormat) -> bool:
        return audio_format.libsndfile

    def missing(self) -> str:
        try:
            import soundfile  # noqa: F401
        except (ImportError, OSError):  # OSError: the wheel's libsndfile would not load
            return "the Python package soundfile is not installed (`pip install soundfile`)"
        return ""

    def decode(self, path: Path, audio_format: AudioFormat) -> tuple[np.ndarray, int]:
        import soundfile

        try:
            with soundfile.SoundFile(str(path)) as handle:
                rate = int(handle.samplerate)
                gathered = MonoBuffer(handle.frames, rate)
                for block in handle.blocks(DECODE_BLOCK_FRAMES, dtype="float32", always_2d=True):
                    gathered.append(mono(block))
        except Exception as error:  # soundfile raises its own error types, varying by version
            raise DecodeFailed(str(error).removeprefix(f"Error opening {str(path)!r}: ")) from None
        return gathered.samples(), rate
