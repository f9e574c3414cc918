"""The head's speech for the tools around Blender: Rhubarb cues, Moho switch data, Papagayo, ARKit CSV.

Exports describe the animation the head has: the timeline Generate kept with the keys (its record), and the
weights as the keys hold them now. Keys edited by hand since Generate are exported as they are, with a
warning that the mouth cues still follow the timeline Generate made.
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass
from pathlib import Path

import bpy

from ..core.base.errors import LipSyncError
from ..core.interchange import export_format_named, export_text, write_export
from . import keyframes, pipeline, sequencer


@dataclass(frozen=True)
class ExportResult:
    path: Path
    export_format: str
    warnings: tuple[str, ...]


def export_path_for(chosen: str, export_format: str) -> Path:
    """The chosen path with the format's own extension (a .json path exported as CSV becomes .csv)."""
    return Path(bpy.path.abspath(chosen)).with_suffix(export_format_named(export_format).suffix)


def export_animation(
    context: bpy.types.Context, head: bpy.types.Object, export_format: str, path: Path
) -> ExportResult:
    """The head's generated animation in one export format, written to path."""
    record = pipeline.animation_record(head)
    if record is None:
        raise LipSyncError(
            f"The head {head.name!r} has no generated animation to export: press Generate Animation first."
        )
    objects = pipeline.head_objects(head)
    tracks = keyframes.read_weight_tracks(objects, record.frame_start, record.frame_count, record.fps)
    tracks = dataclasses.replace(tracks, head_and_eyes=record.head_and_eyes)
    warnings: tuple[str, ...] = ()
    if keyframes.key_fingerprint(objects) != record.key_fingerprint:
        warnings = (
            f"The keys of {head.name!r} were changed after Generate Animation: the weights are exported as "
            "the keys are now, the mouth cues and words as Generate timed them.",
        )
    wav = sequencer.speech_wav_of(context.scene)
    sound = ""
    if wav is not None:
        try:
            sound = os.path.relpath(wav, path.parent)
        except ValueError:  # another drive on Windows
            sound = str(wav)
    contents, format_warnings = export_text(
        export_format, record.timeline, tracks, sound_file=sound, text=record.text
    )
    return ExportResult(write_export(path, contents), export_format, warnings + format_warnings)
