"""The command line: syllables, timeline and quality reports, without Blender."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from .base.errors import LipSyncError
from .base.files import check_distinct_paths, check_writable, read_user_text
from .base.model import Timeline, WeightTracks
from .motion.living import GazeSetup
from .pipeline import (
    FPS_RANGE,
    INTERPOLATION_CHOICES,
    MOTION_CHOICES,
    TIMING_CHOICES,
    LipSyncOptions,
    identifiers,
)


def main(argv: list[str] | None = None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    try:
        return args.run(args)
    except LipSyncError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        return 0


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m turkish_lipsync", description=__doc__)
    commands = parser.add_subparsers(required=True, metavar="COMMAND")

    syllables = commands.add_parser("syllables", help="print each word's syllables joined by '-'")
    syllables.add_argument("words", nargs="+", metavar="WORD")
    syllables.set_defaults(run=_run_syllables)

    normalize = commands.add_parser("normalize", help="print the text as it is spoken, to check a script")
    normalize_source = normalize.add_mutually_exclusive_group(required=True)
    normalize_source.add_argument("text", nargs="*", default=[], metavar="TEXT", help="JSML or plain text")
    normalize_source.add_argument("--file", type=Path, metavar="FILE", help="a JSML or plain text file")
    normalize.set_defaults(run=_run_normalize)

    timeline = commands.add_parser("timeline", help="print the phones, words and emotion spans of a text")
    _add_source_arguments(timeline)
    timeline.add_argument("--format", choices=("json", "tsv"), default="tsv")
    timeline.add_argument("--wav", type=Path, metavar="OUT.wav", help="also write the synthesised speech")
    timeline.set_defaults(run=_run_timeline)

    quality = commands.add_parser("quality", help="measure the motion of the thesis mode and the default")
    _add_source_arguments(quality)
    quality.add_argument("--format", choices=("text", "json"), default="text")
    quality.set_defaults(run=_run_quality)

    from .interchange import export_formats

    export = commands.add_parser(
        "export", help="write the animation for other tools: Rhubarb cues, Moho .dat, Papagayo, ARKit CSV"
    )
    _add_source_arguments(export)
    export.add_argument("--format", required=True, choices=tuple(export_formats()), dest="export_format")
    export.add_argument("--out", type=Path, metavar="PATH", help="the file to write (default: print it)")
    export.add_argument("--wav", type=Path, metavar="OUT.wav", help="also write the speech audio")
    export.set_defaults(run=_run_export)
    return parser


def _add_source_arguments(parser: argparse.ArgumentParser) -> None:
    source = parser.add_mutually_exclusive_group()
    source.add_argument("file", nargs="?", type=Path, metavar="FILE", help="a JSML or plain text file")
    source.add_argument("--text", help="JSML or plain text given on the command line")
    parser.add_argument(
        "--cues",
        type=Path,
        metavar="CUES",
        help="time the visemes by a Rhubarb .tsv/.json/.xml, Papagayo .pgo or Moho .dat file (a .pgo's own "
        "text is used when no text is given; --audio is then its sound, not aligned)",
    )
    add_motion_arguments(parser)
    defaults = LipSyncOptions()
    fps_help = f"frames per second ({FPS_RANGE[0]:g}..{FPS_RANGE[1]:g})"
    parser.add_argument("--fps", type=float, default=defaults.fps, help=fps_help)
    parser.add_argument(
        "--audio",
        type=Path,
        metavar="RECORDING",
        help="a recording of the text to align (WAV, FLAC, OGG, MP3; M4A and videos' sound with PyAV); "
        "without a text, what it says is recognised from the audio",
    )
    add_living_arguments(parser)
    parser.add_argument(
        "--gaze-target",
        type=_gaze_target,
        metavar="YAW,PITCH[,DISTANCE]",
        help="where the eyes seek the listener: degrees to the character's left and up, metres away "
        "(default 0,0,1: straight ahead)",
    )


def add_motion_arguments(parser) -> None:
    """How the speech is timed and the face moved, shared with scripts/render.py (each choice the core's)."""
    defaults = LipSyncOptions()
    parser.add_argument("--timing", choices=identifiers(TIMING_CHOICES), default=defaults.timing)
    parser.add_argument("--motion", choices=identifiers(MOTION_CHOICES), default=defaults.motion)
    parser.add_argument(
        "--interpolation", choices=identifiers(INTERPOLATION_CHOICES), default=defaults.interpolation
    )
    parser.add_argument("--rate", type=float, default=defaults.rate, help="speaking-rate multiplier")
    parser.add_argument("--emotion-strength", type=float, default=defaults.emotion_strength, help="0..1")


def add_living_arguments(parser: argparse.ArgumentParser) -> None:
    """The living layers' flags, shared with scripts/render.py: each layer on or off (default: the motion
    model's) with an amount, and the seed."""
    defaults = LipSyncOptions()
    for layer, amount, what in LIVING_FLAGS:
        parser.add_argument(
            f"--{layer.replace('_', '-')}",
            action=argparse.BooleanOptionalAction,
            default=None,
            help=f"{what} (default: on for the natural motion, off for the thesis's)",
        )
        parser.add_argument(
            f"--{amount.replace('_', '-')}",
            type=float,
            default=getattr(defaults, amount),
            help="how much, 0..2 (1 the usual)",
        )
    parser.add_argument("--seed", type=int, default=defaults.seed, help="seed of the gaze, blinks and head")


def living_option_values(args: argparse.Namespace) -> dict:
    """The living layers' options from parsed flags (add_living_arguments)."""
    names = [name for flags in LIVING_FLAGS for name in flags[:2]] + ["seed"]
    return {name: getattr(args, name) for name in names}


LIVING_FLAGS = (
    ("gaze", "gaze_amount", "eyes that hold the listener and look away with saccades"),
    ("blinks", "blink_amount", "blinks at pauses and gaze shifts (the amount scales their rate)"),
    ("head_motion", "head_amount", "head motion from the voice's pitch and loudness"),
    ("expression", "expression_amount", "brows on pitch accents and emphasis, emotions that breathe"),
)


def _gaze_target(text: str) -> GazeSetup:
    try:
        values = [float(part) for part in text.split(",")]
    except ValueError:
        values = []
    if len(values) not in (2, 3):
        raise argparse.ArgumentTypeError(f"gaze target {text!r} is not YAW,PITCH or YAW,PITCH,DISTANCE")
    yaw, pitch, *distance = values
    return GazeSetup(target_yaw=yaw, target_pitch=pitch, target_distance=distance[0] if distance else 1.0)


def read_source(
    file: Path | None, text: str | None, cues: Path | None = None, audio: Path | None = None
) -> str:
    if text is not None:
        return text
    if file is None:
        if cues is not None or audio is not None:
            return ""  # the cue file's own text, where it has one; else what the recording is heard to say
        raise LipSyncError("give the text to speak: a FILE or --text TEXT (or --audio REC to recognise it)")
    return read_user_text(file, "text to speak")


def check_paths(args: argparse.Namespace, **outputs: Path | None) -> None:
    """Before anything is spoken or written: no output may be an input or another output."""
    inputs = {"FILE": args.file, "--audio": args.audio, "--cues": args.cues}
    check_distinct_paths(inputs, {f"--{name}": path for name, path in outputs.items()})
    for name, path in outputs.items():
        if path is not None:
            check_writable(path, f"output of --{name}")


def options_from(args: argparse.Namespace) -> LipSyncOptions:
    setup = {"gaze_setup": args.gaze_target} if args.gaze_target is not None else {}
    return LipSyncOptions.from_attributes(args, recording=args.audio, **setup)


def _perform(args: argparse.Namespace):
    """The source's scene (one head, or a script's cast), its warnings printed."""
    from .scene import perform

    scene = perform(read_source(args.file, args.text, args.cues, args.audio), options_from(args))
    for warning in scene.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    return scene


def _write_sound(path: Path | None, scene) -> None:
    """The scene's sound as a WAV at path (none asked for: nothing written)."""
    if path is None:
        return
    sound = scene.sound()
    if sound is None:
        raise LipSyncError("--wav needs speech: use --timing phone or word, or give --audio with --cues")
    from .speech import write_wav

    write_wav(path, sound)


def _run_syllables(args: argparse.Namespace) -> int:
    from .text.normalize import turkish_lower
    from .text.syllables import syllabify

    for word in args.words:
        print("-".join(syllabify(turkish_lower(word))))
    return 0


def _run_normalize(args: argparse.Namespace) -> int:
    """Numbers, dates, abbreviations and suffixes as they will be spoken, pauses as punctuation."""
    from .text.normalize import spoken_text

    print(spoken_text(read_source(args.file, " ".join(args.text) if args.text else None)))
    return 0


def _run_timeline(args: argparse.Namespace) -> int:
    """One head's timeline (and weight tracks with --format json); for a script with speakers, its lines
    on the scene's timeline, then each speaker's own timeline."""
    check_paths(args, wav=args.wav)
    scene = _perform(args)
    _write_sound(args.wav, scene)
    if scene.solo:
        character = scene.characters[0]
        if args.format == "json":
            data = timeline_as_dict(character.timeline, args.fps) | {
                "tracks": tracks_as_dict(character.tracks)
            }
            print(json.dumps(data, ensure_ascii=False, indent=1))
        else:
            print(timeline_as_tsv(character.timeline, args.fps))
        return 0
    print(_scene_json(scene, args.fps) if args.format == "json" else _scene_tsv(scene, args.fps))
    return 0


def _scene_json(scene, fps: float) -> str:
    speech, cast = scene.speech, scene.speech.cast
    data = {
        "duration": round(speech.duration, 4),
        "cast": [
            {
                "name": r.name,
                "gender": r.gender,
                "voice": r.voice.variant,
                "pitch": r.voice.pitch,
                "rate": r.voice.rate,
            }
            for r in cast.roles
        ],
        "lines": [_line_as_dict(line, cast) for line in speech.lines],
        "speakers": {
            role.name: timeline_as_dict(speech.speaker_timeline(role.key), fps) for role in cast.roles
        },
    }
    return json.dumps(data, ensure_ascii=False, indent=1)


def _scene_tsv(scene, fps: float) -> str:
    speech, cast = scene.speech, scene.speech.cast
    lines = [
        f"# scene\tlines {len(speech.lines)}\tspeakers {len(cast.roles)}\tduration {speech.duration:.3f}"
    ]
    lines.append("line\tstart\tend\tspeaker\taddressee\ttext")
    for line in speech.lines:
        entry = _line_as_dict(line, cast)
        lines.append(
            f"{entry['line']}\t{entry['start']:.3f}\t{entry['end']:.3f}\t{entry['speaker']}\t"
            f"{entry['addressee']}\t{entry['text']}"
        )
    for role in cast.roles:
        lines.append("")
        lines.append(f"# speaker {role.name}\tvoice {role.voice.variant}")
        lines.append(timeline_as_tsv(speech.speaker_timeline(role.key), fps))
    return "\n".join(lines)


def _line_as_dict(line, cast) -> dict:
    addressee = cast.role(line.addressee).name if line.addressee in cast.keys else line.addressee
    return {
        "line": line.index + 1,
        "start": round(line.first_phone, 4),
        "end": round(line.last_phone, 4),
        "speaker": cast.role(line.speaker).name,
        "addressee": addressee,
        "text": " ".join(word.text for word in line.utterance.words),
    }


def _run_export(args: argparse.Namespace) -> int:
    """One head's cue or CSV file; for a script with speakers a Papagayo project with one voice per
    character, or a file per character (OUT_<Name>.ext) of any other format, the core's own scene (default
    heads on the arc, camera in front)."""
    from .interchange import export_format_named, export_text, write_export
    from .speech.cues.papagayo_pgo import voices_as_pgo

    check_paths(args, out=args.out, wav=args.wav)
    scene = _perform(args)
    _write_sound(args.wav, scene)
    sound_file = _relative_to(args.wav, args.out.parent if args.out else Path.cwd()) if args.wav else ""
    if args.export_format == "papagayo-pgo" and not scene.solo:
        contents = voices_as_pgo(
            [(c.role.name, c.timeline, _spoken_text(scene, c.role.key)) for c in scene.characters],
            scene.options.fps,
            sound_file,
            scene.speech.duration,
        )
        _write_or_print(args.out, contents)
        return 0
    if args.out is None and not scene.solo:
        raise LipSyncError(
            f"A script with speakers gives a {args.export_format} file per character: give --out (each is "
            "written beside it, named after the character)."
        )
    suffix = export_format_named(args.export_format).suffix
    source = read_source(args.file, args.text, args.cues, args.audio) if scene.solo else ""
    for character in scene.characters:
        contents, warnings = export_text(
            args.export_format,
            character.timeline,
            character.tracks,
            sound_file=sound_file,
            text=source if args.export_format == "papagayo-pgo" else "",
        )
        named = f"{character.role.name}: " if character.role.name else ""
        for warning in warnings:
            print(f"warning: {named}{warning}", file=sys.stderr)
        if scene.solo:
            _write_or_print(args.out, contents)
        else:
            name = "_".join(character.role.name.split())
            write_export(args.out.with_name(f"{args.out.stem}_{name}{suffix}"), contents)
    return 0


def _spoken_text(scene, key: str) -> str:
    """A speaker's lines as the words they say, a line a row."""
    return "\n".join(
        " ".join(w.text for w in line.utterance.words) for line in scene.speech.lines if line.speaker == key
    )


def _write_or_print(path: Path | None, contents: str) -> None:
    from .interchange import write_export

    if path is None:
        sys.stdout.write(contents)
    else:
        write_export(path, contents)


def _relative_to(path: Path, folder: Path) -> str:
    """A path as the exported file should name it: relative to the export's folder where possible."""
    try:
        return str(path.resolve().relative_to(folder.resolve()))
    except ValueError:
        return str(path.resolve())


def _run_quality(args: argparse.Namespace) -> int:
    from .motion.quality import compare_modes, format_quality

    scene = _perform(args)
    timeline = scene.characters[0].timeline if scene.solo else scene.speech.scene_timeline()
    report = compare_modes(timeline, args.fps, args.emotion_strength)
    print(json.dumps(report, indent=1) if args.format == "json" else format_quality(report))
    return 0


def timeline_as_dict(timeline: Timeline, fps: float) -> dict:
    return {
        "timing": timeline.timing,
        "fps": fps,
        "duration": round(timeline.duration, 4),
        "phones": [
            {
                "start": round(p.start, 4),
                "end": round(p.end, 4),
                "letter": p.letter,
                "syllable": p.syllable,
                "word": timeline.words[p.word_index].text,
                "viseme": p.viseme,
            }
            for p in timeline.phones
        ],
        "words": [
            {"start": round(w.start, 4), "end": round(w.end, 4), "text": w.text} for w in timeline.words
        ],
        "emotions": [
            {"start": round(e.start, 4), "end": round(e.end, 4), "emotion": e.emotion, "weight": e.weight}
            for e in timeline.emotions
        ],
        "hesitations": [
            {"start": round(h.start, 4), "end": round(h.end, 4), "sound": h.sound, "viseme": h.viseme}
            for h in timeline.hesitations
        ],
    }


def tracks_as_dict(tracks: WeightTracks) -> dict:
    """The weight tracks as Blender keys them: frames from 0 (the scene's start frame) and weights; and the
    head's and eyes' rotations at every frame (degrees, HeadAndEyes' conventions), null when off."""
    motion = tracks.head_and_eyes
    return {
        "fps": tracks.fps,
        "frame_count": tracks.frame_count,
        "interpolation": tracks.interpolation,
        "mode": tracks.mode,
        "keys": {
            track.name: {"frames": track.frames.tolist(), "values": track.values.tolist()}
            for track in tracks.tracks
        },
        "head_and_eyes": None
        if motion is None
        else {
            "units": "degrees per frame; yaw, pitch, roll of the head, and of each eye relative to the head; "
            "yaw + toward the character's left, pitch + up, roll + toward its right shoulder",
            "head": np.round(motion.head, 4).tolist(),
            "left_eye": np.round(motion.left_eye, 4).tolist(),
            "right_eye": np.round(motion.right_eye, 4).tolist(),
        },
    }


def timeline_as_tsv(timeline: Timeline, fps: float) -> str:
    lines = [f"# timing {timeline.timing}\tduration {timeline.duration:.3f}\tfps {fps:g}"]
    lines.append("kind\tstart\tend\tletter\tsyllable\tword\tviseme")
    for p in timeline.phones:
        word = timeline.words[p.word_index].text
        lines.append(f"phone\t{p.start:.3f}\t{p.end:.3f}\t{p.letter}\t{p.syllable}\t{word}\t{p.viseme}")
    for w in timeline.words:
        lines.append(f"word\t{w.start:.3f}\t{w.end:.3f}\t\t\t{w.text}\t")
    for e in timeline.emotions:
        lines.append(f"emotion\t{e.start:.3f}\t{e.end:.3f}\t\t\t{e.emotion} {e.weight:g}\t")
    for h in timeline.hesitations:
        lines.append(f"hesitation\t{h.start:.3f}\t{h.end:.3f}\t{h.sound}\t\t\t{h.viseme}")
    return "\n".join(lines)
