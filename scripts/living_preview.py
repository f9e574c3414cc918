"""A contact strip of a head speaking with gaze, blinks and head motion: docs/living_face.png.

    .venv/bin/python scripts/living_preview.py [--out docs/living_face.png] [--size 240] [--samples 8]
        [--head PATH [--object NAME] [--own-keys-at-rest]]   (default: the default head)

Generates a few sentences at 25 fps on the default head, picks frames that show eye contact, a look away,
a blink and the head turned, renders them with Cycles on the CPU and lays them side by side, labelled
underneath by what the tracks say at that frame.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from turkish_lipsync.blender import heads, pipeline  # noqa: E402
from turkish_lipsync.core.base.model import BLINK_KEYS  # noqa: E402
from turkish_lipsync.core.pipeline import LipSyncOptions  # noqa: E402

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


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("docs/living_face.png"))
    parser.add_argument("--size", type=int, default=240)
    parser.add_argument("--samples", type=int, default=8)
    parser.add_argument("--head", type=Path, help="a head file (.glb .obj .fbx .blend) instead of ours")
    parser.add_argument("--object", help="the head's object where the file holds several meshes")
    parser.add_argument(
        "--own-keys-at-rest", action="store_true", help="set the head's own held shape keys to 0"
    )
    args = parser.parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    context = bpy.context
    scene = context.scene
    scene.render.fps = 25
    scene.render.resolution_x = scene.render.resolution_y = args.size
    head = None
    if args.head is not None:
        imported = heads.import_head(args.head)
        head = bpy.data.objects[args.object] if args.object else heads.find_head(imported)
        if args.own_keys_at_rest:
            pipeline.put_own_keys_at_rest(head)
    head = bpy.data.objects[pipeline.build_keys(context, head).head]
    pipeline.frame_head(scene, head)
    tiles = []
    with tempfile.TemporaryDirectory() as folder:
        result = pipeline.generate(context, head, TEXT, LipSyncOptions(), audio_folder=folder)
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
            pixels = np.array(image.pixels[:], dtype=np.float32).reshape(args.size, args.size, 4)
            tiles.append(pixels)
            print(f"frame {frame}: {label}", flush=True)
    strip = np.concatenate(tiles, axis=1)
    out = bpy.data.images.new("strip", strip.shape[1], strip.shape[0])
    out.pixels.foreach_set(strip.ravel())
    args.out.parent.mkdir(parents=True, exist_ok=True)
    out.filepath_raw = str(args.out.resolve())
    out.file_format = "PNG"
    out.save()
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
