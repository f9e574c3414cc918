"""Decoders of a user's recording, asked in order until one reads it: one module each, in `DECODERS`.

The core's own: plain PCM WAV through the standard library, what libsndfile reads through the soundfile
wheel (float WAV, FLAC, OGG Vorbis and Opus, MP3, AIFF), and what FFmpeg reads through PyAV where it is
installed (AAC in M4A, MP4 and MOV; the sound track of MKV, WebM and other videos). Inside Blender the
Blender layer registers one more when it registers: Blender's own FFmpeg through `aud`
(blender/audio_decoding.py), so the extension's zips need no FFmpeg of their own.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import NoReturn

import numpy as np

from ...base.errors import AudioError
from .base import DECODERS, READ_BLOCK_FRAMES, AudioDecoder, DecodeFailed, MonoBuffer, mono
from .formats import RECORDING_KINDS, RECORDING_SUFFIXES, AudioFormat, sniff_format

REASON_CHARACTERS = 160  # of one decoder's own words in a message: enough to say why, short enough to read


@dataclass(frozen=True)
class DecodedAudio:
    samples: np.ndarray  # mono float32 in [-1, 1], the mean of the file's channels
    rate: int
    decoder: str  # the name of the decoder that read it
    audio_format: AudioFormat


@dataclass(frozen=True)
class _Attempt:
    decoder: AudioDecoder
    reason: str
    ran: bool  # False: the decoder could not run here (its library is missing)


def decode_recording(path: Path) -> DecodedAudio:
    """The recording's samples from the first decoder that reads it; one AudioError naming the file, its
    kind and what to do where none does."""
    try:
        audio_format = sniff_format(path)
    except OSError as error:
        raise AudioError(
            f"cannot open the recording {path} ({error.strerror or error}); check the file's permissions"
        ) from None
    attempts: list[_Attempt] = []
    for decoder in DECODERS.entries().values():
        if not decoder.claims(audio_format):
            continue
        absent = decoder.missing()
        if absent:
            attempts.append(_Attempt(decoder, absent, ran=False))
            continue
        try:
            samples, rate = decoder.decode(path, audio_format)
        except DecodeFailed as failed:
            attempts.append(_Attempt(decoder, str(failed)[:REASON_CHARACTERS], ran=True))
            continue
        return DecodedAudio(samples, rate, decoder.name, audio_format)
    _refuse(path, audio_format, attempts)


def _refuse(path: Path, audio_format: AudioFormat, attempts: list[_Attempt]) -> NoReturn:
    """One error for a file no decoder read: what it is, what each decoder said, what to do."""
    ran = [attempt for attempt in attempts if attempt.ran]
    said = "; ".join(f"{attempt.decoder.label}: {attempt.reason}" for attempt in ran or attempts)
    if any(attempt.decoder.ffmpeg for attempt in ran):
        raise AudioError(
            f"cannot read the recording {path} ({audio_format.label}): {said}; the file may be damaged or "
            "not a recording: check that it plays, then export it again as WAV or FLAC"
        )
    if not audio_format.libsndfile:
        raise AudioError(
            f"cannot read the recording {path} ({audio_format.label}): reading it needs FFmpeg, which "
            "Blender has and this Python lacks; open it in Blender, install PyAV here (`pip install av`), "
            "or export the recording as WAV or FLAC"
        )
    raise AudioError(
        f"cannot read the recording {path} ({audio_format.label}): {said}; export it again as WAV or FLAC, "
        "or install PyAV (`pip install av`) to read it through FFmpeg"
    )


__all__ = [
    "DECODERS",
    "READ_BLOCK_FRAMES",
    "RECORDING_KINDS",
    "RECORDING_SUFFIXES",
    "AudioDecoder",
    "AudioFormat",
    "DecodeFailed",
    "DecodedAudio",
    "MonoBuffer",
    "decode_recording",
    "mono",
]
