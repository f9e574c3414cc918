"""The batch command's Blender work (scripts/render.py; its flags and the join are in core/batch): a scene
opened or made, its heads keyed on the speech (one head, or every speaker of a script), exports, the video,
a still and the saved .blend; or, on a farm, one chunk of frames of a saved scene.

Given a .blend with --head, it changes only the TR_* keys, their F-curves, the TR_speech strip and the frame
range (plus camera and lights only where there are none).
"""

from __future__ import annotations

import argparse
import json
import time

import bpy

from ..core.base.errors import LipSyncError
from ..core.batch.arguments import DEFAULT_FPS, DEFAULT_RESOLUTION
from ..core.batch.command import (
    lip_sync_options,
    print_progress,
    print_warnings,
    scene_sources,
    speaker_choices,
)
from . import audio_decoding, character, conversation, exports, farm, heads, pipeline, sequencer
from .generate import generate


def run_in_blender(arguments: argparse.Namespace) -> None:
    """A farm's chunk (--frames) or a whole run."""
    if arguments.frames:
        run_chunk(arguments)
    else:
        run(arguments)


def set_frame_rate(scene, fps: float) -> None:
    """29.97 becomes fps 30 with base 1.001, as Blender's own presets store it."""
    whole = round(fps)
    scene.render.fps = whole
    scene.render.fps_base = 1.0 if abs(whole - fps) < 1e-6 else whole / fps


def _keyed_or_found_head(scene):
    """The scene's head that has our keys, else the head found among its objects."""
    candidates = [obj for obj in scene.objects if obj.type == "MESH" and pipeline.has_lipsync_keys(obj)]
    return candidates[0] if candidates else heads.find_head(scene.objects)


def run_chunk(arguments: argparse.Namespace) -> None:
    """Render one frame range of a saved scene, as a farm worker does."""
    if arguments.head is not None:
        bpy.ops.wm.open_mainfile(filepath=str(arguments.head.resolve()))
    elif not bpy.data.filepath:
        raise LipSyncError(
            "--frames renders a saved scene: give it with --head SAVED.blend, or open it in Blender "
            "(blender -b SAVED.blend -P render.py -- --frames ...)"
        )
    context = bpy.context
    first, last = arguments.frames
    chunk = farm.render_chunk(
        context,
        _keyed_or_found_head(context.scene),
        str(arguments.out),
        first,
        last,
        engine=arguments.engine,
        samples=arguments.samples,
        resolution=arguments.resolution,
        progress=print_progress,
    )
    print(
        f"Rendered frames {chunk.first_frame}-{chunk.last_frame} with {chunk.engine} in "
        f"{chunk.seconds:.1f} s to {chunk.path}",
        flush=True,
    )


def write_exports(arguments: argparse.Namespace, context, head) -> None:
    """The --export files of the head's generated animation (the speech WAV named relative to each file)."""
    for export_format, path in arguments.export:
        written = exports.export_animation(context, head, export_format, path)
        print_warnings(written.warnings)
        print(f"Exported {export_format} to {written.path}", flush=True)


def named_head(name: str):
    """The open file's head of that name (a library override of a linked one before the linked one)."""
    head = bpy.data.objects.get(name)
    if head is None or head.type != "MESH":
        meshes = ", ".join(sorted(obj.name for obj in bpy.context.scene.objects if obj.type == "MESH"))
        what = "no object" if head is None else f"a {head.type.lower()}, not the head mesh,"
        raise LipSyncError(f"--object {name!r}: the open file has {what} of that name; its meshes: {meshes}")
    return head


def _chosen_head(arguments: argparse.Namespace, scene, new_scene: bool):
    """The head the flags name, import or find; None for the default head, which the build adds."""
    if arguments.object is not None:
        return named_head(arguments.object)
    if arguments.head is None and arguments.open is None:
        return None
    if new_scene:
        return heads.find_head(heads.import_head(arguments.head))
    return _keyed_or_found_head(scene)


