"""Render a contact sheet of the 43 keys (37 visemes + 6 emotions) on a head, for review and the manual.

    .venv/bin/python -m tools.figures.contact_sheet --out out/contact_sheet.png [--head PATH] [--tile 160]

Cycles on the CPU (works headless everywhere, about a minute for the sheet); each tile frames the face from
the brows to below the chin and is labelled on a dark bar under the chin by a text object in the scene.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
from pathlib import Path

import bpy
import numpy as np

from turkish_lipsync.blender import compat, heads, pipeline, render, shapekeys
from turkish_lipsync.blender.living_rig import find_rig
from turkish_lipsync.core.base.errors import LipSyncError
from turkish_lipsync.core.base.model import EMOTIONS, emotion_key_name, viseme_key_name
from turkish_lipsync.core.base.visemes import VISEME_NAMES

TILE_ASPECT = 1.2  # tiles are taller than wide: a face, with a label bar under the chin
BACKGROUND = (0.35, 0.37, 0.4)
LABEL_BAR_COLOUR = (0.0, 0.0, 0.0)  # black stays black under any view transform


LABEL_BAR = 0.16  # share of a tile's height kept below the chin for its label


def _setup_scene(head: bpy.types.Object, tile: int) -> None:
    """Camera on the face from brows to chin, whichever way it looks, a dark bar under the chin with the
    key's name on it."""
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 8
    scene.render.resolution_x = tile
    scene.render.resolution_y = round(tile * TILE_ASPECT)
    scene.render.film_transparent = False
    world = bpy.data.worlds.new("TR_ContactWorld")
    world.color = BACKGROUND
    scene.world = world
    # The face's own axes (columns: left, up, forward) and the band our keys move, brows to chin.
    frame = find_rig(head).frame
    up, forward = frame[:, 1], frame[:, 2]
    right = np.cross(up, forward)  # the camera's x: the viewer's right, facing the face
    points = render.face_points(pipeline.head_objects(head))
    along_up, along_right, along_forward = points @ up, points @ right, points @ forward
    margin = 0.12 * float(np.ptp(along_up))
    face_top, face_bottom = along_up.max() + margin, along_up.min() - margin
    height = face_top - face_bottom
    view_height = height / (1 - LABEL_BAR)
    centre_up = face_top - view_height / 2
    centre_right = float(along_right.max() + along_right.min()) / 2
    front = float(along_forward.max())
    rotation = np.column_stack([right, up, forward])  # x right, y up, looking along -forward

    def placed(obj: bpy.types.Object, ahead: float, rise: float) -> None:
        from mathutils import Matrix

        matrix = np.eye(4)
        matrix[:3, :3] = rotation
        matrix[:3, 3] = right * centre_right + up * rise + forward * (front + ahead)
        obj.matrix_world = Matrix(matrix.tolist())

    camera_data = bpy.data.cameras.new("TR_ContactCamera")
    camera_data.type = "ORTHO"
    camera_data.sensor_fit = "VERTICAL"
    camera_data.ortho_scale = view_height
    camera_data.clip_end = 10 * view_height + 100
    camera = bpy.data.objects.new("TR_ContactCamera", camera_data)
    placed(camera, 3 * view_height, centre_up)
    scene.collection.objects.link(camera)
    scene.camera = camera
    for name, energy, (sideways, ahead, rise) in (("key", 4.0, (-1, 2, 1.6)), ("fill", 1.5, (1.5, 2, 0.2))):
        light_data = bpy.data.lights.new(f"TR_Contact_{name}", "SUN")
        light_data.energy = energy
        light = bpy.data.objects.new(light_data.name, light_data)
        light.rotation_euler = _aim(-(sideways * right + ahead * forward + rise * up))
        scene.collection.objects.link(light)
    # The label bar sits between the camera and the face, so it hides the neck and never the chin.
    bar_height = LABEL_BAR * view_height
    bar_rise = centre_up - view_height / 2 + bar_height / 2
    bar_mesh = bpy.data.meshes.new("TR_ContactLabelBar")
    half_width, half_height = view_height, bar_height / 2
    bar_mesh.from_pydata(
        [(-half_width, -half_height, 0), (half_width, -half_height, 0), (half_width, half_height, 0),
         (-half_width, half_height, 0)],
        [],
        [(0, 1, 2, 3)],
    )  # fmt: skip
    bar = bpy.data.objects.new("TR_ContactLabelBar", bar_mesh)
    placed(bar, 1.5 * view_height, bar_rise)
    bar_mesh.materials.append(_emission_material("TR_ContactLabelBar", LABEL_BAR_COLOUR, 1.0))
    scene.collection.objects.link(bar)
    label_data = bpy.data.curves.new("TR_ContactLabel", "FONT")
    label_data.size = 0.62 * bar_height
    label_data.align_x = "CENTER"
    label_data.align_y = "CENTER"
    label_data.materials.append(_emission_material("TR_ContactLabel", (1.0, 0.92, 0.45), 1.0))
    label = bpy.data.objects.new("TR_ContactLabel", label_data)
    placed(label, 1.51 * view_height, bar_rise)
    scene.collection.objects.link(label)


