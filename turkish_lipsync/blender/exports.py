"""The head's speech for the tools around Blender: Rhubarb cues, Moho switch data, Papagayo, ARKit CSV."""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass
from pathlib import Path

import bpy

from ..core.base.errors import LipSyncError
from ..core.interchange import export_format_named, export_text, write_export
from ..core.pipeline import LipSyncOptions, lip_sync
from . import pipeline, sequencer


@dataclass(frozen=True)
class ExportResult:
    path: Path
    export_format: str
    warnings: tuple[str, ...]


def export_path_for(chosen: str, export_format: str) -> Path:
    """The chosen path with the format's own extension (a .json path exported as CSV becomes .csv)."""
    return Path(bpy.path.abspath(chosen)).with_suffix(export_format_named(export_format).suffix)


def export_animation(
    context: bpy.types.Context,
    head: bpy.types.Object,
    source: str,
    options: LipSyncOptions,
    export_format: str,
    chosen_path: str,
) -> ExportResult:
    """The head's speech in one export format, as Generate Animation made it.

    Blender keeps only the keys, so the timeline is computed again from the same text and settings; the
    head's action must have been generated from this text (its name says so), or the export would describe
    another animation.
    """
    scene = context.scene
    fps = sequencer.scene_fps(scene)
    spoken = lip_sync(source, dataclasses.replace(options, fps=fps))
    keys = head.data.shape_keys
    action = keys.animation_data.action if keys is not None and keys.animation_data else None
    expected = pipeline.action_name_for(spoken.utterance)
    if action is None or not (action.name == expected or action.name.startswith(expected + ".")):
        current = repr(action.name) if action is not None else "none"
        raise LipSyncError(
            f"The head's animation ({current}) was not generated from this text ({expected!r}): press "
            "Generate Animation, then export."
        )
    path = export_path_for(chosen_path, export_format)
    wav = sequencer.speech_wav_of(scene)
    sound = ""
    if wav is not None:
        try:
            sound = os.path.relpath(wav, path.parent)
        except ValueError:  # another drive on Windows
            sound = str(wav)
    contents, warnings = export_text(
        export_format, spoken.timeline, spoken.tracks, sound_file=sound, text=source
    )
    return ExportResult(write_export(path, contents), export_format, spoken.warnings + warnings)
