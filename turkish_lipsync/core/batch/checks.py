"""render.py's flags checked together once parsed: what a run needs, files that exist, and no output that
replaces an input or another output (check_paths, before anything is read or written)."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..faces.key_sources import RHO_RANGE

HEAD_FILE_SUFFIXES = (".obj", ".glb", ".gltf", ".fbx", ".blend")


def check_arguments(parser: argparse.ArgumentParser, arguments: argparse.Namespace) -> None:
    """Every check in the order a user meets them; parser.error ends the run at the first one refused."""
    if arguments.join or arguments.frames:
        _check_farm_arguments(parser, arguments)
    else:
        _check_text_and_outputs(parser, arguments)
        _check_input_files(parser, arguments)
        _check_conversation_arguments(parser, arguments)
        _check_key_arguments(parser, arguments)
    arguments.engine = arguments.engine.upper()


def _check_text_and_outputs(parser: argparse.ArgumentParser, arguments: argparse.Namespace) -> None:
    """Something to speak, and outputs of the kinds they are named."""
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
    if arguments.built_json is not None and arguments.save_blend is None:
        parser.error("--built-json describes the saved scene: give --save-blend OUT.blend with it")
    if arguments.gltf is not None and arguments.gltf.suffix.lower() != ".glb":
        parser.error(f"--gltf {arguments.gltf} must end in .glb")


def _check_input_files(parser: argparse.ArgumentParser, arguments: argparse.Namespace) -> None:
    if arguments.head is not None and not arguments.head.is_file():
        parser.error(f"--head {arguments.head} does not exist")
    if arguments.open is not None and (
        arguments.open.suffix.lower() != ".blend" or not arguments.open.is_file()
    ):
        parser.error(f"--open {arguments.open} must be a .blend file that exists")
    if arguments.open is not None and arguments.head is not None:
        parser.error("give --open SHOT.blend or --head HEAD, not both (--object names the head in --open)")
    if arguments.jsml is not None and not arguments.jsml.is_file():
        parser.error(f"--jsml {arguments.jsml} does not exist")
    if arguments.audio is not None and not arguments.audio.is_file():
        parser.error(f"--audio {arguments.audio} does not exist")
    if arguments.mapping is not None and not arguments.mapping.is_file():
        parser.error(f"--mapping {arguments.mapping} does not exist")


def _check_conversation_arguments(parser: argparse.ArgumentParser, arguments: argparse.Namespace) -> None:
    """The speakers' flags: files that exist, voices the cast knows, strengths in 0..1."""
    from ..scene.cast import known_variants

    for name, head in arguments.cast:
        if head.lower() != "default" and Path(head).suffix.lower() in HEAD_FILE_SUFFIXES:
            if not Path(head).is_file():
                parser.error(f"--cast {name}={head}: {head} does not exist")
    for name, voice in arguments.voice:
        variant, *numbers = voice.split(":")
        if variant.lower() not in (*known_variants(), "female", "male") or len(numbers) > 2:
            parser.error(
                f"--voice {name}={voice}: expected one of {', '.join(known_variants())}, female or male, "
                "optionally :PITCH:RATE"
            )
        try:
            [float(number) for number in numbers]
        except ValueError:
            parser.error(f"--voice {name}={voice}: PITCH and RATE are multipliers such as 0.9 or 1.1")
    for name, value in arguments.speaker_emotion:
        try:
            strength = float(value)
        except ValueError:
            strength = -1.0
        if not 0.0 <= strength <= 1.0:
            parser.error(f"--speaker-emotion {name}={value}: expected a strength from 0 to 1")
    for name, path in arguments.speaker_audio:
        if not Path(path).is_file():
            parser.error(f"--speaker-audio {name}={path}: {path} does not exist")
    if arguments.line_audio is not None and not arguments.line_audio.is_dir():
        parser.error(f"--line-audio {arguments.line_audio} is not a folder")


def _check_key_arguments(parser: argparse.ArgumentParser, arguments: argparse.Namespace) -> None:
    if (arguments.key_source == "obj_folder") != (arguments.obj_folder is not None):
        parser.error("--key-source obj_folder and --obj-folder FOLDER go together")
    if arguments.obj_folder is not None and not arguments.obj_folder.is_dir():
        parser.error(f"--obj-folder {arguments.obj_folder} is not a folder")
    if not RHO_RANGE[0] <= arguments.rho <= RHO_RANGE[1]:
        parser.error(f"--rho {arguments.rho} must lie between {RHO_RANGE[0]:g} and {RHO_RANGE[1]:g}")


def _speech_flags(arguments: argparse.Namespace) -> dict:
    """The flags of a run that speaks a text, by name: a chunk or a join takes none of them."""
    return {
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
        "--built-json": arguments.built_json,
        "--still": arguments.still,
        "--gaze-target": arguments.gaze_target,
        "--cast": arguments.cast,
        "--voice": arguments.voice,
        "--speaker-emotion": arguments.speaker_emotion,
        "--speaker-audio": arguments.speaker_audio,
        "--line-audio": arguments.line_audio,
    }


def _check_farm_arguments(parser: argparse.ArgumentParser, arguments: argparse.Namespace) -> None:
    """--frames renders a chunk of a saved scene and --join joins chunks: neither speaks a text."""
    used = [flag for flag, value in _speech_flags(arguments).items() if value]
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


def check_paths(arguments: argparse.Namespace) -> None:
    """No output of this run may replace one of its inputs or another of its outputs (checked first)."""
    from ..base.files import check_distinct_paths, check_writable

    inputs = {
        "--jsml": arguments.jsml,
        "--audio": arguments.audio,
        "--head": arguments.head,
        "--open": arguments.open,
        "--cues": arguments.cues,
        "--mapping": arguments.mapping,
    }
    inputs |= {f"--join chunk {number}": chunk for number, chunk in enumerate(arguments.join or (), start=1)}
    inputs |= {f"--speaker-audio {name}": Path(path) for name, path in arguments.speaker_audio}
    inputs |= {
        f"--cast {name}": Path(head)
        for name, head in arguments.cast
        if head.lower() != "default" and Path(head).is_file()
    }
    outputs = {
        "--out": arguments.out,
        "--save-blend": arguments.save_blend,
        "--still": arguments.still,
        "--built-json": arguments.built_json,
    }
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
