"""Batch lip sync: Turkish text in, a head speaking it out (MP4 with sound and/or a .blend).

Runs inside Blender and with the bpy module:

    blender -b -P scripts/render.py -- --text "Merhaba" --out out/merhaba.mp4
    python scripts/render.py --jsml examples/demo.jsml --out out/demo.mp4 --save-blend out/demo.blend
    python scripts/render.py --audio take.wav --out out/take.mp4   # no text: what the take says is recognised

On any error it prints one line and exits non-zero. Given a .blend with --head, it changes only the TR_* keys,
their F-curves, the TR_speech strip and the frame range (plus camera and lights only where there are none).

On a render farm (farm/flamenco/turkish_lipsync.js), each worker renders a chunk of the saved .blend and one
task joins the chunks with the speech, copying the video (the join needs PyAV, not Blender):

    blender -b saved.blend -P scripts/render.py -- --frames 1-50 --engine cycles --out chunks/0001-0050.mp4
    python scripts/render.py --join chunks/0001-0050.mp4 chunks/0051-0100.mp4 --audio speech.wav --out out.mp4
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

REPOSITORY = Path(__file__).resolve().parent.parent
if str(REPOSITORY) not in sys.path:
    sys.path.insert(0, str(REPOSITORY))

from turkish_lipsync.core.base.errors import LipSyncError  # noqa: E402  (the core needs no bpy)
from turkish_lipsync.core.cli import add_living_arguments, living_option_values  # noqa: E402
from turkish_lipsync.core.faces.key_sources import KEY_SOURCE_CHOICES, RHO_RANGE  # noqa: E402
from turkish_lipsync.core.pipeline import (  # noqa: E402
    INTERPOLATION_CHOICES,
    MOTION_CHOICES,
    TIMING_CHOICES,
    LipSyncOptions,
    identifiers,
)

DEFAULT_RESOLUTION = (960, 540)
DEFAULT_FPS = 25.0


class OneLineArgumentParser(argparse.ArgumentParser):
    def error(self, message: str):  # one clear line instead of usage + message
        print(f"render.py: error: {message} (see --help)", file=sys.stderr)
        sys.exit(2)


def _resolution(text: str) -> tuple[int, int]:
    try:
        width, height = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"resolution {text!r} is not WIDTHxHEIGHT, e.g. 960x540") from None
    if not (16 <= width <= 8192 and 16 <= height <= 8192):
        raise argparse.ArgumentTypeError(f"resolution {text!r} must be between 16 and 8192 on each side")
    return width, height


def _fps(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"frame rate {text!r} is not a number, e.g. 25 or 29.97") from None
    if not 1 <= value <= 240:
        raise argparse.ArgumentTypeError(f"frame rate {text!r} must be between 1 and 240")
    return value


def _positive(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} must be at least 1")
    return value


def _frame_range(text: str) -> tuple[int, int]:
    """START-END (or one frame), as Flamenco's frame chunker writes them."""
    first, _, last = text.partition("-")
    try:
        start, end = int(first), int(last or first)
    except ValueError:
        raise argparse.ArgumentTypeError(f"frames {text!r} are not START-END, e.g. 1-50") from None
    if end < start:
        raise argparse.ArgumentTypeError(f"frames {text!r} end before they start")
    return start, end


def _export(text: str) -> tuple[str, Path]:
    from turkish_lipsync.core.interchange import export_formats

    export_format, _, path = text.partition("=")
    if export_format not in export_formats() or not path:
        raise argparse.ArgumentTypeError(
            f"--export {text!r} is not FORMAT=PATH with FORMAT one of {', '.join(export_formats())}"
        )
    return export_format, Path(path)


