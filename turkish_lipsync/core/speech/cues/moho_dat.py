"""Moho switch data (.dat): "MohoSwitch1", then one "FRAME MOUTH" line per mouth change, frames from 1.

Read by Moho (a switch layer's lip-sync data) and OpenToonz (Apply Lip Sync Data to Column). Mouths are
Preston Blair's names (AI, E, etc, FV, L, MBP, O, rest, U), as Moho's mouth rigs name their switch layers.
"""

from __future__ import annotations

from pathlib import Path

from ...base.model import Timeline
from .common import (
    CueFileError,
    CueFormat,
    CueSource,
    MouthCue,
    frame_of,
    mouth_cues,
    read_counted,
    register,
)
from .shapes import shape_for_phoneme, shape_table, uses_preston_blair

MOHO_HEADER = "MohoSwitch1"


@register
class MohoDat(CueFormat):
    name = "moho-dat"
    order = 4
    suffixes = (".dat",)
    label = "Moho Switch Data"
    description = "Preston Blair mouths per frame for Moho and OpenToonz (.dat)"

    def read(self, path: Path, fps: float) -> CueSource:
        """The cues of a Moho switch file at fps (the file does not hold it); the last change lasts a frame.

        Frames count from 1 and must rise from line to line: a file that goes back in time or names frame 0
        is refused with its line.
        """
        text = read_counted(path)
        lines = [(number, line.strip()) for number, line in enumerate(text.splitlines(), 1)]
        lines = [(number, line) for number, line in lines if line]
        if not lines or lines[0][1] != MOHO_HEADER:
            raise CueFileError(f"{path}: line 1 must be '{MOHO_HEADER}': is this Moho switch data?")
        preston_blair = uses_preston_blair(line.split()[-1] for _, line in lines[1:])
        changes: list[tuple[int, str]] = []
        for number, line in lines[1:]:
            fields = line.split()
            valid = len(fields) == 2 and fields[0].isdigit()
            shape = shape_for_phoneme(fields[1], preston_blair) if valid else None
            if shape is None:
                raise CueFileError(
                    f"{path}: line {number}: expected 'FRAME SHAPE' with a known shape, got {line!r}"
                )
            frame = int(fields[0])
            if frame < 1:
                raise CueFileError(f"{path}: line {number}: frame {frame}: Moho counts frames from 1")
            if changes and frame <= changes[-1][0]:
                raise CueFileError(
                    f"{path}: line {number}: frame {frame} does not come after frame {changes[-1][0]} of the "
                    "line before: the changes must be in the order they are shown"
                )
            changes.append((frame, shape))
        if not changes:
            raise CueFileError(f"{path}: holds no mouth changes")
        starts = [(frame - 1) / fps for frame, _ in changes]
        ends = starts[1:] + [starts[-1] + 1 / fps]
        cues = tuple(
            MouthCue(start, end, shape) for (_, shape), start, end in zip(changes, starts, ends, strict=True)
        )
        return CueSource(path, cues, cues[-1].end)

    def write(self, timeline: Timeline, fps: float, *, sound_file: str = "", text: str = ""):
        """Each mouth change on the frame it shows (frame 1 is the first), in Preston Blair's names."""
        names = shape_table().preston_blair
        changes: dict[int, str] = {}
        for cue in mouth_cues(timeline):
            changes[frame_of(cue.start, fps) + 1] = names[cue.shape]
        lines = [MOHO_HEADER]
        previous = None
        for frame in sorted(changes):
            if changes[frame] != previous:
                lines.append(f"{frame} {changes[frame]}")
                previous = changes[frame]
        return "\n".join(lines) + "\n", ()
