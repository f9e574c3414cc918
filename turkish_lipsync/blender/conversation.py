"""Several characters from one script: a head per speaker, an action and record each, the lines' sound.

Each speaker is played by the head the cast names (an object of the file, or a head file imported), else by
a default head of its own, made in a tone of its own (conversation.toml [[tones]]) and stood on the arc the
core lays out (core/scene/layout.py), turned toward the others. Generate again reuses those heads where
they are (the user may have moved them) and replaces only what the last Generate made: our keys' curves,
our living motion, our strips (by the names it recorded, scene_record.py).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import bpy
import numpy as np
from mathutils import Vector

from ..core.base.errors import HeadError
from ..core.scene import Cast, Standing
from ..core.scene.layout import arc_positions
from ..core.scene.tables import conversation_table
from . import gltf_export, living, pipeline, render, shapekeys
from . import heads as head_files
from .character import check_can_speak
from .face_rig import is_linked
from .living_rig import LivingRig, find_rig
from .scene_record import conversation_record

CAST_PROPERTY = "tr_cast_speaker"  # on a default head Generate made for a speaker: the speaker's key


# ---------------------------------------------------------------- heads


def cast_heads(context: bpy.types.Context, cast: Cast) -> dict[str, str]:
    """Each speaker's head (speaker's key -> object name): the role's object, a head file imported, the
    default head Generate made for the speaker before, or a new default head in the speaker's tone on its
    place of the arc. What was made here is removed again when a head fails."""
    scene = context.scene
    made: list[bpy.types.Object] = []
    heads: dict[str, str] = {}
    slots = arc_positions(len(cast.roles))
    table = conversation_table()
    try:
        for index, role in enumerate(cast.roles):
            if role.head and role.head in bpy.data.objects:
                head = bpy.data.objects[role.head]
            elif role.head:
                path = Path(bpy.path.abspath(role.head))
                if path.suffix.lower() not in head_files.IMPORTABLE_SUFFIXES:
                    raise HeadError(
                        f"{role.name}'s head {role.head!r} is neither an object of this file nor a head file "
                        f"({', '.join(head_files.IMPORTABLE_SUFFIXES)}); choose one, or leave it empty for "
                        "the default head."
                    )
                imported = head_files.import_head(path)
                made += imported
                head = head_files.find_head(imported)
            else:
                head = next(
                    (o for o in scene.objects if o.get(CAST_PROPERTY) == role.key and o.type == "MESH"), None
                )
                if head is None:
                    tone = table.tones[index % len(table.tones)] if index else None
                    parts = head_files.create_reference_head(
                        context, _head_name(role.name), tone, tone_name=role.name if tone else ""
                    )
                    made += parts.values()
                    head = parts["head"]
                    head[CAST_PROPERTY] = role.key
                    position, turn = slots[index]
                    head.location = head.location + Vector(position.tolist())
                    head.rotation_euler.z += math.radians(turn)
            if head.type != "MESH":
                raise HeadError(
                    f"{role.name}'s head {head.name!r} is not a mesh; choose the head mesh itself."
                )
            if is_linked(head):  # a linked character's keys are built in its own file
                check_can_speak(head, [head])
            elif not pipeline.has_lipsync_keys(head):
                context.view_layer.update()
                shapekeys.build_shape_keys(head)
            heads[role.key] = head.name
    except Exception:
        for obj in made:
            data = obj.data
            bpy.data.objects.remove(obj, do_unlink=True)
            if data is not None and data.users == 0 and isinstance(data, bpy.types.Mesh):
                bpy.data.meshes.remove(data)
        raise
    context.view_layer.update()
    return heads


def _head_name(name: str) -> str:
    return "TR_Head_" + (re.sub(r"\s+", "_", name.strip()) or "speaker")[:40]


def standings(context, cast: Cast, heads: dict[str, str]):
    """Each character's rig at rest, where it stands as the core sees it, and the camera's point: the
    scene's camera, else where Render's two-shot camera will stand."""
    scene = context.scene
    with living.at_rest(scene):
        rigs: dict[str, LivingRig] = {key: find_rig(bpy.data.objects[name]) for key, name in heads.items()}
        if scene.camera is not None:
            camera = np.array(scene.camera.matrix_world.translation)
        else:
            objects = [
                obj for name in heads.values() for obj in pipeline.head_objects(bpy.data.objects[name])
            ]
            facing = pipeline.group_facing(list(rigs.values()))
            centre, distance, _sensor, _size = render.camera_placement(scene, objects, facing, group=True)
            camera = np.array(centre) + facing[:, 2] * distance
    standings = {key: Standing(rig.pivot, rig.frame, rig.gaze_setup(None)[0]) for key, rig in rigs.items()}
    return rigs, standings, camera


def export_conversation_gltf(
    context: bpy.types.Context, filepath: str | Path
) -> list[gltf_export.GltfExport]:
    """A conversation as glTF: the whole scene in the chosen file, and each character in a file of its own
    beside it (scene_Ayşe.glb), each with the scene's speech WAV beside it."""
    record = conversation_record(context.scene)
    if record is None:
        raise HeadError("The scene has no conversation to export: generate one from a script with speakers.")
    path = Path(bpy.path.abspath(str(filepath))).with_suffix(".glb")
    heads = record.head_objects()
    written = [gltf_export.export_heads_gltf(context, heads, path)]
    for key, name in record.heads.items():
        if name in bpy.data.objects:
            speaker = "_".join(record.names.get(key, key).split())
            written.append(
                gltf_export.export_heads_gltf(
                    context, [bpy.data.objects[name]], path.with_name(f"{path.stem}_{speaker}.glb")
                )
            )
    return written
