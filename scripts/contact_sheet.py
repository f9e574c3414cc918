"""Render a contact sheet of the 43 keys (37 visemes + 6 emotions) on a head, for review and the README.

    .venv/bin/python scripts/contact_sheet.py --out out/contact_sheet.png [--head PATH] [--tile 160]

Cycles on the CPU (works headless everywhere); each tile is labelled by a text object in the scene.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from turkish_lipsync.blender import compat, heads, shapekeys  # noqa: E402
from turkish_lipsync.core.errors import LipSyncError  # noqa: E402
from turkish_lipsync.core.faces.recipes import VISEME_NAMES  # noqa: E402
from turkish_lipsync.core.model import EMOTIONS, emotion_key_name, viseme_key_name  # noqa: E402


def _setup_scene(head: bpy.types.Object, tile: int) -> None:
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 8
    scene.render.resolution_x = scene.render.resolution_y = tile
    scene.render.film_transparent = False
    world = bpy.data.worlds.new("TR_ContactWorld")
    world.color = (0.35, 0.37, 0.4)
    scene.world = world
    matrix = np.array(head.matrix_world)
    box = np.array([tuple(c) for c in head.bound_box]) @ matrix[:3, :3].T + matrix[:3, 3]
    lower, upper = box.min(axis=0), box.max(axis=0)
    centre = (lower + upper) / 2
    height = float(upper[2] - lower[2])
    face = np.array([centre[0], lower[1], lower[2] + 0.45 * height])  # the chin-to-eyes band
    camera_data = bpy.data.cameras.new("TR_ContactCamera")
    camera_data.type = "ORTHO"
    camera_data.ortho_scale = 0.55 * height
    camera = bpy.data.objects.new("TR_ContactCamera", camera_data)
    camera.location = (face[0], face[1] - 3 * height, face[2])
    camera.rotation_euler = (math.pi / 2, 0, 0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    for name, energy, offset in (("key", 4.0, (-1, -2, 1.2)), ("fill", 1.5, (1.5, -2, 0.2))):
        light_data = bpy.data.lights.new(f"TR_Contact_{name}", "SUN")
        light_data.energy = energy
        light = bpy.data.objects.new(light_data.name, light_data)
        direction = -np.array(offset, dtype=float)
        light.rotation_euler = _aim(direction)
        scene.collection.objects.link(light)
    label_data = bpy.data.curves.new("TR_ContactLabel", "FONT")
    label_data.size = 0.05 * height
    label_data.align_x = "CENTER"
    label = bpy.data.objects.new("TR_ContactLabel", label_data)
    label.location = (face[0], face[1] - 2 * height, face[2] - 0.24 * height)
    label.rotation_euler = (math.pi / 2, 0, 0)
    material = bpy.data.materials.new("TR_ContactLabel")
    compat.enable_material_nodes(material)
    shader = next(n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    shader.inputs["Base Color"].default_value = (1, 1, 0.2, 1)
    label_data.materials.append(material)
    scene.collection.objects.link(label)


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
    sheet = np.zeros((rows * tile, columns * tile, 4), dtype=np.float32)
    with tempfile.TemporaryDirectory() as folder:
        for index, key in enumerate(keys):
            for obj in objects:
                for block in obj.data.shape_keys.key_blocks[1:]:
                    block.value = 1.0 if block.name == key else 0.0
            label.data.body = key.removeprefix("TR_viseme_").removeprefix("TR_emotion_")
            bpy.context.scene.render.filepath = str(Path(folder) / f"{index}.png")
            bpy.ops.render.render(write_still=True)
            image = bpy.data.images.load(bpy.context.scene.render.filepath)
            pixels = np.array(image.pixels[:], dtype=np.float32).reshape(tile, tile, 4)
            bpy.data.images.remove(image)
            row, column = divmod(index, columns)
            sheet[(rows - 1 - row) * tile : (rows - row) * tile, column * tile : (column + 1) * tile] = pixels
            print(f"{index + 1}/{len(keys)} {key}", flush=True)
    result = bpy.data.images.new("TR_ContactSheet", columns * tile, rows * tile, alpha=True)
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
