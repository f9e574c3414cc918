"""Writing speech audio as a 16-bit PCM WAV (stdlib wave: no dependency, plays everywhere).

A file is written beside its final name and renamed when complete, so a failed write leaves nothing half
written and never a wave writer to be closed at exit. Speech WAVs of Generate are named after their own
content: two scenes saved in one folder never share one WAV with different sound, and a WAV we did not write
is never overwritten.
"""

from __future__ import annotations

import hashlib
import os
import wave
from pathlib import Path

import numpy as np

from ..base.errors import AudioError
from .base import Synthesis

SOFTWARE_TAG = b"Turkish Lip Sync"  # the WAV's INFO/ISFT entry: how a WAV we wrote is told from others


def _pcm(synthesis: Synthesis) -> memoryview:
    """The samples as little-endian 16-bit bytes, without a copy where they are int16 already (ten minutes of
    speech are 26 MB)."""
    return memoryview(np.ascontiguousarray(synthesis.samples, dtype="<i2")).cast("B")


def write_wav(path: str | Path, synthesis: Synthesis) -> Path:
    """Write the synthesis's samples as mono 16-bit PCM; returns the path written."""
    path = Path(path)
    partial = path.with_name(f".{path.name}.part")
    try:
        with open(partial, "wb") as raw, wave.open(raw, "wb") as handle:
            handle.setnchannels(1)
            handle.setsampwidth(2)
            handle.setframerate(int(synthesis.sample_rate))
            handle.writeframes(_pcm(synthesis))
        _append_software_tag(partial)
        os.replace(partial, path)
    except OSError as error:
        try:
            partial.unlink(missing_ok=True)
        except OSError:
            pass
        reason = error.strerror or str(error)
        raise AudioError(
            f"cannot write the speech audio to {path}: {reason}; choose a writable file path"
        ) from None
    return path


def _append_software_tag(path: Path) -> None:
    """Add a LIST/INFO chunk naming us as the software (players skip it) and fix the RIFF size."""
    value = SOFTWARE_TAG + b"\0"
    value += b"\0" * (len(value) % 2)
    info = b"INFO" + b"ISFT" + len(value).to_bytes(4, "little") + value
    with open(path, "r+b") as handle:
        handle.seek(0, os.SEEK_END)
        if handle.tell() % 2:
            handle.write(b"\0")
        handle.write(b"LIST" + len(info).to_bytes(4, "little") + info)
        size = handle.tell() - 8
        handle.seek(4)
        handle.write(size.to_bytes(4, "little"))


def is_our_wav(path: str | Path) -> bool:
    """Whether the file is a WAV this extension wrote (it carries our software tag)."""
    try:
        with open(path, "rb") as handle:
            header = handle.read(12)
            if header[:4] != b"RIFF" or header[8:12] != b"WAVE":
                return False
            while chunk := handle.read(8):
                if len(chunk) < 8:
                    return False
                name, size = chunk[:4], int.from_bytes(chunk[4:], "little")
                if name == b"LIST":
                    body = handle.read(size)
                    return body[:4] == b"INFO" and b"ISFT" in body and SOFTWARE_TAG in body
                handle.seek(size + size % 2, os.SEEK_CUR)
    except OSError:
        return False
    return False


def _holds(path: Path, pcm: memoryview, sample_rate: int) -> bool:
    """Whether the WAV at path holds exactly this mono 16-bit sound."""
    try:
        with wave.open(str(path), "rb") as handle:
            if (handle.getnchannels(), handle.getsampwidth(), handle.getframerate()) != (1, 2, sample_rate):
                return False
            return pcm == handle.readframes(handle.getnframes())
    except (OSError, EOFError, wave.Error):
        return False


def speech_wav_in(folder: str | Path, stem: str, synthesis: Synthesis) -> Path:
    """The WAV of this speech in folder, named <stem>-<digest of the sound>.wav: written where it is not
    there yet, reused where it is; a file of that name with another sound is left alone and the next free
    name (-2, -3, ...) taken."""
    pcm = _pcm(synthesis)
    rate = int(synthesis.sample_rate)
    sound = hashlib.sha1(pcm)
    sound.update(rate.to_bytes(4, "little"))
    digest = sound.hexdigest()[:10]
    folder = Path(folder)
    for number in range(1, 1000):
        path = folder / (f"{stem}-{digest}.wav" if number == 1 else f"{stem}-{digest}-{number}.wav")
        if not path.exists():
            return write_wav(path, synthesis)
        if _holds(path, pcm, rate):
            return path
    raise AudioError(
        f"{folder} holds 999 other files named {stem}-{digest}*.wav; choose another speech folder"
    )
