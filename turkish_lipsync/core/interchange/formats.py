"""What an export format is, and the registry of them: every cue format, and the exports of this package.

An export format is one class: its name, the suffix it writes, a label and description for the panel and
--help, and `write` (the animation to the file's text, with warnings for what the format cannot hold). Each
cue format of speech/cues is an export as it is; other exports (the ARKit CSV) are modules of this package
that subclass `ExportFormat` and decorate it with `@register_export`.
"""

from __future__ import annotations

from pathlib import Path

from ..base.model import Timeline, WeightTracks
from ..base.registry import Registry
from ..speech.cues import CueFormat, cue_formats


class ExportFormat:
    name: str = ""
    suffix: str = ""
    label: str = ""
    description: str = ""
    order: int = 0  # place among the formats (the panel's list)

    def write(
        self, timeline: Timeline, tracks: WeightTracks, *, sound_file: str = "", text: str = ""
    ) -> tuple[str, tuple[str, ...]]:
        raise NotImplementedError


class CueExport(ExportFormat):
    """A cue format written as an export: the timeline's mouth cues at the tracks' frame rate."""

    def __init__(self, cue_format: CueFormat) -> None:
        self.cue_format = cue_format
        self.name = cue_format.name
        self.suffix = cue_format.suffixes[0]
        self.label = cue_format.label
        self.description = cue_format.description
        self.order = cue_format.order

    def write(self, timeline, tracks, *, sound_file: str = "", text: str = ""):
        return self.cue_format.write(timeline, tracks.fps, sound_file=sound_file, text=text)


EXPORTS: Registry[ExportFormat] = Registry("export format", __package__, Path(__file__).parent)
register_export = EXPORTS.register


def export_formats() -> dict[str, ExportFormat]:
    """Every export format by name: the cue formats first, then this package's own exports."""
    cues = {name: CueExport(cue_format) for name, cue_format in cue_formats().items()}
    return cues | EXPORTS.entries()
