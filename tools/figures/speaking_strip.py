"""The default head speaking a sentence, for the manual: a strip of frames, one per letter, and an animation.

    nice -n 10 .venv/bin/python -m tools.figures.speaking_strip [--strip docs/images/speaking_strip.jpg]
        [--animation docs/images/speaking.webp] [--text TEXT] [--words 2] [--tile 150] [--size 240]

The strip shows the frame in the middle of each letter of the first --words words, left to right (a row
per word, Cycles on the CPU); the letters are printed, for the caption. The animation is every frame of
the sentence as an animated WebP that loops (no sound), for the README. Both use the default head and its
defaults (natural motion, the living face on, 25 fps).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import bpy
import numpy as np

from turkish_lipsync.blender import pipeline
from turkish_lipsync.blender.generate import generate
from turkish_lipsync.core.pipeline import LipSyncOptions

FPS = 25
TEXT = "Merhaba, benim adım Erdem."
# The part of a frame (left, top, right, bottom, as shares of its side) the strip keeps: the face from the
# eyes to the chin, as pipeline.frame_head frames the default head.
FACE_BOX = (0.26, 0.42, 0.74, 0.9)
BACKGROUND = 52  # the grey of the renders' background, for the strip's empty places


def rendered(context, head, frame: int, size: int, samples: int, folder: str) -> np.ndarray:
    """One frame as RGB rows from the top, values 0..255."""
    path = pipeline.render_still(
        context,
        head,
        str(Path(folder) / f"{frame}.png"),
        frame=frame,
        engine="CYCLES",
        samples=samples,
        resolution=(size, size),
    )
    image = bpy.data.images.load(path)
    pixels = np.empty(size * size * 4, np.float32)
    image.pixels.foreach_get(pixels)
    bpy.data.images.remove(image)
    rgb = pixels.reshape(size, size, 4)[::-1, :, :3]  # Blender's rows start at the bottom
    return (np.clip(rgb, 0.0, 1.0) * 255 + 0.5).astype(np.uint8)


def face_of(frame: np.ndarray) -> np.ndarray:
    """The face of a rendered frame: FACE_BOX of it."""
    side = frame.shape[0]
    left, top, right, bottom = (round(share * side) for share in FACE_BOX)
    return frame[top:bottom, left:right]


def letter_frames(result, words: int) -> list[list[tuple[int, str]]]:
    """Per word, (frame, letter) in the middle of each of its letters."""
    rows: list[list[tuple[int, str]]] = [[] for _ in range(words)]
    for phone in result.timeline.phones:
        if phone.word_index < words:
            middle = (phone.start + phone.end) / 2
            rows[phone.word_index].append((result.frame_start + round(middle * result.fps), phone.letter))
    return rows


def save_jpeg(rgb: np.ndarray, out: Path) -> None:
    height, width, _ = rgb.shape
    image = bpy.data.images.new("strip", width, height)
    rgba = np.concatenate(
        (rgb[::-1].astype(np.float32) / 255, np.ones((height, width, 1), np.float32)), axis=2
    )
    image.pixels.foreach_set(rgba.ravel())
    out.parent.mkdir(parents=True, exist_ok=True)
    image.filepath_raw = str(out.resolve())
    image.file_format = "JPEG"
    bpy.context.scene.render.image_settings.quality = 85
    image.save()


def save_webp(frames: list[np.ndarray], out: Path, fps: float) -> None:
    import av

    out.parent.mkdir(parents=True, exist_ok=True)
    with av.open(str(out), "w", format="webp", options={"loop": "0"}) as container:
        stream = container.add_stream("libwebp_anim", rate=round(fps))
        stream.height, stream.width = frames[0].shape[:2]
        stream.pix_fmt = "yuv420p"
        stream.options = {"quality": "60"}
        for frame in frames:
            for packet in stream.encode(av.VideoFrame.from_ndarray(frame, format="rgb24")):
                container.mux(packet)
        for packet in stream.encode(None):
            container.mux(packet)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--strip", type=Path, help="the strip of frames, one per letter (.jpg)")
    parser.add_argument("--animation", type=Path, help="the sentence as an animated WebP (.webp)")
    parser.add_argument("--text", default=TEXT)
    parser.add_argument("--words", type=int, default=2, help="words of the strip, a row each")
    parser.add_argument("--tile", type=int, default=150, help="pixels per frame of the strip")
    parser.add_argument("--size", type=int, default=240, help="pixels per frame of the animation")
    parser.add_argument("--samples", type=int, default=8)
    args = parser.parse_args()
    if args.strip is None and args.animation is None:
        parser.error("give --strip, --animation or both")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    context = bpy.context
    context.scene.render.fps = FPS
    head = bpy.data.objects[pipeline.build_keys(context, None).head]
    with tempfile.TemporaryDirectory() as folder:
        result = generate(context, args.text, LipSyncOptions(), audio_folder=folder, head=head)
        if args.strip is not None:
            rows = letter_frames(result, args.words)
            width = max(len(row) for row in rows)
            side = round(args.tile / (FACE_BOX[2] - FACE_BOX[0]))  # rendered so that the face is a tile
            strip = np.full((len(rows) * args.tile, width * args.tile, 3), BACKGROUND, np.uint8)
            for row_index, row in enumerate(rows):
                for column, (frame, _) in enumerate(row):
                    tile = face_of(rendered(context, head, frame, side, args.samples, folder))
                    top, left = row_index * args.tile, column * args.tile
                    strip[top : top + args.tile, left : left + args.tile] = tile
                print("letters:", " ".join(letter for _, letter in row), flush=True)
            save_jpeg(strip, args.strip)
            print(f"wrote {args.strip}")
        if args.animation is not None:
            frames = [
                rendered(context, head, frame, args.size, args.samples, folder)
                for frame in range(result.frame_start, result.frame_end + 1)
            ]
            save_webp(frames, args.animation, result.fps)
            print(f"wrote {args.animation} ({len(frames)} frames)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
