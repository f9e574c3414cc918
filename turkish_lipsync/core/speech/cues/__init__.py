"""Cue files other tools write and read (Rhubarb, Moho, Papagayo): one module per format, found by name.

A new format is one new module here with a `CueFormat` subclass decorated with `@register`; it is then
readable as a timing source (`--cues`) and writable as an export, with no other file changed.
"""

from __future__ import annotations

from pathlib import Path

from .common import CUE_FORMATS, CueFileError, CueFormat, CueSource, MouthCue, mouth_cues


def cue_formats() -> dict[str, CueFormat]:
    """Every cue format by name, in the order of their modules' names."""
    return CUE_FORMATS.entries()


def cue_format_for(path: Path | str) -> CueFormat:
    """The format a file is read as, by its suffix."""
    path = Path(path)
    suffix = path.suffix.lower()
    for cue_format in cue_formats().values():
        if suffix in cue_format.suffixes:
            return cue_format
    known = ", ".join(s for f in cue_formats().values() for s in f.suffixes)
    raise CueFileError(f"{path}: unknown timing file type {suffix or '(none)'}; give one of {known}")


def read_cue_file(path: Path | str, fps: float = 24.0) -> CueSource:
    """Read any cue file (fps for the formats that count frames without saying at what rate)."""
    return cue_format_for(path).read(Path(path), fps)


__all__ = [
    "CueFileError",
    "CueFormat",
    "CueSource",
    "MouthCue",
    "cue_format_for",
    "cue_formats",
    "mouth_cues",
    "read_cue_file",
]