def _keys_wanted(arguments: argparse.Namespace, head) -> bool:
    """Whether the head's keys are built (again): asked for, or the head cannot speak as it is."""
    rebuild = (
        arguments.rebuild_keys
        or arguments.arkit_keys
        or arguments.mapping is not None
        or arguments.key_source != "auto"
        or arguments.empowered
    )
    return head is None or rebuild or character.speech_problem(head) is not None


def _build_keys(arguments: argparse.Namespace, context, head) -> str:
    """The head's keys built (the default head added where none is given); returns the head's name."""
    report = pipeline.build_keys(
        context,
        head,
        arkit_keys=arguments.arkit_keys,
        source=arguments.key_source,
        obj_folder=str(arguments.obj_folder) if arguments.obj_folder else None,
        mapping_file=str(arguments.mapping) if arguments.mapping else None,
        empowered=arguments.empowered,
        rho=arguments.rho,
        progress=print_progress,
    )
    print(f"Built the shape keys on {report.head} from {report.convention or report.source}", flush=True)
    print_warnings(report.warnings)
    return report.head


def _export_head(arguments: argparse.Namespace, context, head_name: str) -> None:
    """--export and --gltf of one head's animation."""
    if arguments.export:
        write_exports(arguments, context, bpy.data.objects[head_name])
    if arguments.gltf is not None:
        from .gltf_export import export_gltf

        exported = export_gltf(context, bpy.data.objects[head_name], arguments.gltf)
        print(
            f"Exported glTF to {exported.path} ({exported.morph_targets} morph targets); "
            f"speech: {exported.wav_path or 'none'}",
            flush=True,
        )


def run_one_head(arguments, context, scene, source: str, new_scene: bool, audio_folder: str) -> str:
    """One head speaks the text: built where it needs keys, generated, exported; returns its name."""
    head = _chosen_head(arguments, scene, new_scene)
    head_name = _build_keys(arguments, context, head) if _keys_wanted(arguments, head) else head.name
    if arguments.own_keys_at_rest:
        cleared = pipeline.put_own_keys_at_rest(bpy.data.objects[head_name])
        print(f"Set {cleared} of the head's own shape keys to 0", flush=True)
    result = generate(
        context,
        source,
        lip_sync_options(arguments),
        audio_folder=audio_folder,
        progress=print_progress,
        gaze_target=arguments.gaze_target or "",
        head=bpy.data.objects[head_name],
    )
    print_warnings(result.warnings)
    print(
        f"Generated {result.phone_count} phones, {result.duration:.2f} s, frames {result.frame_start}-"
        f"{result.frame_end} at {result.fps:.3f} fps; audio: {result.wav_path or 'none'}",
        flush=True,
    )
    _export_head(arguments, context, head_name)
    return head_name


def run_conversation(arguments: argparse.Namespace, context, script, audio_folder: str) -> list[str]:
    """Every speaker of the script played by its head: generated, exported; returns the heads' names."""
    result = generate(
        context,
        script.source,
        lip_sync_options(arguments),
        sources=scene_sources(arguments),
        audio_folder=audio_folder,
        progress=print_progress,
        choices=speaker_choices(arguments),
    )
    print_warnings(result.warnings)
    cast = ", ".join(f"{name} by {head}" for name, head in result.heads.items())
    print(
        f"Generated {len(script.lines)} lines of {len(result.heads)} characters ({cast}), "
        f"{result.duration:.2f} s, frames {result.frame_start}-{result.frame_end} at {result.fps:.3f} fps; "
        f"audio: {result.wav_path or 'none'}",
        flush=True,
    )
    for export_format, path in arguments.export:
        for written in exports.export_scene(context, export_format, path):
            print_warnings(written.warnings)
            print(f"Exported {export_format} to {written.path}", flush=True)
    if arguments.gltf is not None:
        for exported in conversation.export_conversation_gltf(context, arguments.gltf):
            print(f"Exported glTF to {exported.path}; speech: {exported.wav_path or 'none'}", flush=True)
    return list(result.heads.values())


def open_the_scene(arguments: argparse.Namespace) -> bool:
    """A new scene, the .blend given (--open, --head), or the file Blender opened (with --object); returns
    whether the scene is new."""
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


