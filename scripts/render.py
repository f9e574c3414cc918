"""Batch lip sync: Turkish text in, a head speaking it out (MP4 with sound and/or a .blend).

Runs inside Blender and with the bpy module:

    blender -b -P scripts/render.py -- --text "Merhaba" --out out/merhaba.mp4
    python scripts/render.py --jsml examples/demo.jsml --out out/demo.mp4 --save-blend out/demo.blend
    python scripts/render.py --audio take.wav --out out/take.mp4   # no text: what the take says is recognised

In a shot where a character is linked and library-overridden, --object names the head to animate (its
keys or face rig built in the character's own file): the file Blender opened, or --open with the bpy module:

    blender -b shot.blend -P scripts/render.py -- --object Head --jsml line.jsml --out line.mp4
    python scripts/render.py --open shot.blend --object Head --jsml line.jsml --out line.mp4

On any error it prints one line and exits non-zero. Given a .blend with --head, it changes only the TR_* keys,
their F-curves, the TR_speech strip and the frame range (plus camera and lights only where there are none).

On a render farm (farm/flamenco/turkish_lipsync.js), each worker renders a chunk of the saved .blend and one
task joins the chunks with the speech, copying the video (the join needs PyAV, not Blender):

    blender -b saved.blend -P scripts/render.py -- --frames 1-50 --engine cycles --out chunks/0001-0050.mp4
    python scripts/render.py --join chunks/0001-0050.mp4 chunks/0051-0100.mp4 --audio speech.wav --out out.mp4
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def import_beside(name: str, path: Path):
    """The module (or package, given its __init__.py) at path, imported as name: this script runs from a
    checkout or the extension's folder, inside Blender (-P) or with the bpy module, where neither is
    installed; the import path is left as it is."""
    if name not in sys.modules:
        folder = [str(path.parent)] if path.name == "__init__.py" else None
        spec = importlib.util.spec_from_file_location(name, path, submodule_search_locations=folder)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


import_beside("turkish_lipsync", HERE.parent / "turkish_lipsync" / "__init__.py")
render_arguments = import_beside("render_arguments", HERE / "render_arguments.py")
DEFAULT_FPS, DEFAULT_RESOLUTION = render_arguments.DEFAULT_FPS, render_arguments.DEFAULT_RESOLUTION
check_paths, parse_arguments = render_arguments.check_paths, render_arguments.parse_arguments

from turkish_lipsync.core.base.errors import LipSyncError  # noqa: E402  (the core needs no bpy)
from turkish_lipsync.core.cli import living_option_values  # noqa: E402
from turkish_lipsync.core.pipeline import LipSyncOptions  # noqa: E402


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


def run_one_head(arguments, context, scene, source: str, new_scene: bool, audio_folder: str) -> str:
    """One head speaks the text: built where it needs keys, generated, exported; returns its name."""
    import bpy

    from turkish_lipsync.blender import character, heads, pipeline
    from turkish_lipsync.blender.generate import generate

    if arguments.object is not None:
        head = named_head(arguments.object)
    elif arguments.head is None and arguments.open is None:
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
    if head is None or rebuild or character.speech_problem(head) is not None:
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

    if arguments.own_keys_at_rest:
        cleared = pipeline.put_own_keys_at_rest(bpy.data.objects[head_name])
        print(f"Set {cleared} of the head's own shape keys to 0", flush=True)
    result = generate(
        context,
        source,
        lip_sync_options(arguments),
        audio_folder=audio_folder,
        progress=_print_progress,
        gaze_target=arguments.gaze_target or "",
        head=bpy.data.objects[head_name],
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
    return head_name


def named_head(name: str):
    """The open file's head of that name (a library override of a linked one before the linked one)."""
    import bpy

    head = bpy.data.objects.get(name)
    if head is None or head.type != "MESH":
        meshes = ", ".join(sorted(obj.name for obj in bpy.context.scene.objects if obj.type == "MESH"))
        what = "no object" if head is None else f"a {head.type.lower()}, not the head mesh,"
        raise LipSyncError(f"--object {name!r}: the open file has {what} of that name; its meshes: {meshes}")
    return head


def open_the_scene(arguments: argparse.Namespace) -> bool:
    """A new scene, the .blend given (--open, --head), or the file Blender opened (with --object); returns
    whether the scene is new."""
    import bpy

    opened = arguments.open or (
        arguments.head if arguments.head and arguments.head.suffix.lower() == ".blend" else None
    )
    if opened is not None:
        bpy.ops.wm.open_mainfile(filepath=str(opened.resolve()))
        return False
    if arguments.object is not None and arguments.head is None:
        if not bpy.data.filepath:
            raise LipSyncError(
                "--object names a head of the open file: open it (blender -b SHOT.blend -P render.py -- ...) "
                "or give --open SHOT.blend"
            )
        return False
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return True