def _emission_material(name: str, colour: tuple[float, float, float], strength: float) -> bpy.types.Material:
    """A flat, unlit colour: labels read the same whatever the lights do."""
    material = bpy.data.materials.new(name)
    compat.enable_material_nodes(material)
    nodes = material.node_tree.nodes
    for node in list(nodes):
        nodes.remove(node)
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (*colour, 1.0)
    emission.inputs["Strength"].default_value = strength
    output = nodes.new("ShaderNodeOutputMaterial")
    material.node_tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
    return material


def _aim(direction: np.ndarray) -> tuple[float, float, float]:
    """Euler angles that point a light's -Z along direction."""
    from mathutils import Vector

    return Vector(direction.tolist()).to_track_quat("-Z", "Y").to_euler()[:]


def render_contact_sheet(out: Path, head_path: Path | None, tile: int, columns: int) -> None:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if head_path is None:
        head = heads.create_reference_head(bpy.context)["head"]
    else:
        head = heads.find_head(heads.import_head(head_path))
    report = shapekeys.build_shape_keys(head)
    print(f"built {len(report.keys)} keys from source {report.source}")
    _setup_scene(head, tile)
    label = bpy.data.objects["TR_ContactLabel"]
    keys = [viseme_key_name(v) for v in VISEME_NAMES] + [emotion_key_name(e) for e in EMOTIONS]
    objects = [bpy.data.objects[name] for name in report.objects]
    rows = math.ceil(len(keys) / columns)
    tile_height = round(tile * TILE_ASPECT)
    sheet = np.empty((rows * tile_height, columns * tile, 4), dtype=np.float32)
    sheet[...] = (*LABEL_BAR_COLOUR, 1.0)  # empty cells: the labels' dark bar
    with tempfile.TemporaryDirectory() as folder:
        for index, key in enumerate(keys):
            for obj in objects:
                for block in obj.data.shape_keys.key_blocks[1:]:
                    block.value = 1.0 if block.name == key else 0.0
            label.data.body = key.removeprefix("TR_viseme_").removeprefix("TR_emotion_")
            bpy.context.scene.render.filepath = str(Path(folder) / f"{index}.png")
            bpy.ops.render.render(write_still=True)
            image = bpy.data.images.load(bpy.context.scene.render.filepath)
            pixels = np.empty(tile * tile_height * 4, dtype=np.float32)
            image.pixels.foreach_get(pixels)
            pixels = pixels.reshape(tile_height, tile, 4)
            bpy.data.images.remove(image)
            row, column = divmod(index, columns)
            top = (rows - 1 - row) * tile_height
            sheet[top : top + tile_height, column * tile : (column + 1) * tile] = pixels
            print(f"{index + 1}/{len(keys)} {key}", flush=True)
    result = bpy.data.images.new("TR_ContactSheet", columns * tile, rows * tile_height, alpha=True)
    result.pixels.foreach_set(sheet.ravel())
    out.parent.mkdir(parents=True, exist_ok=True)
    result.filepath_raw = str(out)
    result.file_format = "PNG"
    result.save()
    print(f"wrote {out}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("out/contact_sheet.png"))
    parser.add_argument("--head", type=Path, default=None, help="head file (.obj .glb .gltf .fbx .blend)")
    parser.add_argument("--tile", type=int, default=160, help="tile size in pixels")
    parser.add_argument("--columns", type=int, default=8)
    args = parser.parse_args(argv)
    try:
        render_contact_sheet(args.out, args.head, args.tile, args.columns)
    except LipSyncError as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else None))