def _set_up_scene(arguments: argparse.Namespace) -> bool:
    """The scene opened or made, at the frame rate and size asked (a new one at the defaults); returns
    whether it is new."""
    audio_decoding.register()  # Blender's FFmpeg reads the recordings, as in the panel
    new_scene = open_the_scene(arguments)
    scene = bpy.context.scene
    if arguments.fps is not None:
        set_frame_rate(scene, arguments.fps)
    elif new_scene:
        set_frame_rate(scene, DEFAULT_FPS)
    if arguments.resolution is not None:
        scene.render.resolution_x, scene.render.resolution_y = arguments.resolution
    elif new_scene:
        scene.render.resolution_x, scene.render.resolution_y = DEFAULT_RESOLUTION
    return new_scene


def _audio_folder(arguments: argparse.Namespace) -> str:
    """Where the speech WAV goes: --audio-folder, else lipsync_audio beside the .blend or the video."""
    if arguments.audio_folder is not None:
        return str(arguments.audio_folder.resolve())
    beside = arguments.save_blend or arguments.out
    return str(beside.resolve().parent / "lipsync_audio") if beside is not None else ""


def _speak(arguments: argparse.Namespace, context, new_scene: bool) -> str | None:
    """The text spoken by its head, or a script by its cast; returns the head the renders frame."""
    from ..core.base.errors import TextError
    from ..core.base.files import read_user_text
    from ..core.text.script import read_script

    if arguments.jsml is not None:
        source = read_user_text(arguments.jsml, "--jsml text", TextError)
    else:
        source = arguments.text or ""  # with --cues alone, the cue file's own text; with --audio, the heard
    audio_folder = _audio_folder(arguments)
    script = read_script(source) if source.strip() else None
    if script is None:
        return run_one_head(arguments, context, context.scene, source, new_scene, audio_folder)
    if arguments.head is not None and not arguments.head.suffix.lower() == ".blend":
        raise LipSyncError(
            "The text has speakers: give each one's head with --cast NAME=HEAD (--head opens a .blend "
            "whose objects --cast may name)"
        )
    heads_shown = run_conversation(arguments, context, script, audio_folder)
    return heads_shown[0] if heads_shown else None


def _render_video(arguments: argparse.Namespace, context, head) -> None:
    rendered = pipeline.render_video(
        context,
        head,
        str(arguments.out),
        engine=arguments.engine,
        samples=arguments.samples,
        resolution=arguments.resolution,
        progress=print_progress,
    )
    print(
        f"Rendered {rendered.frame_count} frames with {rendered.engine} in {rendered.seconds:.1f} s "
        f"({rendered.seconds / max(1, rendered.frame_count):.2f} s/frame) to {rendered.path}",
        flush=True,
    )


def _render_still(arguments: argparse.Namespace, context, head) -> None:
    scene = context.scene
    frame = arguments.still_frame
    if frame is not None and not scene.frame_start <= frame <= scene.frame_end:
        print_warnings(
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


def _save(arguments: argparse.Namespace, scene) -> None:
    """The scene saved (its speech named relative to the .blend); with --built-json, what was saved."""
    arguments.save_blend.parent.mkdir(parents=True, exist_ok=True)
    sequencer.relate_speech_to(scene, arguments.save_blend)
    bpy.ops.wm.save_as_mainfile(filepath=str(arguments.save_blend.resolve()))
    print(f"Saved {arguments.save_blend}", flush=True)
    if arguments.built_json is not None:
        wav = sequencer.speech_wav_of(scene)
        built = {"frames": [scene.frame_start, scene.frame_end], "speech": str(wav) if wav else None}
        arguments.built_json.write_text(json.dumps(built), encoding="utf-8")


def run(arguments: argparse.Namespace) -> None:
    started = time.perf_counter()
    new_scene = _set_up_scene(arguments)
    context = bpy.context
    head_name = _speak(arguments, context, new_scene)
    head = bpy.data.objects[head_name] if head_name else None
    if not arguments.no_render:
        _render_video(arguments, context, head)
    if arguments.still is not None:
        _render_still(arguments, context, head)
    if arguments.save_blend is not None:
        _save(arguments, context.scene)
    print(f"Done in {time.perf_counter() - started:.1f} s", flush=True)
