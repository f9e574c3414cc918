"""The batch command: its flags read, its paths checked, then a farm's chunks joined here (no Blender
needed) or the Blender work handed to the function scripts/render.py gives (turkish_lipsync/blender/batch.py,
imported only then); every error one line and a non-zero exit. Also what the flags choose as the core's
values, which an episode's plan (core/farm/plan.py) times its scenes with."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

from ..base.errors import LipSyncError
from ..cli import living_option_values
from ..pipeline import LipSyncOptions
from .arguments import parse_arguments
from .checks import check_paths


def script_arguments(script: str | Path) -> list[str]:
    """The arguments after '--' inside Blender; all of them when the script itself was run by Python."""
    if "--" in sys.argv:
        return sys.argv[sys.argv.index("--") + 1 :]
    if Path(sys.argv[0]).resolve() == Path(script).resolve():
        return sys.argv[1:]
    return []


def print_progress(fraction: float, message: str) -> None:
    print(f"[{fraction * 100:5.1f}%] {message}", flush=True)


def print_warnings(warnings: tuple[str, ...]) -> None:
    for warning in warnings:
        print(f"render.py: warning: {warning}", file=sys.stderr, flush=True)


def run_join(arguments: argparse.Namespace) -> None:
    """Join rendered chunks with the speech, copying the video: no Blender needed."""
    from ..interchange.video import join_videos

    if arguments.audio is None:
        print_warnings(("no --audio given: the joined video is silent.",))
    joined = join_videos(arguments.join, arguments.out, arguments.audio)
    print(
        f"Joined {len(arguments.join)} chunks ({', '.join(map(str, joined.chunk_frames))} frames), "
        f"{joined.frame_count} frames, {joined.seconds:.2f} s, to {joined.path}",
        flush=True,
    )


def main(argv: list[str], run_in_blender: Callable[[argparse.Namespace], None]) -> int:
    """render.py with these arguments; run_in_blender does a chunk or a whole run (it imports bpy)."""
    arguments = parse_arguments(argv)
    try:
        check_paths(arguments)
        if arguments.join:
            run_join(arguments)
        else:
            run_in_blender(arguments)
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


def speaker_choices(arguments: argparse.Namespace) -> dict:
    """What --cast, --voice, --speaker-emotion and --speaker-audio chose per speaker (by the speaker's key,
    so AYŞE and Ayşe are one)."""
    from ..scene import RoleChoice
    from ..text.script import speaker_key

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
    from ..scene.speech import SceneSources, line_recordings_in

    return SceneSources(
        scene_recording=arguments.audio,
        line_recordings=line_recordings_in(arguments.line_audio) if arguments.line_audio else (),
        cues=arguments.cues,
    )
