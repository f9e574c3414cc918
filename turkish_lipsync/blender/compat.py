"""Every difference between Blender 4.2 LTS, 4.5 LTS and 5.0, and nowhere else.

- Actions: 4.4 introduced layered actions (slot -> layer -> keyframe strip -> channelbag -> F-curves);
  5.0 removed the legacy ``Action.fcurves``. ``channelbag.fcurves.new`` takes ``group_name`` only on 5.0.
- Sequencer: ``SequenceEditor.sequences`` became ``strips`` in 5.0.
- EEVEE is ``BLENDER_EEVEE_NEXT`` from 4.2 to 4.5 and ``BLENDER_EEVEE`` in 5.0.
- Video output in 5.0 needs ``image_settings.media_type = 'VIDEO'`` before ``file_format = 'FFMPEG'``.
- The 4.2 bpy module crashes at exit once its glTF exporter has run (see ``survive_gltf_export_at_exit``).
"""

from __future__ import annotations

import atexit
import gc
from dataclasses import dataclass

import bpy

VERSION: tuple[int, int, int] = tuple(bpy.app.version)  # type: ignore[assignment]

# Layered actions exist from 4.4 on; 4.2 and 4.3 have only Action.fcurves.
HAS_LAYERED_ACTIONS = "slots" in bpy.types.Action.bl_rna.properties
FCURVE_NEW_TAKES_GROUP_NAME = VERSION >= (5, 0, 0)
_EXIT_GUARD: list[bool] = []


def survive_gltf_export_at_exit() -> None:
    """Keep a process that ran the glTF exporter on 4.2 from crashing as it exits (call after exporting).

    There, garbage the exporter leaves is otherwise freed by Python's last collection after Blender has
    freed the types it points into: a segmentation fault once all work is done, which turns a finished
    script's or test run's exit status into 139. Collecting it now, while Blender is alive, and freezing the
    heap at exit avoids that; 4.5 and 5.0 exit cleanly without it.
    """
    if VERSION >= (4, 5, 0):
        return
    gc.collect()
    if not _EXIT_GUARD:
        atexit.register(gc.freeze)
        _EXIT_GUARD.append(True)


# ---------------------------------------------------------------- actions and F-curves


def action_slot_for(action: bpy.types.Action, id_data: bpy.types.ID, id_type: str):
    """The action's slot for id_data (created when missing); None on Blender without slots."""
    if not HAS_LAYERED_ACTIONS:
        return None
    animation_data = id_data.animation_data
    if animation_data is not None and animation_data.action == action and animation_data.action_slot:
        return animation_data.action_slot
    for slot in action.slots:
        if slot.target_id_type == id_type:
            return slot
    return action.slots.new(id_type=id_type, name=id_data.name)


def assign_action(id_data: bpy.types.ID, action: bpy.types.Action, id_type: str) -> None:
    """Make action the active action of id_data, on the right slot where slots exist."""
    animation_data = id_data.animation_data or id_data.animation_data_create()
    slot = action_slot_for(action, id_data, id_type)
    if animation_data.action != action:
        animation_data.action = action
    if slot is not None and animation_data.action_slot != slot:
        animation_data.action_slot = slot


def _channelbag(action: bpy.types.Action, slot, create: bool):
    """The F-curve container of action for slot (layered actions only)."""
    if not action.layers:
        if not create:
            return None
        action.layers.new("Layer")
    layer = action.layers[0]
    if not layer.strips:
        if not create:
            return None
        layer.strips.new(type="KEYFRAME")
    return layer.strips[0].channelbag(slot, ensure=create)


@dataclass(frozen=True)
class Channels:
    """Where an ID's F-curves and their groups live in an action (the action itself before 4.4)."""

    fcurves: object
    groups: object