def parse_arguments(argv: list[str]) -> argparse.Namespace:
    parser = OneLineArgumentParser(prog="render.py", description=__doc__.split("\n\n")[0])
    source = parser.add_mutually_exclusive_group()
    source.add_argument("--text", help="Turkish text to speak (plain or JSML)")
    source.add_argument("--jsml", type=Path, help="a UTF-8 file with Turkish text (plain or JSML)")
    parser.add_argument(
        "--head", type=Path, help="head file: .obj .glb .gltf .fbx or .blend (default: reference)"
    )
    parser.add_argument("--out", type=Path, help="the MP4 to render (H.264 + AAC)")
    parser.add_argument("--save-blend", type=Path, help="save the animated scene to this .blend")
    parser.add_argument(
        "--engine",
        default="auto",
        type=str.lower,
        choices=("auto", "eevee", "cycles", "workbench"),
        help="render engine (auto: EEVEE with OpenGL, else Cycles)",
    )
    parser.add_argument(
        "--resolution", type=_resolution, help="WIDTHxHEIGHT (default 960x540 for new scenes)"
    )
    parser.add_argument("--fps", type=_fps, help="frame rate, fractional allowed (default 25 for new scenes)")
    defaults = LipSyncOptions()
    parser.add_argument("--timing", default=defaults.timing, choices=identifiers(TIMING_CHOICES))
    parser.add_argument("--motion", default=defaults.motion, choices=identifiers(MOTION_CHOICES))
    parser.add_argument(
        "--interpolation", default=defaults.interpolation, choices=identifiers(INTERPOLATION_CHOICES)
    )
    parser.add_argument("--emotion-strength", type=float, default=defaults.emotion_strength, help="0..1")
    parser.add_argument("--rate", type=float, default=defaults.rate, help="speaking-rate multiplier")
    parser.add_argument(
        "--audio",
        type=Path,
        help="a recording of the text (WAV, FLAC, OGG) to use instead of eSpeak; without --text or --jsml, "
        "what it says is recognised from the audio",
    )
    add_living_arguments(parser)
    parser.add_argument(
        "--gaze-target", metavar="OBJECT", help="the object the eyes seek (default: the scene's camera)"
    )
    parser.add_argument(
        "--arkit-keys", action="store_true", help="also keep the 52 ARKit unit keys on the head"
    )
    parser.add_argument("--rebuild-keys", action="store_true", help="rebuild the TR_* keys even if present")
    parser.add_argument(
        "--own-keys-at-rest",
        action="store_true",
        help="set the head's own shape keys that hold a value (and are not animated) to 0 before speaking",
    )
    parser.add_argument(
        "--key-source",
        default="auto",
        choices=identifiers(KEY_SOURCE_CHOICES),
        help="what the keys are built from (auto: the head's own visemes or ARKit keys, else a transfer)",
    )
    parser.add_argument(
        "--obj-folder", type=Path, help="with --key-source obj_folder: the thesis's OBJ models (a.obj, ...)"
    )
    parser.add_argument(
        "--empowered",
        action="store_true",
        help="store the emotion keys empowered (thesis eq. 5.2), for keying them by hand",
    )
    parser.add_argument(
        "--rho", type=float, default=3.0, help="the empowering constant of eq. 5.2 (the thesis uses 3)"
    )
    parser.add_argument(
        "--audio-folder",
        type=Path,
        help="where the speech WAV goes (default: lipsync_audio beside the output)",
    )
    parser.add_argument("--no-render", action="store_true", help="only animate (and save with --save-blend)")
    parser.add_argument("--samples", type=_positive, help="render samples per pixel (default 16)")
    parser.add_argument(
        "--still", type=Path, help="also render one frame to this PNG (widest mouth by default)"
    )
    parser.add_argument("--still-frame", type=int, help="the frame for --still")
    parser.add_argument(
        "--cues",
        type=Path,
        help="time the visemes by a Rhubarb .tsv/.json/.xml, Papagayo .pgo or Moho .dat file (a .pgo brings "
        "its own text; --audio is then the sound as it is)",
    )
    parser.add_argument(
        "--export",
        type=_export,
        action="append",
        default=[],
        metavar="FORMAT=PATH",
        help="also write the animation for other tools (repeatable): rhubarb-tsv, rhubarb-json, rhubarb-xml, "
        "moho-dat, papagayo-pgo, arkit-csv",
    )
    parser.add_argument(
        "--gltf",
        type=Path,
        help="also write the head and its speech animation as .glb, the speech WAV beside it",
    )
    parser.add_argument(
        "--mapping",
        type=Path,
        help="a TOML file naming the head's own keys for the Turkish visemes (README: heads with visemes of "
        "their own)",
    )
    parser.add_argument(
        "--frames",
        type=_frame_range,
        metavar="START-END",
        help="farm chunk: render only these frames of the saved .blend (--head, or the file Blender opened) "
        "to --out (.mp4/.mkv: lossless video without sound; otherwise a folder of PNG frames)",
    )
    parser.add_argument(
        "--join",
        type=Path,
        nargs="+",
        metavar="CHUNK",
        help="join chunk videos in this order with the speech (--audio WAV) into --out, copying the video",
    )
    arguments = parser.parse_args(argv)
    if arguments.join or arguments.frames:
        _check_farm_arguments(parser, arguments)
        return arguments
    if all(getattr(arguments, name) is None for name in ("text", "jsml", "cues", "audio")):
        parser.error(
            "give the text: --text TEXT or --jsml FILE (or --cues with a Papagayo .pgo, or --audio REC alone "
            "to recognise what it says)"
        )
    if arguments.cues is not None and not arguments.cues.is_file():
        parser.error(f"--cues {arguments.cues} does not exist")
    if not arguments.no_render and arguments.out is None:
        parser.error("--out OUT.mp4 is required unless --no-render is given")
    if arguments.out is not None and arguments.out.suffix.lower() != ".mp4":
        parser.error(f"--out {arguments.out} must end in .mp4")
    if arguments.still is not None and arguments.still.suffix.lower() != ".png":
        parser.error(f"--still {arguments.still} must end in .png")
    if arguments.save_blend is not None and arguments.save_blend.suffix.lower() != ".blend":
        parser.error(f"--save-blend {arguments.save_blend} must end in .blend")
    if arguments.head is not None and not arguments.head.is_file():
        parser.error(f"--head {arguments.head} does not exist")
    if arguments.jsml is not None and not arguments.jsml.is_file():
        parser.error(f"--jsml {arguments.jsml} does not exist")
    if arguments.audio is not None and not arguments.audio.is_file():
        parser.error(f"--audio {arguments.audio} does not exist")
    if arguments.gltf is not None and arguments.gltf.suffix.lower() != ".glb":
        parser.error(f"--gltf {arguments.gltf} must end in .glb")
    if arguments.mapping is not None and not arguments.mapping.is_file():
        parser.error(f"--mapping {arguments.mapping} does not exist")
    if (arguments.key_source == "obj_folder") != (arguments.obj_folder is not None):
        parser.error("--key-source obj_folder and --obj-folder FOLDER go together")
    if arguments.obj_folder is not None and not arguments.obj_folder.is_dir():
        parser.error(f"--obj-folder {arguments.obj_folder} is not a folder")
    if not RHO_RANGE[0] <= arguments.rho <= RHO_RANGE[1]:
        parser.error(f"--rho {arguments.rho} must lie between {RHO_RANGE[0]:g} and {RHO_RANGE[1]:g}")
    arguments.engine = arguments.engine.upper()
    return arguments


