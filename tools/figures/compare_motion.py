"""Thesis motion and the default side by side: two reference heads speaking the same sentence in one video.

The left head moves by the thesis's eq. 5.3/5.4, the right one by the default co-articulation model.
The script prints the quality report of both modes (the numbers of `python -m turkish_lipsync quality`).

    python -m tools.figures.compare_motion --text "<HAPPY>Mehmet bey bu sabah vapura binip geçti.</HAPPY>" \\
        --out out/compare.mp4 [--fps 25] [--timing phone] [--engine auto] [--resolution 1280x540]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

MODES = ("thesis", "natural")
LABELS = {"thesis": "thesis (eq. 5.4)", "natural": "default (co-articulation)"}


def _arguments(argv: list[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="compare_motion.py", description=__doc__.splitlines()[0])
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--text", help="JSML or plain Turkish text")
    source.add_argument("--jsml", type=Path, help="a JSML or text file")
    parser.add_argument("--out", type=Path, default=Path("out/compare_motion.mp4"))
    parser.add_argument("--fps", type=float, default=25.0)
    parser.add_argument("--timing", choices=("phone", "word", "table"), default="phone")
    parser.add_argument("--engine", default="auto", help="auto, EEVEE, CYCLES or WORKBENCH")
    parser.add_argument("--resolution", default="1280x540", help="WIDTHxHEIGHT of the whole video")
    parser.add_argument("--samples", type=int, default=8, help="render samples per pixel (Cycles, EEVEE)")
    parser.add_argument("--save-blend", type=Path, help="also save the scene")
    parser.add_argument("--no-render", action="store_true", help="build the scene and print the report only")
    parser.add_argument("--format", choices=("text", "json"), default="text", help="of the quality report")
    if "--" in argv:
        argv = argv[argv.index("--") + 1 :]
    return parser.parse_args(argv)


def main(argv: list[str]) -> int:
    args = _arguments(argv)
    from turkish_lipsync.core.base.errors import LipSyncError
    from turkish_lipsync.core.cli import read_source
    from turkish_lipsync.core.motion.quality import format_quality, quality_report

    try:
        source = read_source(args.jsml, args.text)
        import bpy

        from turkish_lipsync.blender import heads, keyframes, render, sequencer, shapekeys
        from turkish_lipsync.blender.pipeline import head_objects
        from turkish_lipsync.core.motion import weight_tracks
        from turkish_lipsync.core.speech import synthesize_timeline, write_wav
        from turkish_lipsync.core.text.utterance import build_utterance

        speech = synthesize_timeline(build_utterance(source), args.timing)

        timeline, synthesis = speech.timeline, speech.synthesis
        tracks = {mode: weight_tracks(timeline, args.fps, mode=mode) for mode in MODES}
        report = {
            "thesis": quality_report(timeline, tracks["thesis"]),
            "default": quality_report(timeline, tracks["natural"]),
        }
        print(json.dumps(report, indent=1) if args.format == "json" else format_quality(report), flush=True)

        bpy.ops.wm.read_factory_settings(use_empty=True)
        context = bpy.context
        scene = context.scene
        scene.render.fps = round(args.fps)
        scene.render.fps_base = round(args.fps) / args.fps
        all_objects = []
        for position, mode in enumerate(MODES):
            print(f"Building the {LABELS[mode]} head ...", flush=True)
            parts = heads.create_reference_head(context, name=f"TR_Head_{mode}")
            head = parts["head"]
            shapekeys.build_shape_keys(head)
            objects = head_objects(head)
            # Thesis on the left, default on the right, a little more than a whole head (ears too) apart.
            head.location.x += (position - 0.5) * head.dimensions.x * 1.1
            context.view_layer.update()
            keyframes.write_weight_tracks(objects, tracks[mode], scene.frame_start, f"TR_compare_{mode}")
            all_objects += objects
        last_frame = scene.frame_start + max(t.frame_count for t in tracks.values()) - 1
        scene.frame_end = last_frame
        if synthesis is not None:
            wav_path = args.out.with_suffix(".wav")
            wav_path.parent.mkdir(parents=True, exist_ok=True)
            write_wav(wav_path, synthesis)
            sequencer.place_speech_strip(scene, wav_path, scene.frame_start, timeline.duration)
            scene.frame_end = last_frame
        render.frame_face(scene, all_objects)
        if args.save_blend:
            args.save_blend.parent.mkdir(parents=True, exist_ok=True)
            bpy.ops.wm.save_as_mainfile(filepath=str(args.save_blend.resolve()))
        if args.no_render:
            return 0
        width, height = (int(part) for part in args.resolution.lower().split("x"))
        engine = render.choose_engine(args.engine.upper())
        render.configure_engine(scene, engine, args.samples)
        render.configure_output(scene, args.out, (width, height))
        print(f"Rendering {scene.frame_end - scene.frame_start + 1} frames with {engine} ...", flush=True)
        bpy.ops.render.render(animation=True, scene=scene.name)
        from turkish_lipsync.blender import compat

        if synthesis is not None and not compat.HAS_AUDIO:
            render.mux_audio(args.out, args.out.with_suffix(".wav"))
        print(f"Wrote {args.out} (left: {LABELS['thesis']}, right: {LABELS['natural']})")
        return 0
    except (LipSyncError, OSError, ValueError) as error:
        print(f"compare_motion.py: error: {error}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
