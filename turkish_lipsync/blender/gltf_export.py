"""glTF 2.0 (.glb) of a speaking head for game engines and three.js: the mesh with its shape keys as morph
targets, the speech as morph-weight animation, and the speech WAV beside the file (glTF has no audio).

Blender's own glTF exporter writes the file; this module chooses what goes in, keeps the user's selection,
and reads the file back to make sure the animation is there.
"""

from __future__ import annotations

import json
import shutil
import struct
from dataclasses import dataclass
from pathlib import Path

import bpy

from ..core.base.errors import LipSyncError
from ..core.base.files import check_writable
from ..core.speech.wav import is_our_wav
from . import compat, sequencer
from .heads import find_head_parts

_GLB_MAGIC = b"glTF"


@dataclass(frozen=True)
class GltfExport:
    """What an export wrote (paths and counts, read back from the file)."""

    path: str
    wav_path: str | None  # the speech beside the .glb, same stem; None when the scene has no speech
    morph_targets: int  # on the head's mesh
    animated_nodes: int  # nodes (objects) whose morph weights the animation drives
    frame_start: int
    frame_end: int


def read_glb_document(path: str | Path) -> dict:
    """The JSON chunk of a .glb file."""
    data = Path(path).read_bytes()
    if len(data) < 20 or data[:4] != _GLB_MAGIC:
        raise LipSyncError(f"{path} is not a binary glTF (.glb) file; export it again.")
    (length,) = struct.unpack("<I", data[12:16])
    return json.loads(data[20 : 20 + length])


def export_gltf(context: bpy.types.Context, head: bpy.types.Object, filepath: str | Path) -> GltfExport:
    """Write head and its parts (teeth, tongue, eyes) as .glb with the scene's frame range of speech.

    The speech WAV of the scene is copied beside the file as <name>.wav.
    """
    return export_heads_gltf(context, [head], filepath)


def export_heads_gltf(
    context: bpy.types.Context, heads: list[bpy.types.Object], filepath: str | Path
) -> GltfExport:
    """Several heads (a conversation's characters) and their parts in one .glb, each with its morph-weight
    animation and turns; the scene's speech WAV beside it. Its counts are the first head's."""
    path = Path(bpy.path.abspath(str(filepath)))
    if path.suffix.lower() != ".glb":
        path = path.with_suffix(".glb")
    for head in heads:
        if head is None or head.type != "MESH" or head.data.shape_keys is None:
            raise LipSyncError(
                "Choose a head with shape keys to export: press 'Build Shape Keys', then 'Generate "
                "Animation'."
            )
        key = head.data.shape_keys
        if key.animation_data is None or key.animation_data.action is None:
            raise LipSyncError(
                f"{head.name!r} has no shape-key animation to export; press 'Generate Animation' first."
            )
    check_writable(path, "glTF file")
    speech = _speech_to_copy(context.scene, path)
    objects = [obj for head in heads for obj in (head, *find_head_parts(head))]
    _export_selected(context, list(dict.fromkeys(objects)), path)
    document = read_glb_document(path)
    meshes = {m.get("name"): m for m in document.get("meshes", [])}
    animated = {
        channel["target"].get("node")
        for animation in document.get("animations", [])
        for channel in animation.get("channels", [])
        if channel.get("target", {}).get("path") == "weights"
    }
    if any(head.data.name not in meshes for head in heads) or len(animated) < len(heads):
        raise LipSyncError(
            f"Blender's glTF exporter wrote {path} without the speech's morph-weight animation; "
            "check that the head's shape keys are animated and export again."
        )
    wav_path = _copy_speech_beside(speech, path)
    head_mesh = meshes[heads[0].data.name]
    targets = max((len(p.get("targets", [])) for p in head_mesh.get("primitives", [])), default=0)
    return GltfExport(
        path=str(path),
        wav_path=str(wav_path) if wav_path else None,
        morph_targets=targets,
        animated_nodes=len(animated),
        frame_start=context.scene.frame_start,
        frame_end=context.scene.frame_end,
    )


def _export_selected(context: bpy.types.Context, objects: list[bpy.types.Object], path: Path) -> None:
    """Run the exporter on exactly these objects, giving the user's selection and active object back."""
    view_layer = context.view_layer
    selected = [obj.name for obj in view_layer.objects if obj.select_get()]
    active = view_layer.objects.active.name if view_layer.objects.active else None
    try:
        for obj in view_layer.objects:
            obj.select_set(obj in objects)
        view_layer.objects.active = objects[0]
        bpy.ops.export_scene.gltf(
            filepath=str(path),
            export_format="GLB",
            use_selection=True,
            export_apply=False,  # applying modifiers would drop the shape keys
            export_morph=True,
            export_morph_normal=False,  # halves the file; normals are recomputed by the engines
            export_animations=True,
            export_animation_mode="ACTIVE_ACTIONS",
            export_morph_animation=True,
            export_force_sampling=True,  # one sample per frame: the engine plays what Blender plays
            export_frame_range=True,
            export_skins=False,
        )
    except RuntimeError as error:
        raise LipSyncError(f"Blender's glTF exporter failed on {path}: {error}".strip()) from error
    finally:
        for obj in view_layer.objects:
            obj.select_set(obj.name in selected)
        view_layer.objects.active = view_layer.objects.get(active) if active else None
        compat.survive_gltf_export_at_exit()


def _speech_to_copy(scene: bpy.types.Scene, path: Path) -> Path | None:
    """The scene's speech WAV to copy beside the .glb, checked before anything is written: a WAV beside it
    that we did not write (a user's own recording of that name) is never overwritten."""
    source = sequencer.speech_wav_of(scene)
    if source is None or not source.is_file():
        return None
    target = path.with_suffix(".wav")
    if target.exists() and not target.samefile(source) and not is_our_wav(target):
        raise LipSyncError(
            f"{target} exists and was not written by this extension (a recording of yours?); the glTF's "
            f"speech WAV would replace it: give the glTF another name than {path.name}."
        )
    check_writable(target, "speech WAV beside the glTF")
    return source


def _copy_speech_beside(source: Path | None, path: Path) -> Path | None:
    if source is None:
        return None
    target = path.with_suffix(".wav")
    if not (target.exists() and target.samefile(source)):
        shutil.copyfile(source, target)
    return target