def _check_farm_arguments(parser: argparse.ArgumentParser, arguments: argparse.Namespace) -> None:
    """--frames renders a chunk of a saved scene and --join joins chunks: neither speaks a text."""
    speech_flags = {
        "--text": arguments.text,
        "--jsml": arguments.jsml,
        "--cues": arguments.cues,
        "--export": arguments.export,
        "--gltf": arguments.gltf,
        "--mapping": arguments.mapping,
        "--arkit-keys": arguments.arkit_keys,
        "--rebuild-keys": arguments.rebuild_keys,
        "--own-keys-at-rest": arguments.own_keys_at_rest,
        "--key-source": arguments.key_source != "auto",
        "--obj-folder": arguments.obj_folder,
        "--empowered": arguments.empowered,
        "--audio-folder": arguments.audio_folder,
        "--save-blend": arguments.save_blend,
        "--still": arguments.still,
        "--gaze-target": arguments.gaze_target,
    }
    used = [flag for flag, value in speech_flags.items() if value]
    mode = "--join" if arguments.join else "--frames"
    if arguments.join and arguments.frames:
        parser.error("--frames renders a chunk and --join joins chunks: run them as separate tasks")
    if used:
        parser.error(f"{mode} works on a saved scene or rendered chunks; drop {', '.join(used)}")
    if arguments.out is None:
        parser.error(f"{mode} needs --out")
    if arguments.join:
        if arguments.out.suffix.lower() != ".mp4":
            parser.error(f"--out {arguments.out} must end in .mp4")
        missing = [str(chunk) for chunk in arguments.join if not chunk.is_file()]
        if missing:
            parser.error(f"--join: no such chunk {', '.join(missing)}")
        if arguments.audio is not None and not arguments.audio.is_file():
            parser.error(f"--audio {arguments.audio} does not exist")
    elif arguments.head is not None and arguments.head.suffix.lower() != ".blend":
        parser.error(f"--frames renders a saved scene: --head {arguments.head} must be a .blend")
    elif arguments.head is not None and not arguments.head.is_file():
        parser.error(f"--head {arguments.head} does not exist")
    arguments.engine = arguments.engine.upper()


