"""A contact strip of a head speaking with gaze, blinks and head motion: docs/images/living_face.png.

    .venv/bin/python -m tools.figures.living_preview [--out docs/images/living_face.png] [--size 240]
        [--samples 8]
        [--head PATH [--head PATH ...] [--object NAME] [--own-keys-at-rest]]   (default: the default head)

A row for each head (docs/images/living_heads.jpg: --head default and each shared head, --own-keys-at-rest
--size 200 --samples 6). Generates a few sentences at 25 fps on each head, picks frames that show eye
contact, a look away, a blink and the head turned, renders them with Cycles on the CPU and lays them side by
side; the labels (what the tracks say at that frame) are printed.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import bpy
import numpy as np

from turkish_lipsync.blender import heads, pipeline
from turkish_lipsync.blender.generate import generate
from turkish_lipsync.core.base.model import BLINK_KEYS
from turkish_lipsync.core.pipeline import LipSyncOptions

TEXT = "Merhaba, benim adım Erdem. Bugün hava çok güzel, parka gidip yürüyelim mi? Sonra eve döneriz."


def chosen_frames(tracks) -> list[tuple[int, str]]:
    motion = tracks.head_and_eyes
    frames = np.arange(tracks.frame_count)
    names, values = tracks.sample(frames.astype(float))
    blink = values[:, names.index(BLINK_KEYS[0])]
    gaze = np.hypot(motion.left_eye[:, 0], motion.left_eye[:, 1])
    turn = np.hypot(motion.head[:, 0], motion.head[:, 2])
    picks = [
        (int(np.argmin(gaze + 10 * blink)), "eye contact"),
        (int(np.argmax(np.abs(motion.left_eye[:, 0]) - 10 * blink)), "looking aside"),
        (int(np.argmax(blink)), "blink"),
        (int(np.argmax(turn - 10 * blink)), "head turned and tilted"),
        (int(np.argmax(motion.left_eye[:, 1] * -1 - 10 * blink)), "looking down (lids follow)"),
    ]
    return picks


def strip_of(head_path: Path | None, args) -> np.ndarray:
    """A row of tiles: the head (ours where head_path is None) built, speaking, rendered at chosen frames."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    context = bpy.context
    scene = context.scene
    scene.render.fps = 25
    scene.render.resolution_x = scene.render.resolution_y = args.size
    head = None
    if head_path is not None:
        imported = heads.import_head(head_path)
        head = bpy.data.objects[args.object] if args.object else heads.find_head(imported)
        if args.own_keys_at_rest:
            pipeline.put_own_keys_at_rest(head)
    head = bpy.data.objects[pipeline.build_keys(context, head).head]
    pipeline.frame_head(scene, head)
    tiles = []
    with tempfile.TemporaryDirectory() as folder:
        result = generate(context, TEXT, LipSyncOptions(), audio_folder=folder, head=head)
        for frame, label in chosen_frames(result.tracks):
            path = pipeline.render_still(
                context,
                head,
                str(Path(folder) / f"{frame}.png"),
                frame=result.frame_start + frame,
                engine="CYCLES",
                samples=args.samples,
                resolution=(args.size, args.size),
            )
            image = bpy.data.images.load(path)
            pixels = np.empty(args.size * args.size * 4, np.float32)
            image.pixels.foreach_get(pixels)
            tiles.append(pixels.reshape(args.size, args.size, 4))
            print(f"{head.name}, frame {frame}: {label}", flush=True)
    return np.concatenate(tiles, axis=1)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("docs/images/living_face.png"))
    parser.add_argument("--size", type=int, default=240)
    parser.add_argument("--samples", type=int, default=8)
    parser.add_argument(
        "--head",
        type=Path,
        action="append",
        help="a head file (.glb .obj .fbx .blend) instead of ours; again for a row each ('default': ours)",
    )
    parser.add_argument("--object", help="the head's object where the file holds several meshes")
    parser.add_argument(
        "--own-keys-at-rest", action="store_true", help="set the heads' own held shape keys to 0"
    )
    args = parser.parse_args()
    chosen = args.head or [Path("default")]
    rows = [strip_of(None if str(path) == "default" else path, args) for path in chosen]
    # Blender's pixels start at the bottom row: the first head's row goes on top.
    sheet = np.concatenate(rows[::-1], axis=0)
    out = bpy.data.images.new("strip", sheet.shape[1], sheet.shape[0])
    out.pixels.foreach_set(sheet.ravel())
    args.out.parent.mkdir(parents=True, exist_ok=True)
    out.filepath_raw = str(args.out.resolve())
    out.file_format = "JPEG" if args.out.suffix.lower() in (".jpg", ".jpeg") else "PNG"
    out.save()
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
