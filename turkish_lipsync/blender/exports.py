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
from ..core.speech.cues.papagayo_pgo import voices_as_pgo
from . import conversation, gltf_export, keyframes, pipeline, sequencer
from .scene_record import conversation_record


@dataclass(frozen=True)
class ExportResult:
    path: Path
    export_format: str
    warnings: tuple[str, ...]


def export_path_for(chosen: str, export_format: str) -> Path:
    """The chosen path with the format's own extension (a .json path exported as CSV becomes .csv)."""
    return Path(bpy.path.abspath(chosen)).with_suffix(export_format_named(export_format).suffix)


def in_conversation(scene: bpy.types.Scene, head: bpy.types.Object | None) -> bool:
    """Whether an export is the scene's conversation's: it holds one, and no other head is chosen."""
    characters = pipeline.conversation_heads(scene)
    return bool(characters) and (head is None or head in characters)


def export_speech(
    context: bpy.types.Context, head: bpy.types.Object | None, export_format: str, path: Path
) -> tuple[ExportResult, ...]:
    """What Generate made, for other tools: a conversation's (export_scene) where the head is one of its
    characters or none is chosen, else the head's own (export_animation)."""
    if in_conversation(context.scene, head):
        return export_scene(context, export_format, path)
    if head is None:
        raise LipSyncError("Choose the head whose speech to export in the Lip Sync panel.")
    return (export_animation(context, head, export_format, path),)


def export_speech_gltf(
    context: bpy.types.Context, head: bpy.types.Object | None, path: str | Path
) -> list[gltf_export.GltfExport]:
    """The speech as glTF: a conversation's scene and each character beside it, else the head's own."""
    if in_conversation(context.scene, head):
        return conversation.export_conversation_gltf(context, path)
    return [gltf_export.export_gltf(context, head, path)]


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
    if not tracks.tracks:
        warnings = (
            f"{head.name!r} speaks through its face rig, not its shape keys: formats of weights (the Live "
            "Link Face CSV) export them at rest; mouth cues and words are timed as Generate timed them.",
        )
    elif keyframes.key_fingerprint(objects) != record.key_fingerprint:
        warnings = (
            f"The keys of {head.name!r} were changed after Generate Animation: the weights are exported as "
            "the keys are now, the mouth cues and words as Generate timed them.",
        )
    contents, format_warnings = export_text(
        export_format,
        record.timeline,
        tracks,
        sound_file=_sound_beside(context.scene, path),
        text=record.text,
    )
    return ExportResult(write_export(path, contents), export_format, warnings + format_warnings)


def _sound_beside(scene: bpy.types.Scene, path: Path) -> str:
    """The scene's speech WAV as an export names it: relative to the export's folder where it can be."""
    wav = sequencer.speech_wav_of(scene)
    if wav is None:
        return ""
    try:
        return os.path.relpath(wav, path.parent)
    except ValueError:  # another drive on Windows
        return str(wav)


def character_path(path: Path, name: str) -> Path:
    """One character's file of a scene's export: the name after the chosen file's stem (scene_Ayşe.json)."""
    return path.with_name(f"{path.stem}_{'_'.join(name.split())}{path.suffix}")


def export_scene(context: bpy.types.Context, export_format: str, path: Path) -> tuple[ExportResult, ...]:
    """A conversation's animation: a Papagayo project with one voice per character at path, or one file per
    character of any other format beside it (character_path)."""
    record = conversation_record(context.scene)
    if record is None:
        raise LipSyncError(
            "The scene has no conversation to export: generate one from a script with speakers."
        )
    characters = [
        (key, record.names.get(key, key), bpy.data.objects[name])
        for key, name in record.heads.items()
        if name in bpy.data.objects
    ]
    if export_format != "papagayo-pgo":
        return tuple(
            export_animation(context, head, export_format, character_path(path, name))
            for _key, name, head in characters
        )
    voices, fps, warnings = [], record.fps, ()
    for _key, name, head in characters:
        animation = pipeline.animation_record(head)
        if animation is None:
            raise LipSyncError(
                f"{name}'s head {head.name!r} has no generated animation: press Generate again."
            )
        voices.append((name, animation.timeline, animation.text))
    if abs(fps - round(fps)) > 1e-6:
        warnings = (
            f"Papagayo counts whole frame rates: the project says {round(fps)} fps for the scene's {fps:g}.",
        )
    contents = voices_as_pgo(voices, fps, _sound_beside(context.scene, path), record.duration)
    return (ExportResult(write_export(path, contents), export_format, warnings),)