def speaker_choices(arguments: argparse.Namespace) -> dict:
    """What --cast, --voice, --speaker-emotion and --speaker-audio chose per speaker (by the speaker's key,
    so AYŞE and Ayşe are one)."""
    from dataclasses import replace

    from turkish_lipsync.core.scene import RoleChoice
    from turkish_lipsync.core.text.script import speaker_key

    choices: dict[str, RoleChoice] = {}
    names: dict[str, str] = {}

    def choose(name: str, **values) -> None:
        key = speaker_key(name)
        names.setdefault(key, name)
        choices[key] = replace(choices.get(key, RoleChoice()), **values)

    for name, head in arguments.cast:
        default = head.lower() == "default"
        choose(name, head="" if default else str(Path(head).resolve()) if Path(head).is_file() else head)
    for name, voice in arguments.voice:
        variant, *numbers = voice.split(":")
        chosen = (
            {"gender": variant.lower()} if variant.lower() in ("female", "male") else {"variant": variant}
        )
        if numbers:
            chosen["pitch"] = float(numbers[0])
        if len(numbers) > 1:
            chosen["rate"] = float(numbers[1])
        choose(name, **chosen)
    for name, value in arguments.speaker_emotion:
        choose(name, emotion_strength=arguments.emotion_strength * float(value))
    for name, path in arguments.speaker_audio:
        choose(name, recording=Path(path))
    return {names[key]: choice for key, choice in choices.items()}


def scene_sources(arguments: argparse.Namespace):
    """Where a script's speech comes from: --audio (the whole scene), --line-audio, --cues, or the engine."""
    from turkish_lipsync.core.scene.speech import SceneSources, line_recordings_in

    return SceneSources(
        scene_recording=arguments.audio,
        line_recordings=line_recordings_in(arguments.line_audio) if arguments.line_audio else (),
        cues=arguments.cues,
    )


def run_conversation(arguments: argparse.Namespace, context, script, audio_folder: str) -> list[str]:
    """Every speaker of the script played by its head: generated, exported; returns the heads' names."""
    from turkish_lipsync.blender import conversation, exports
    from turkish_lipsync.blender.generate import generate

    result = generate(
        context,
        script.source,
        lip_sync_options(arguments),
        sources=scene_sources(arguments),
        audio_folder=audio_folder,
        progress=_print_progress,
        choices=speaker_choices(arguments),
    )
    _print_warnings(result.warnings)
    cast = ", ".join(f"{name} by {head}" for name, head in result.heads.items())
    print(
        f"Generated {len(script.lines)} lines of {len(result.heads)} characters ({cast}), "
        f"{result.duration:.2f} s, frames {result.frame_start}-{result.frame_end} at {result.fps:.3f} fps; "
        f"audio: {result.wav_path or 'none'}",
        flush=True,
    )
    for export_format, path in arguments.export:
        for written in exports.export_scene(context, export_format, path):
            _print_warnings(written.warnings)
            print(f"Exported {export_format} to {written.path}", flush=True)
    if arguments.gltf is not None:
        for exported in conversation.export_conversation_gltf(context, arguments.gltf):
            print(f"Exported glTF to {exported.path}; speech: {exported.wav_path or 'none'}", flush=True)
    return list(result.heads.values())


def lip_sync_options(arguments: argparse.Namespace) -> LipSyncOptions:
    return LipSyncOptions(
        timing=arguments.timing,
        motion=arguments.motion,
        interpolation=arguments.interpolation,
        emotion_strength=arguments.emotion_strength,
        rate=arguments.rate,
        recording=arguments.audio,
        cues=arguments.cues,
        **living_option_values(arguments),
    )


def run(arguments: argparse.Namespace) -> None:
    import bpy

    from turkish_lipsync.blender import audio_decoding, pipeline, sequencer
    from turkish_lipsync.core.base.errors import TextError
    from turkish_lipsync.core.base.files import read_user_text
    from turkish_lipsync.core.text.script import read_script

    started = time.perf_counter()
    audio_decoding.register()  # Blender's FFmpeg reads the recordings, as in the panel
    new_scene = open_the_scene(arguments)
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

    if arguments.audio_folder is not None:
        audio_folder = str(arguments.audio_folder.resolve())
    elif arguments.save_blend is not None:
        audio_folder = str(arguments.save_blend.resolve().parent / "lipsync_audio")
    elif arguments.out is not None:
        audio_folder = str(arguments.out.resolve().parent / "lipsync_audio")
    else:
        audio_folder = ""

    script = read_script(source) if source.strip() else None
    if script is not None:
        if arguments.head is not None and not arguments.head.suffix.lower() == ".blend":
            raise LipSyncError(
                "The text has speakers: give each one's head with --cast NAME=HEAD (--head opens a .blend "
                "whose objects --cast may name)"
            )
        heads_shown = run_conversation(arguments, context, script, audio_folder)
        head_name = heads_shown[0] if heads_shown else None
    else:
        head_name = run_one_head(arguments, context, scene, source, new_scene, audio_folder)
    head = bpy.data.objects[head_name] if head_name else None
    if not arguments.no_render:
        rendered = pipeline.render_video(
            context,
            head,
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
            head,
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