def check_paths(arguments: argparse.Namespace) -> None:
    """No output of this run may replace one of its inputs or another of its outputs (checked first)."""
    from turkish_lipsync.core.base.files import check_distinct_paths, check_writable

    inputs = {
        "--jsml": arguments.jsml,
        "--audio": arguments.audio,
        "--head": arguments.head,
        "--cues": arguments.cues,
        "--mapping": arguments.mapping,
    }
    inputs |= {f"--join chunk {number}": chunk for number, chunk in enumerate(arguments.join or (), start=1)}
    outputs = {"--out": arguments.out, "--save-blend": arguments.save_blend, "--still": arguments.still}
    if arguments.gltf is not None:
        outputs |= {
            "--gltf": arguments.gltf,
            "the speech WAV beside --gltf": arguments.gltf.with_suffix(".wav"),
        }
    for number, (name, path) in enumerate(arguments.export, start=1):
        outputs[
            f"--export {name}" if f"--export {name}" not in outputs else f"--export {name} ({number})"
        ] = path
    check_distinct_paths(inputs, outputs)
    chunk_folder = arguments.frames and arguments.out.suffix.lower() not in (".mp4", ".mkv")
    for name, path in outputs.items():
        if path is not None and not (name == "--out" and chunk_folder):
            check_writable(path, f"output of {name}")


def script_arguments() -> list[str]:
    """Arguments after '--' inside Blender; all of them with the bpy module."""
    if "--" in sys.argv:
        return sys.argv[sys.argv.index("--") + 1 :]
    if Path(sys.argv[0]).resolve() == Path(__file__).resolve():
        return sys.argv[1:]
    return []


def set_frame_rate(scene, fps: float) -> None:
    """29.97 becomes fps 30 with base 1.001, as Blender's own presets store it."""
    whole = round(fps)
    scene.render.fps = whole
    scene.render.fps_base = 1.0 if abs(whole - fps) < 1e-6 else whole / fps


def _print_progress(fraction: float, message: str) -> None:
    print(f"[{fraction * 100:5.1f}%] {message}", flush=True)


def _print_warnings(warnings: tuple[str, ...]) -> None:
    for warning in warnings:
        print(f"render.py: warning: {warning}", file=sys.stderr, flush=True)


def run_join(arguments: argparse.Namespace) -> None:
    """Join rendered chunks with the speech, copying the video: no Blender needed."""
    from turkish_lipsync.core.interchange.video import join_videos

    if arguments.audio is None:
        _print_warnings(("no --audio given: the joined video is silent.",))
    joined = join_videos(arguments.join, arguments.out, arguments.audio)
    print(
        f"Joined {len(arguments.join)} chunks ({', '.join(map(str, joined.chunk_frames))} frames), "
        f"{joined.frame_count} frames, {joined.seconds:.2f} s, to {joined.path}",
        flush=True,
    )


