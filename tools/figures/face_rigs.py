"""The face-rig and linked-character pictures of the manual, rendered with Cycles on the CPU:

    nice -n 10 .venv/bin/python -m tools.figures.face_rigs [--folder docs/images] [--tile 150] [--size 240]

- jaw_bone_character.jpg: a game character whose jaw is a bone and whose lids are shape keys (the default
  head on a neck, head and jaw armature, lab/kit/rigged_heads.py): the open mouth, a closed b/m/p, a
  blink, a look aside and the head turned; below, the letters of the first word of a spoken sentence.
- rigify_face.jpg: the same on the default head moved by Rigify's face rig (no shape keys at all).
- linked_shot.jpg: the default head with linkable keys, linked from its own file into a shot and
  library-overridden, speaking there (the shot's frames of the same moments).

Each tile is the face cut from a square render; what each tile shows is printed, for the captions.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import bpy
import numpy as np

from lab.kit.rigged_heads import default_jaw_bone_character, rigify_face_character
from tools.figures.speaking_strip import BACKGROUND, face_of, letter_frames, rendered, save_jpeg
from turkish_lipsync.blender import face_rig, heads, linking, shapekeys
from turkish_lipsync.blender.generate import generate
from turkish_lipsync.core.faces.rig_mappings import OwnRig

FPS = 25
TEXT = "Merhaba, benim adım Erdem. Bu sabah babamı gördüm, bir de vapura binip geçtim."
SENTENCE_WORDS = 1  # the letters of "Merhaba" make the strip's second row


def moments(result) -> list[tuple[int, str]]:
    """Scene frames of the open mouth, a closed b/m/p, a blink, a look aside and the head turned."""
    tracks = result.tracks
    frames = np.arange(tracks.frame_count, dtype=np.float64)
    names, values = tracks.sample(frames)
    opened = values[:, names.index("TR_viseme_a")]
    closed = sum(values[:, names.index(n)] for n in names if n.startswith(("TR_viseme_bp", "TR_viseme_m")))
    motion = tracks.head_and_eyes
    blink = values[:, names.index("TR_blink_left")]
    scores = [
        (opened, "the open mouth (a)"),
        (closed, "closed lips (b, m, p)"),
        (blink, "a blink"),
        (np.abs(motion.left_eye[:, 0]) / 10 - blink, "a look aside"),
        (np.hypot(motion.head[:, 0], motion.head[:, 2]) / 5 - blink, "the head turned"),
    ]
    picks: list[tuple[int, str]] = []
    for score, label in scores:  # each at its best frame a few frames from those already shown
        taken = np.zeros(len(frames), bool)
        for frame, _label in picks:
            taken[max(0, frame - 6) : frame + 7] = True
        picks.append((int(np.argmax(np.where(taken, -np.inf, score))), label))
    return [(result.frame_start + frame, label) for frame, label in picks]


def sheet_of(context, head, result, args, folder: str, name: str) -> np.ndarray:
    """Two rows of faces: the moments, then the letters of the first words."""
    rows = []
    for chosen in (moments(result), [pair for row in letter_frames(result, SENTENCE_WORDS) for pair in row]):
        tiles = []
        for frame, label in chosen:
            tiles.append(face_of(rendered(context, head, frame, args.size, args.samples, folder)))
            print(f"{name}, frame {frame}: {label}", flush=True)
        rows.append(_scaled_row(tiles, args.tile))
    width = max(row.shape[1] for row in rows)
    padded = [np.pad(r, ((0, 0), (0, width - r.shape[1]), (0, 0)), constant_values=BACKGROUND) for r in rows]
    return np.concatenate(padded, axis=0)


def _scaled_row(tiles: list[np.ndarray], height: int) -> np.ndarray:
    """The tiles side by side, each resized (nearest pixel) to the given height."""
    scaled = []
    for tile in tiles:
        rows = np.linspace(0, tile.shape[0] - 1, height).round().astype(int)
        columns = np.linspace(0, tile.shape[1] - 1, round(tile.shape[1] * height / tile.shape[0])).round()
        scaled.append(tile[rows][:, columns.astype(int)])
    return np.concatenate(scaled, axis=1)


def _scene() -> bpy.types.Context:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.render.fps = FPS
    return bpy.context


def jaw_bone_picture(args, folder: str) -> np.ndarray:
    context = _scene()
    character = default_jaw_bone_character(context)
    shapekeys.build_shape_keys(character["head"])  # its lids blink by keys; the jaw is the bone's
    face_rig.store_setup(character["armature"], OwnRig("jaw_bone"))
    result = generate(context, TEXT, audio_folder=folder, head=character["head"])
    return sheet_of(context, character["head"], result, args, folder, "jaw bone")


def rigify_picture(args, folder: str) -> np.ndarray:
    context = _scene()
    character = rigify_face_character(context)
    face_rig.store_setup(character["rig"], OwnRig("rigify_face"))
    result = generate(context, TEXT, audio_folder=folder, head=character["head"])
    return sheet_of(context, character["head"], result, args, folder, "Rigify face")


def linked_picture(args, folder: str) -> np.ndarray:
    """The default head saved in a character file of its own, linked into a shot, overridden, speaking."""
    context = _scene()
    parts = heads.create_reference_head(context)
    shapekeys.build_shape_keys(parts["head"])
    linking.make_keys_linkable(parts["head"], heads.find_head_parts(parts["head"]))
    collection = bpy.data.collections.new("Character")
    context.scene.collection.children.link(collection)
    for obj in list(context.scene.collection.objects):
        collection.objects.link(obj)
        context.scene.collection.objects.unlink(obj)
    character = Path(folder) / "character.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(character))
    context = _scene()
    with bpy.data.libraries.load(str(character), link=True) as (_source, target):
        target.collections = ["Character"]
    linked = target.collections[0]
    context.scene.collection.children.link(linked)
    linked.override_hierarchy_create(context.scene, context.view_layer, do_fully_editable=False)
    if linked.name in context.scene.collection.children:  # the override stands in for the linked one
        context.scene.collection.children.unlink(linked)
    bpy.ops.wm.save_as_mainfile(filepath=str(Path(folder) / "shot.blend"))
    head = bpy.data.objects["TR_Head"]  # the override, not the linked head
    result = generate(context, TEXT, audio_folder=folder, head=head)
    return sheet_of(context, head, result, args, folder, "linked, in a shot")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--folder", type=Path, default=Path("docs/images"))
    parser.add_argument("--tile", type=int, default=150, help="each face's height in the sheet, pixels")
    parser.add_argument("--size", type=int, default=240, help="the square render each face is cut from")
    parser.add_argument("--samples", type=int, default=8)
    args = parser.parse_args()
    for name, picture in (
        ("jaw_bone_character.jpg", jaw_bone_picture),
        ("rigify_face.jpg", rigify_picture),
        ("linked_shot.jpg", linked_picture),
    ):
        with tempfile.TemporaryDirectory() as folder:
            save_jpeg(picture(args, folder), args.folder / name)
        print(f"wrote {args.folder / name}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
