"""render.py's command line: its flags, each checked when parsed, and the paths of a run checked together.

Kept apart from render.py so that the script reads as what it does; every flag's choices come from the
core's option choices, as the panel's and the command line's do.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from turkish_lipsync.core.cli import add_living_arguments
from turkish_lipsync.core.faces.key_sources import KEY_SOURCE_CHOICES, RHO_RANGE
from turkish_lipsync.core.pipeline import (
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


def _named(flag: str, what: str):
    """A NAME=VALUE flag of a script's speaker (the name as the script writes it, any case)."""

    def parse(text: str) -> tuple[str, str]:
        name, _, value = text.partition("=")
        if not name.strip() or not value.strip():
            raise argparse.ArgumentTypeError(f"{flag} {text!r} is not NAME={what}")
        return name.strip(), value.strip()

    return parse


def parse_arguments(argv: list[str]) -> argparse.Namespace:
    parser = OneLineArgumentParser(prog="render.py", description=__doc__.split("\n\n")[0])
    source = parser.add_mutually_exclusive_group()
    source.add_argument("--text", help="Turkish text to speak (plain or JSML)")
    source.add_argument("--jsml", type=Path, help="a UTF-8 file with Turkish text (plain or JSML)")
    parser.add_argument(
        "--head", type=Path, help="head file: .obj .glb .gltf .fbx or .blend (default: reference)"
    )
    parser.add_argument(
        "--open", type=Path, help="a .blend to work in as it is (a shot: its linked characters included)"
    )
    parser.add_argument(
        "--object",
        help="the head to animate, by name, in the open file (--open, --head .blend, or the file Blender "
        "opened): a library override of a linked character too",
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
        help="a recording of the text (WAV, FLAC, OGG, MP3, M4A, or a video with sound: MP4, MOV, MKV, WebM) "
        "to use instead of eSpeak; without --text or --jsml, what it says is recognised from the audio",
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
    conversation = parser.add_argument_group(
        "a script with speakers (<VOICE NAME=...> lines or a screenplay, NAME: text)"
    )
    conversation.add_argument(
        "--cast",
        type=_named("--cast", "HEAD"),
        action="append",
        default=[],
        metavar="NAME=HEAD",
        help="the head that plays a speaker (repeatable): a head file, an object of the --head .blend, or "
        "'default' (the default: a default head of the speaker's own, beside the others)",
    )
    conversation.add_argument(
        "--voice",
        type=_named("--voice", "VOICE"),
        action="append",
        default=[],
        metavar="NAME=VOICE",
        help="a speaker's voice (repeatable): an eSpeak NG variant (f1-f5, m1-m8) or female/male, optionally "
        "with :PITCH:RATE multipliers, e.g. Ali=m7:0.9:1.05",
    )
    conversation.add_argument(
        "--speaker-emotion",
        type=_named("--speaker-emotion", "STRENGTH"),
        action="append",
        default=[],
        metavar="NAME=STRENGTH",
        help="how strongly a speaker's emotions show, 0..1, times --emotion-strength (repeatable)",
    )
    conversation.add_argument(
        "--speaker-audio",
        type=_named("--speaker-audio", "RECORDING"),
        action="append",
        default=[],
        metavar="NAME=RECORDING",
        help="a speaker's track of the scene (repeatable; every speaker then needs one); --audio is a "
        "recording of the whole scene",
    )
    conversation.add_argument(
        "--line-audio",
        type=Path,
        metavar="FOLDER",
        help="a folder of recordings, one per line of the script, in the order of their names",
    )
    parser.add_argument(
        "--mapping",
        type=Path,
        help="a TOML file naming the head's own keys for the Turkish visemes (the manual's Heads page: "
        "a mapping file)",
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
    if arguments.gltf is not None and arguments.gltf.suffix.lower() != ".glb":
        parser.error(f"--gltf {arguments.gltf} must end in .glb")
    if arguments.mapping is not None and not arguments.mapping.is_file():
        parser.error(f"--mapping {arguments.mapping} does not exist")
    _check_conversation_arguments(parser, arguments)
    if (arguments.key_source == "obj_folder") != (arguments.obj_folder is not None):
        parser.error("--key-source obj_folder and --obj-folder FOLDER go together")
    if arguments.obj_folder is not None and not arguments.obj_folder.is_dir():
        parser.error(f"--obj-folder {arguments.obj_folder} is not a folder")
    if not RHO_RANGE[0] <= arguments.rho <= RHO_RANGE[1]:
        parser.error(f"--rho {arguments.rho} must lie between {RHO_RANGE[0]:g} and {RHO_RANGE[1]:g}")
    arguments.engine = arguments.engine.upper()
    return arguments


def _check_conversation_arguments(parser: argparse.ArgumentParser, arguments: argparse.Namespace) -> None:
    """The speakers' flags: files that exist, voices the cast knows, strengths in 0..1."""
    from turkish_lipsync.core.scene.cast import known_variants

    for name, head in arguments.cast:
        if head.lower() != "default" and Path(head).suffix.lower() in (
            ".obj",
            ".glb",
            ".gltf",
            ".fbx",
            ".blend",
        ):
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
        "--cast": arguments.cast,
        "--voice": arguments.voice,
        "--speaker-emotion": arguments.speaker_emotion,
        "--speaker-audio": arguments.speaker_audio,
        "--line-audio": arguments.line_audio,
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