def run_chunk(arguments: argparse.Namespace) -> None:
    """Render one frame range of a saved scene, as a farm worker does."""
    import bpy

    from turkish_lipsync.blender import farm, heads, pipeline
    from turkish_lipsync.core.base.errors import LipSyncError

    if arguments.head is not None:
        bpy.ops.wm.open_mainfile(filepath=str(arguments.head.resolve()))
    elif not bpy.data.filepath:
        raise LipSyncError(
            "--frames renders a saved scene: give it with --head SAVED.blend, or open it in Blender "
            "(blender -b SAVED.blend -P render.py -- --frames ...)"
        )
    context = bpy.context
    candidates = [o for o in context.scene.objects if o.type == "MESH" and pipeline.has_lipsync_keys(o)]
    head = candidates[0] if candidates else heads.find_head(context.scene.objects)
    first, last = arguments.frames
    chunk = farm.render_chunk(
        context,
        head,
        str(arguments.out),
        first,
        last,
        engine=arguments.engine,
        samples=arguments.samples,
        resolution=arguments.resolution,
        progress=_print_progress,
    )
    print(
        f"Rendered frames {chunk.first_frame}-{chunk.last_frame} with {chunk.engine} in "
        f"{chunk.seconds:.1f} s to {chunk.path}",
        flush=True,
    )


def write_exports(arguments: argparse.Namespace, context, head) -> None:
    """The --export files of the head's generated animation (the speech WAV named relative to each file)."""
    from turkish_lipsync.blender import exports

    for export_format, path in arguments.export:
        written = exports.export_animation(context, head, export_format, path)
        _print_warnings(written.warnings)
        print(f"Exported {export_format} to {written.path}", flush=True)


