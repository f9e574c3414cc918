"""render.py's flags, in groups, each checked as it is parsed; the flags checked together are in checks.py.

Every flag's choices come from the core's option choices, as the panel's and the command line's do.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..cli import add_living_arguments, add_motion_arguments
from ..faces.key_sources import KEY_SOURCE_CHOICES
from ..pipeline import identifiers

DESCRIPTION = "Batch lip sync: Turkish text in, a head speaking it out (MP4 with sound and/or a .blend)."
DEFAULT_RESOLUTION = (960, 540)
DEFAULT_FPS = 25.0


class OneLineArgumentParser(argparse.ArgumentParser):
    """One clear line instead of usage + message, named after the program (a sub-command's too)."""

    def error(self, message: str):
        print(f"{self.prog.split()[0]}: error: {message} (see --help)", file=sys.stderr)
        sys.exit(2)


def resolution(text: str) -> tuple[int, int]:
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


def frame_range(text: str) -> tuple[int, int]:
    """START-END (or one frame), as Flamenco's frame chunker and an episode's job write them."""
    first, _, last = text.partition("-")
    try:
        start, end = int(first), int(last or first)
    except ValueError:
        raise argparse.ArgumentTypeError(f"frames {text!r} are not START-END, e.g. 1-50") from None
    if end < start:
        raise argparse.ArgumentTypeError(f"frames {text!r} end before they start")
    return start, end


def _export(text: str) -> tuple[str, Path]:
    from ..interchange import export_formats

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


def batch_parser() -> OneLineArgumentParser:
    parser = OneLineArgumentParser(prog="render.py", description=DESCRIPTION)
    for add_group in (_inputs, _outputs, _render, _motion, _keys, _conversation, _farm):
        add_group(parser)
    return parser


def _inputs(parser: argparse.ArgumentParser) -> None:
    inputs = parser.add_argument_group("what is spoken, and by which head")
    source = inputs.add_mutually_exclusive_group()
    source.add_argument("--text", help="Turkish text to speak (plain or JSML)")
    source.add_argument("--jsml", type=Path, help="a UTF-8 file with Turkish text (plain or JSML)")
    inputs.add_argument(
        "--audio",
        type=Path,
        help="a recording of the text (WAV, FLAC, OGG, MP3, M4A, or a video with sound: MP4, MOV, MKV, WebM) "
        "to use instead of eSpeak; without --text or --jsml, what it says is recognised from the audio",
    )
    inputs.add_argument(
        "--cues",
        type=Path,
        help="time the visemes by a Rhubarb .tsv/.json/.xml, Papagayo .pgo or Moho .dat file (a .pgo brings "
        "its own text; --audio is then the sound as it is)",
    )
    inputs.add_argument(
        "--head", type=Path, help="head file: .obj .glb .gltf .fbx or .blend (default: reference)"
    )
    inputs.add_argument(
        "--open", type=Path, help="a .blend to work in as it is (a shot: its linked characters included)"
    )
    inputs.add_argument(
        "--object",
        help="the head to animate, by name, in the open file (--open, --head .blend, or the file Blender "
        "opened): a library override of a linked character too",
    )


def _outputs(parser: argparse.ArgumentParser) -> None:
    outputs = parser.add_argument_group("what is written")
    outputs.add_argument("--out", type=Path, help="the MP4 to render (H.264 + AAC)")
    outputs.add_argument("--save-blend", type=Path, help="save the animated scene to this .blend")
    outputs.add_argument(
        "--audio-folder",
        type=Path,
        help="where the speech WAV goes (default: lipsync_audio beside the output)",
    )
    outputs.add_argument(
        "--still", type=Path, help="also render one frame to this PNG (widest mouth by default)"
    )
    outputs.add_argument("--still-frame", type=int, help="the frame for --still")
    outputs.add_argument(
        "--export",
        type=_export,
        action="append",
        default=[],
        metavar="FORMAT=PATH",
        help="also write the animation for other tools (repeatable): rhubarb-tsv, rhubarb-json, rhubarb-xml, "
        "moho-dat, papagayo-pgo, arkit-csv",
    )
    outputs.add_argument(
        "--gltf",
        type=Path,
        help="also write the head and its speech animation as .glb, the speech WAV beside it",
    )


def _render(parser: argparse.ArgumentParser) -> None:
    render = parser.add_argument_group("how the video is rendered")
    render.add_argument(
        "--engine",
        default="auto",
        type=str.lower,
        choices=("auto", "eevee", "cycles", "workbench"),
        help="render engine (auto: EEVEE with OpenGL, else Cycles)",
    )
    render.add_argument("--resolution", type=resolution, help="WIDTHxHEIGHT (default 960x540 for new scenes)")
    render.add_argument("--fps", type=_fps, help="frame rate, fractional allowed (default 25 for new scenes)")
    render.add_argument("--samples", type=_positive, help="render samples per pixel (default 16)")
    render.add_argument("--no-render", action="store_true", help="only animate (and save with --save-blend)")


def _motion(parser: argparse.ArgumentParser) -> None:
    motion = parser.add_argument_group("how the face moves")
    add_motion_arguments(motion)
    add_living_arguments(motion)
    motion.add_argument(
        "--gaze-target", metavar="OBJECT", help="the object the eyes seek (default: the scene's camera)"
    )


def _keys(parser: argparse.ArgumentParser) -> None:
    keys = parser.add_argument_group("the head's shape keys")
    keys.add_argument(
        "--arkit-keys", action="store_true", help="also keep the 52 ARKit unit keys on the head"
    )
    keys.add_argument("--rebuild-keys", action="store_true", help="rebuild the TR_* keys even if present")
    keys.add_argument(
        "--own-keys-at-rest",
        action="store_true",
        help="set the head's own shape keys that hold a value (and are not animated) to 0 before speaking",
    )
    keys.add_argument(
        "--key-source",
        default="auto",
        choices=identifiers(KEY_SOURCE_CHOICES),
        help="what the keys are built from (auto: the head's own visemes or ARKit keys, else a transfer)",
    )
    keys.add_argument(
        "--obj-folder", type=Path, help="with --key-source obj_folder: the thesis's OBJ models (a.obj, ...)"
    )
    keys.add_argument(
        "--mapping",
        type=Path,
        help="a TOML file naming the head's own keys for the Turkish visemes (the manual's Heads page: "
        "a mapping file)",
    )
    keys.add_argument(
        "--empowered",
        action="store_true",
        help="store the emotion keys empowered (thesis eq. 5.2), for keying them by hand",
    )
    keys.add_argument(
        "--rho", type=float, default=3.0, help="the empowering constant of eq. 5.2 (the thesis uses 3)"
    )


# A script's speakers' NAME=VALUE flags (repeatable): flag, what VALUE is, help
SPEAKER_FLAGS = (
    (
        "--cast",
        "HEAD",
        "the head that plays a speaker (repeatable): a head file, an object of the --head .blend, or "
        "'default' (the default: a default head of the speaker's own, beside the others)",
    ),
    (
        "--voice",
        "VOICE",
        "a speaker's voice (repeatable): an eSpeak NG variant (f1-f5, m1-m8) or female/male, optionally "
        "with :PITCH:RATE multipliers, e.g. Ali=m7:0.9:1.05",
    ),
    (
        "--speaker-emotion",
        "STRENGTH",
        "how strongly a speaker's emotions show, 0..1, times --emotion-strength (repeatable)",
    ),
    (
        "--speaker-audio",
        "RECORDING",
        "a speaker's track of the scene (repeatable; every speaker then needs one); --audio is a "
        "recording of the whole scene",
    ),
)


def _conversation(parser: argparse.ArgumentParser) -> None:
    conversation = parser.add_argument_group(
        "a script with speakers (<VOICE NAME=...> lines or a screenplay, NAME: text)"
    )
    for flag, what, help_text in SPEAKER_FLAGS:
        conversation.add_argument(
            flag, type=_named(flag, what), action="append", default=[], metavar=f"NAME={what}", help=help_text
        )
    conversation.add_argument(
        "--line-audio",
        type=Path,
        metavar="FOLDER",
        help="a folder of recordings, one per line of the script, in the order of their names",
    )


def _farm(parser: argparse.ArgumentParser) -> None:
    farm = parser.add_argument_group("on a render farm")
    farm.add_argument(
        "--frames",
        type=frame_range,
        metavar="START-END",
        help="farm chunk: render only these frames of the saved .blend (--head, or the file Blender opened) "
        "to --out (.mp4/.mkv: lossless video without sound; otherwise a folder of PNG frames)",
    )
    farm.add_argument(
        "--join",
        type=Path,
        nargs="+",
        metavar="CHUNK",
        help="join chunk videos in this order with the speech (--audio WAV) into --out, copying the video",
    )
    farm.add_argument(
        "--built-json",
        type=Path,
        metavar="PATH",
        help="with --save-blend: write the saved scene's frame range and speech WAV to this JSON file "
        "(what an episode's build step reads)",
    )


def parse_arguments(argv: list[str]) -> argparse.Namespace:
    """render.py's flags parsed and checked together (checks.py); a refused one ends the run with one line."""
    from .checks import check_arguments

    parser = batch_parser()
    arguments = parser.parse_args(argv)
    check_arguments(parser, arguments)
    return arguments