def action_channels(
    action: bpy.types.Action, id_data: bpy.types.ID, id_type: str, create: bool = True
) -> Channels | None:
    """The F-curves that animate id_data in action (None when there are none and create is False)."""
    if not HAS_LAYERED_ACTIONS:
        return Channels(action.fcurves, action.groups)
    slot = action_slot_for(action, id_data, id_type)
    channelbag = _channelbag(action, slot, create)
    return None if channelbag is None else Channels(channelbag.fcurves, channelbag.groups)


def new_fcurve(channels: Channels, data_path: str, group_name: str, index: int = 0):
    """A new F-curve filed under group_name (the keyword differs per version)."""
    if not HAS_LAYERED_ACTIONS:
        return channels.fcurves.new(data_path, index=index, action_group=group_name)
    if FCURVE_NEW_TAKES_GROUP_NAME:
        return channels.fcurves.new(data_path, index=index, group_name=group_name)
    fcurve = channels.fcurves.new(data_path, index=index)
    group = channels.groups.get(group_name) or channels.groups.new(group_name)
    fcurve.group = group
    return fcurve


def all_action_fcurves(action: bpy.types.Action) -> list:
    """Every F-curve of action, over all slots (for reports and tests)."""
    if not HAS_LAYERED_ACTIONS:
        return list(action.fcurves)
    curves = []
    for layer in action.layers:
        for strip in layer.strips:
            for channelbag in strip.channelbags:
                curves.extend(channelbag.fcurves)
    return curves


# ---------------------------------------------------------------- sequencer

# The bpy module 4.2 from PyPI is built without Audaspace: no sounds, no sound strips, no audio in renders.
HAS_AUDIO = bool(getattr(bpy.app.build_options, "audaspace", True))
# Audaspace reads recordings through Blender's FFmpeg (AAC, the sound tracks of videos) where both are built
# in: every Blender release and the PyPI modules 4.5 and 5.0.
HAS_FFMPEG_AUDIO = HAS_AUDIO and bool(getattr(bpy.app.build_options, "codec_ffmpeg", False))
# FFmpeg 7.1 (Blender 4.5 and 5.0) decodes the priming samples a Matroska track's CodecDelay announces (an
# AAC encoder's 1024) as sound, 21-32 ms before the recording's own; FFmpeg 8.1 drops them (measured).
FFMPEG_KEEPS_MATROSKA_CODEC_DELAY = HAS_FFMPEG_AUDIO and bpy.app.ffmpeg.avformat_version < (62, 0, 0)


def sequencer_strips(scene: bpy.types.Scene, create: bool = True):
    """The scene's top-level strips (None when there is no sequencer and create is False)."""
    editor = scene.sequence_editor
    if editor is None:
        if not create:
            return None
        editor = scene.sequence_editor_create()
    return editor.strips if hasattr(editor, "strips") else editor.sequences


# ---------------------------------------------------------------- render engines and output

ENGINE_IDS = {
    "EEVEE": "BLENDER_EEVEE" if VERSION >= (5, 0, 0) else "BLENDER_EEVEE_NEXT",
    "CYCLES": "CYCLES",
    "WORKBENCH": "BLENDER_WORKBENCH",
}


def engine_id(engine: str) -> str:
    """Blender's identifier of EEVEE, CYCLES or WORKBENCH in this version."""
    return ENGINE_IDS[engine]


def set_video_output(image_settings) -> None:
    """Switch the output to FFmpeg video (5.0 first needs the media type)."""
    if hasattr(image_settings, "media_type"):
        image_settings.media_type = "VIDEO"
    image_settings.file_format = "FFMPEG"


def set_image_output(image_settings, file_format: str = "PNG") -> None:
    if hasattr(image_settings, "media_type"):
        image_settings.media_type = "IMAGE"
    image_settings.file_format = file_format


# ---------------------------------------------------------------- materials


def enable_material_nodes(material: bpy.types.Material) -> None:
    """Give a material its node tree; from 5.0 on every material has one and use_nodes is deprecated."""
    if VERSION < (5, 0, 0):
        material.use_nodes = True
