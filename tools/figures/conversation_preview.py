"""A strip of frames of the default cast in conversation: docs/images/conversation_strip.jpg.

    .venv/bin/python -m tools.figures.conversation_preview [--out docs/images/conversation_strip.jpg]
        [--width 480] [--samples 8] [--script examples/conversation.txt] [--three examples/...]

Generates the script's scene (a default head per speaker, the two-shot camera) at 25 fps and renders, with
Cycles on the CPU, frames that show what the characters do: each speaking with its mouth open while the
other looks at it, a listener's nod at the speaker's phrase end, a speaker looking away as a turn starts;
a second row does the same for three characters. The labels (what the tracks say at that frame) are printed.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import bpy
import numpy as np

from tools import REPOSITORY
from turkish_lipsync.blender import pipeline
from turkish_lipsync.blender.generate import generate
from turkish_lipsync.core.base.model import viseme_key_name
from turkish_lipsync.core.pipeline import LipSyncOptions
from turkish_lipsync.core.text.script import read_script


def chosen_frames(result) -> list[tuple[int, str]]:
    """Frames (from the scene's first) worth showing, with what they show."""
    speech = result.scene.speech
    fps = result.fps
    picks = []
    for character in result.scene.characters[:2]:
        tracks = character.tracks
        names, weights = tracks.sample(np.arange(tracks.frame_count, dtype=float))
        open_mouth = weights[:, names.index(viseme_key_name("a"))]
        own = np.zeros(tracks.frame_count, bool)
        for line in speech.lines:
            if line.speaker == character.role.key:
                own[int(line.first_phone * fps) : int(line.last_phone * fps)] = True
        frame = int(np.argmax(np.where(own, open_mouth, -1)))
        picks.append((frame, f"{character.role.name} speaking, the others looking at {character.role.name}"))
    for character in result.scene.characters[:1]:
        pitch = character.tracks.head_and_eyes.head[:, 1]
        listening = np.zeros(len(pitch), bool)
        for start, end, mode, _target in character.tracks.extra["attention"]:
            if mode == "listening":
                listening[int(start * fps) : int(end * fps)] = True
        baseline = np.convolve(pitch, np.ones(int(fps)) / int(fps), "same")
        frame = int(np.argmin(np.where(listening, pitch - baseline, np.inf)))
        picks.append((frame, f"{character.role.name} nodding at a phrase end"))
    speaker = result.scene.characters[-1]
    eyes = speaker.tracks.head_and_eyes.left_eye
    speaking = np.zeros(len(eyes), bool)
    for start, end, mode, _target in speaker.tracks.extra["attention"]:
        if mode == "speaking":
            speaking[int(start * fps) : int(end * fps)] = True
    away = np.abs(eyes[:, 1])  # the faces are level with each other: a look up or down is a look away
    picks.append(
        (int(np.argmax(np.where(speaking, away, -1))), f"{speaker.role.name} looking away as it speaks")
    )
    return picks


def row_of(script_path: Path, args, folder: str) -> np.ndarray:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    context = bpy.context
    scene = context.scene
    scene.render.fps = 25
    width, height = args.width, args.width * 5 // 12  # wide: the faces side by side, little sky
    scene.render.resolution_x, scene.render.resolution_y = width, height
    script = read_script(script_path.read_text(encoding="utf-8"))
    result = generate(context, script.source, LipSyncOptions(), audio_folder=folder)
    first_head = bpy.data.objects[next(iter(result.heads.values()))]
    tiles = []
    for frame, label in chosen_frames(result):
        path = pipeline.render_still(
            context,
            first_head,
            str(Path(folder) / f"{script_path.stem}_{frame}.png"),
            frame=result.frame_start + frame,
            engine="CYCLES",
            samples=args.samples,
            resolution=(width, height),
        )
        image = bpy.data.images.load(path)
        pixels = np.empty(width * height * 4, np.float32)
        image.pixels.foreach_get(pixels)
        tiles.append(pixels.reshape(height, width, 4))
        print(f"{script_path.name}, frame {frame} ({frame / result.fps:.2f} s): {label}", flush=True)
    return np.concatenate(tiles, axis=1)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=REPOSITORY / "docs" / "images" / "conversation_strip.jpg")
    parser.add_argument("--width", type=int, default=480)
    parser.add_argument("--samples", type=int, default=8)
    parser.add_argument("--script", type=Path, default=REPOSITORY / "examples" / "conversation.txt")
    parser.add_argument("--three", type=Path, default=REPOSITORY / "examples" / "conversation_three.txt")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        rows = [row_of(args.script, args, folder), row_of(args.three, args, folder)]
    # Blender's pixels start at the bottom row: the first row goes on top.
    sheet = np.concatenate(rows[::-1], axis=0)
    out = bpy.data.images.new("strip", sheet.shape[1], sheet.shape[0])
    out.pixels.foreach_set(sheet.ravel())
    args.out.parent.mkdir(parents=True, exist_ok=True)
    out.filepath_raw = str(args.out.resolve())
    out.file_format = "JPEG"
    out.save()
    print(f"wrote {args.out} ({args.out.stat().st_size // 1024} KB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
