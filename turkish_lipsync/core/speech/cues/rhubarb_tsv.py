"""Rhubarb Lip Sync's TSV: one line per mouth change, its start time and shape; the simplest to parse."""

from __future__ import annotations

from pathlib import Path

from ...base.model import Timeline
from .common import (
    CueFileError,
    CueFormat,
    CueSource,
    MouthCue,
    checked_shape,
    checked_time,
    mouth_cues,
    ordered,
    read_counted,
    register,
)
from .shapes import REST


@register
class RhubarbTsv(CueFormat):
    name = "rhubarb-tsv"
    order = 1
    suffixes = (".tsv", ".txt")
    label = "Rhubarb TSV"
    description = "Mouth cues A-H and X with their start times (Rhubarb Lip Sync)"

    def read(self, path: Path, fps: float) -> CueSource:
        """The last cue ends where the file's last line starts."""
        starts: list[tuple[float, str]] = []
        text = read_counted(path)
        for number, line in enumerate(text.splitlines(), start=1):
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            fields = line.split("\t") if "\t" in line else line.split()
            if len(fields) < 2:
                raise CueFileError(f"{path}: line {number}: expected 'START<TAB>SHAPE', got {line!r}")
            where = f"line {number}"
            starts.append((checked_time(path, where, fields[0]), checked_shape(path, where, fields[1])))
        if not starts:
            raise CueFileError(f"{path}: holds no mouth cues")
        cues = [
            MouthCue(start, end, shape) for (start, shape), (end, _) in zip(starts, starts[1:], strict=False)
        ]
        last_start, last_shape = starts[-1]
        if last_shape != REST or not cues:
            cues.append(MouthCue(last_start, last_start, last_shape))
        return CueSource(path, ordered(path, cues), last_start)

    def write(self, timeline: Timeline, fps: float, *, sound_file: str = "", text: str = ""):
        """Each cue lasts until the next line; a rest closes the file."""
        cues = mouth_cues(timeline)
        lines = [f"{cue.start:.3f}\t{cue.shape}" for cue in cues]
        if cues and cues[-1].shape != REST:
            lines.append(f"{cues[-1].end:.3f}\t{REST}")
        return "\n".join(lines) + "\n", ()