def run(arguments: argparse.Namespace) -> None:
    import bpy

    from turkish_lipsync.blender import heads, pipeline, sequencer
    from turkish_lipsync.core.base.errors import TextError
    from turkish_lipsync.core.base.files import read_user_text

    started = time.perf_counter()
    new_scene = arguments.head is None or arguments.head.suffix.lower() != ".blend"
    if new_scene:
        bpy.ops.wm.read_factory_settings(use_empty=True)
    else:
        bpy.ops.wm.open_mainfile(filepath=str(arguments.head.resolve()))
    context = bpy.context
    scene = context.scene
    if arguments.fps is not None:
        set_frame_rate(scene, arguments.fps)
    elif new_scene:
        set_frame_rate(scene, DEFAULT_FPS)
    if arguments.resolution is not None:
        scene.render.resolution_x, scene.render.resolution_y = arguments.resolution
    elif new_scene:
        scene.render.resolution_x, scene.render.resolution_y = DEFAULT_RESOLUTION

    if arguments.jsml is not None:
        source = read_user_text(arguments.jsml, "--jsml text", TextError)
    else:
        source = arguments.text or ""  # with --cues alone, the cue file's own text; with --audio, the heard

    if arguments.head is None:
        head = None
    elif new_scene:
        head = heads.find_head(heads.import_head(arguments.head))
    else:
        candidates = [obj for obj in scene.objects if obj.type == "MESH" and pipeline.has_lipsync_keys(obj)]
        head = candidates[0] if candidates else heads.find_head(scene.objects)
    rebuild = (
        arguments.rebuild_keys
        or arguments.arkit_keys
        or arguments.mapping is not None
        or arguments.key_source != "auto"
        or arguments.empowered
    )
    if head is None or rebuild or not pipeline.has_lipsync_keys(head):
        report = pipeline.build_keys(
            context,
            head,
            arkit_keys=arguments.arkit_keys,
            source=arguments.key_source,
            obj_folder=str(arguments.obj_folder) if arguments.obj_folder else None,
            mapping_file=str(arguments.mapping) if arguments.mapping else None,
            empowered=arguments.empowered,
            rho=arguments.rho,
            progress=_print_progress,
        )
        print(f"Built the shape keys on {report.head} from {report.convention or report.source}", flush=True)
        _print_warnings(report.warnings)
        head = bpy.data.objects[report.head]
    head_name = head.name

    if arguments.audio_folder is not None:
        audio_folder = str(arguments.audio_folder.resolve())
    elif arguments.save_blend is not None:
        audio_folder = str(arguments.save_blend.resolve().parent / "lipsync_audio")
    elif arguments.out is not None:
        audio_folder = str(arguments.out.resolve().parent / "lipsync_audio")
    else:
        audio_folder = ""

    if arguments.own_keys_at_rest:
        cleared = pipeline.put_own_keys_at_rest(bpy.data.objects[head_name])
        print(f"Set {cleared} of the head's own shape keys to 0", flush=True)
    result = pipeline.generate(
        context,
        bpy.data.objects[head_name],
        source,
        LipSyncOptions(
            timing=arguments.timing,
            motion=arguments.motion,
            interpolation=arguments.interpolation,
            emotion_strength=arguments.emotion_strength,
            rate=arguments.rate,
            recording=arguments.audio,
            cues=arguments.cues,
            **living_option_values(arguments),
        ),
        audio_folder=audio_folder,
        progress=_print_progress,
        gaze_target=arguments.gaze_target or "",
    )
    _print_warnings(result.warnings)
    print(
        f"Generated {result.phone_count} phones, {result.duration:.2f} s, frames {result.frame_start}-"
        f"{result.frame_end} at {result.fps:.3f} fps; audio: {result.wav_path or 'none'}",
        flush=True,
    )
    if arguments.export:
        write_exports(arguments, context, bpy.data.objects[head_name])
    if arguments.gltf is not None:
        from turkish_lipsync.blender.gltf_export import export_gltf

        exported = export_gltf(context, bpy.data.objects[head_name], arguments.gltf)
        print(
            f"Exported glTF to {exported.path} ({exported.morph_targets} morph targets); "
            f"speech: {exported.wav_path or 'none'}",
            flush=True,
        )
    if not arguments.no_render:
        rendered = pipeline.render_video(
            context,
            bpy.data.objects[head_name],
            str(arguments.out),
            engine=arguments.engine,
            samples=arguments.samples,
            resolution=arguments.resolution,
            progress=_print_progress,
        )
        print(
            f"Rendered {rendered.frame_count} frames with {rendered.engine} in {rendered.seconds:.1f} s "
            f"({rendered.seconds / max(1, rendered.frame_count):.2f} s/frame) to {rendered.path}",
            flush=True,
        )
    if arguments.still is not None:
        frame = arguments.still_frame
        if frame is not None and not scene.frame_start <= frame <= scene.frame_end:
            _print_warnings(
                (
                    f"--still-frame {frame} is outside the animation (frames {scene.frame_start}-"
                    f"{scene.frame_end}): the still shows the face at rest there.",
                )
            )
        still = pipeline.render_still(
            context,
            bpy.data.objects[head_name],
            str(arguments.still),
            frame=arguments.still_frame,
            engine=arguments.engine,
            samples=arguments.samples,
            resolution=arguments.resolution,
        )
        print(f"Rendered the still {still}", flush=True)
    if arguments.save_blend is not None:
        arguments.save_blend.parent.mkdir(parents=True, exist_ok=True)
        sequencer.relate_speech_to(scene, arguments.save_blend)
        bpy.ops.wm.save_as_mainfile(filepath=str(arguments.save_blend.resolve()))
        print(f"Saved {arguments.save_blend}", flush=True)
    print(f"Done in {time.perf_counter() - started:.1f} s", flush=True)


def main(argv: list[str] | None = None) -> int:
    arguments = parse_arguments(script_arguments() if argv is None else argv)
    try:
        check_paths(arguments)
        if arguments.join:
            run_join(arguments)
        elif arguments.frames:
            run_chunk(arguments)
        else:
            run(arguments)
    except LipSyncError as error:
        print(f"render.py: error: {error}", file=sys.stderr)
        return 1
    except ImportError as error:
        print(
            f"render.py: error: {error}. Run it with Blender or with the bpy module installed.",
            file=sys.stderr,
        )
        return 1
    except Exception as error:  # Blender's own failures (RuntimeError from operators, OSError, ...): one line
        message = " ".join(str(error).split())
        print(f"render.py: error: {type(error).__name__}: {message}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
