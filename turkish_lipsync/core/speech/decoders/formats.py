"""What kind of file a recording is, from its first bytes (its name only where they say nothing).

The kind decides which decoders are asked (libsndfile reads no MP4 or Matroska) and names the file in an
error the user can act on ("take.m4a (M4A/AAC)").
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

HEADER_BYTES = 64  # enough for every signature below (a WebM's doc type, an Ogg stream's first header)


@dataclass(frozen=True)
class AudioFormat:
    name: str
    label: str  # for messages: "M4A/AAC"
    suffixes: tuple[str, ...]
    libsndfile: bool  # libsndfile (the soundfile wheel) reads it; the rest needs FFmpeg
    video: bool = False  # may hold a picture beside its sound


FORMATS = {
    audio_format.name: audio_format
    for audio_format in (
        AudioFormat("wav", "WAV", (".wav", ".wave"), True),
        AudioFormat("flac", "FLAC", (".flac",), True),
        AudioFormat("ogg", "OGG Vorbis", (".ogg", ".oga"), True),
        AudioFormat("opus", "OGG Opus", (".opus",), True),
        AudioFormat("mp3", "MP3", (".mp3",), True),
        AudioFormat("aiff", "AIFF", (".aif", ".aiff", ".aifc"), True),
        AudioFormat("caf", "CAF/Core Audio", (".caf",), True),
        AudioFormat("m4a", "M4A/AAC", (".m4a", ".m4b"), False),
        AudioFormat("aac", "ADTS AAC", (".aac",), False),
        AudioFormat("mp4", "MP4", (".mp4", ".m4v"), False, video=True),
        AudioFormat("mov", "MOV/QuickTime", (".mov", ".qt"), False, video=True),
        AudioFormat("3gp", "3GP", (".3gp", ".3g2"), False, video=True),
        AudioFormat("mkv", "MKV/Matroska", (".mkv", ".mka"), False, video=True),
        AudioFormat("webm", "WebM", (".webm",), False, video=True),
        AudioFormat("avi", "AVI", (".avi",), False, video=True),
        AudioFormat("asf", "WMA/WMV", (".wma", ".wmv", ".asf"), False, video=True),
    )
}
RECORDING_SUFFIXES = tuple(suffix for audio_format in FORMATS.values() for suffix in audio_format.suffixes)
RECORDING_KINDS = "WAV, FLAC, OGG, MP3, M4A or a video with sound (MP4, MOV, MKV, WebM)"  # in messages


def unknown_format(path: Path) -> AudioFormat:
    """A file none of the signatures knows: every decoder may try it."""
    suffix = path.suffix.lower()
    return AudioFormat("unknown", "a kind not recognised", (suffix,), True, video=True)


def sniff_format(path: Path) -> AudioFormat:
    """The kind of the recording at path (OSError where it cannot be opened)."""
    with open(path, "rb") as handle:
        head = handle.read(HEADER_BYTES)
    by_suffix = next((f for f in FORMATS.values() if path.suffix.lower() in f.suffixes), None)
    name = _signature(head) or (by_suffix.name if by_suffix else None)
    if name == "id3":  # a tag before the audio: MP3 unless the name says AAC
        name = "aac" if by_suffix is not None and by_suffix.name == "aac" else "mp3"
    return FORMATS[name] if name else unknown_format(path)


def _signature(head: bytes) -> str:
    """The format whose signature the header carries, or "" where it carries none."""
    kind, brand = head[:4], head[8:12]
    if kind in (b"RIFF", b"RF64", b"BW64"):
        return {b"WAVE": "wav", b"AVI ": "avi"}.get(brand, "")
    if kind == b"FORM" and brand in (b"AIFF", b"AIFC"):
        return "aiff"
    if head[4:8] == b"ftyp":
        return _mp4_brand(brand)
    if head[4:8] in (b"moov", b"mdat", b"wide", b"free", b"skip"):
        return "mov"  # QuickTime from before the ftyp box
    if kind == b"\x1a\x45\xdf\xa3":
        return "webm" if b"webm" in head else "mkv"
    if kind == b"OggS":
        return "opus" if b"OpusHead" in head else "ogg"
    simple = {b"fLaC": "flac", b"caff": "caf", b"0&\xb2u": "asf"}
    if kind in simple:
        return simple[kind]
    if head[:3] == b"ID3":
        return "id3"
    if len(head) >= 2 and head[0] == 0xFF and head[1] & 0xF6 == 0xF0:
        return "aac"  # an ADTS frame: layer bits zero
    if len(head) >= 2 and head[0] == 0xFF and head[1] & 0xE0 == 0xE0 and head[1] & 0x06:
        return "mp3"  # an MPEG audio frame
    return ""


def _mp4_brand(brand: bytes) -> str:
    if brand in (b"M4A ", b"M4B ", b"M4P "):
        return "m4a"
    if brand == b"qt  ":
        return "mov"
    if brand.startswith(b"3g"):
        return "3gp"
    return "mp4"
