"""Interchange with the tools around Blender: the generated animation written in their formats.

Every cue format (speech/cues: Rhubarb TSV/JSON/XML, Moho .dat, Papagayo .pgo) and the 52 ARKit weights per
frame as Live Link Face CSV (arkit_csv.py). Formats are found by name in `export_formats()`; a new one is one
new module (formats.py says how).
"""

from __future__ import annotations

from pathlib import Path

from ..base.choices import Choice
from ..base.errors import LipSyncError
from ..base.model import Timeline, WeightTracks
from .formats import ExportFormat, export_formats


def export_choices() -> tuple[Choice, ...]:
    """The export formats for the panel and --help: what each one is and who reads it."""
    return tuple(Choice(f.name, f.label, f.description) for f in export_formats().values())


def export_format_named(name: str) -> ExportFormat:
    formats = export_formats()
    if name not in formats:
        raise LipSyncError(f"unknown export format {name!r}; choose one of: {', '.join(formats)}")
    return formats[name]


def export_text(
    name: str, timeline: Timeline, tracks: WeightTracks, *, sound_file: str = "", text: str = ""
) -> tuple[str, tuple[str, ...]]:
    """The file contents of one export format, and warnings for what the format could not hold."""
    return export_format_named(name).write(timeline, tracks, sound_file=sound_file, text=text)


def write_export(path: Path | str, contents: str) -> Path:
    """Write an export beside nothing else: the folder is created, errors say where."""
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(contents, encoding="utf-8")
    except OSError as error:
        raise LipSyncError(
            f"cannot write the export {path}: {error.strerror}; choose a writable place"
        ) from None
    return path


__all__ = [
    "ExportFormat",
    "export_choices",
    "export_format_named",
    "export_formats",
    "export_text",
    "write_export",
]
