"""The first audio track of a Matroska (MKV, WebM) file as its header declares it: codec and codec delay.

An AAC encoder primes its stream with samples that are not part of the recording (1024 of them); Matroska
announces them as the track's CodecDelay. FFmpeg 8.1 (PyAV's) drops them; FFmpeg 7.1 (Blender 4.5 and 5.0)
keeps them, so the Blender decoder drops them itself (blender/audio_decoding.py), reading this header.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

HEADER_BYTES = 1 << 20  # the tracks come before the first cluster, within the file's first kilobytes
SEGMENT, TRACKS, TRACK_ENTRY, CLUSTER = 0x18538067, 0x1654AE6B, 0xAE, 0x1F43B675
TRACK_TYPE, CODEC_ID, CODEC_DELAY = 0x83, 0x86, 0x56AA
AUDIO_TRACK = 2


@dataclass(frozen=True)
class MatroskaAudioTrack:
    codec: str  # Matroska's codec ID: "A_AAC", "A_OPUS", ...
    codec_delay: float  # seconds of the encoder's priming samples


def first_audio_track(path: Path) -> MatroskaAudioTrack | None:
    """The header's first audio track, or None where the header holds none (or is not Matroska's)."""
    with open(path, "rb") as handle:
        data = handle.read(HEADER_BYTES)
    for element, start, end in _elements(data, 0, len(data)):
        if element == SEGMENT:
            for child, child_start, child_end in _elements(data, start, end):
                if child == CLUSTER:
                    return None
                if child == TRACKS:
                    return _audio_track(data, child_start, child_end)
    return None


def _audio_track(data: bytes, start: int, end: int) -> MatroskaAudioTrack | None:
    for element, entry_start, entry_end in _elements(data, start, end):
        if element != TRACK_ENTRY:
            continue
        fields = {field: data[a:b] for field, a, b in _elements(data, entry_start, entry_end)}
        if int.from_bytes(fields.get(TRACK_TYPE, b""), "big") == AUDIO_TRACK:
            codec = fields.get(CODEC_ID, b"").rstrip(b"\0").decode("ascii", "replace")
            return MatroskaAudioTrack(codec, int.from_bytes(fields.get(CODEC_DELAY, b""), "big") / 1e9)
    return None


def _elements(data: bytes, start: int, end: int) -> Iterator[tuple[int, int, int]]:
    """(element ID, payload start, payload end) of the EBML elements between start and end."""
    position = start
    while position < end:
        element, position = _vint(data, position, keep_marker=True)
        size, position = _vint(data, position, keep_marker=False)
        if element is None or size is None:
            return
        stop = end if size < 0 else min(position + size, end)  # an unknown size runs to the end
        yield element, position, stop
        position = stop


def _vint(data: bytes, position: int, keep_marker: bool) -> tuple[int | None, int]:
    """EBML's variable-length integer at position (-1 for a size of all ones: unknown) and what follows."""
    if position >= len(data) or data[position] == 0:
        return None, len(data)
    length = 9 - data[position].bit_length()
    raw = int.from_bytes(data[position : position + length], "big")
    if keep_marker:
        return raw, position + length
    value = raw & ((1 << (7 * length)) - 1)
    return (-1 if value == (1 << (7 * length)) - 1 else value), position + length
