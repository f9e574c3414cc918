"""The command line: syllables, timeline and quality reports, without Blender."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from .base.errors import LipSyncError
from .base.files import check_distinct_paths, check_writable, read_user_text
from .base.model import Timeline, WeightTracks
from .pipeline import (
    FPS_RANGE,
    INTERPOLATION_CHOICES,
    MOTION_CHOICES,
    TIMING_CHOICES,
    LipSyncOptions,
    LipSyncResult,
    identifiers,
    lip_sync,
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
    defaults = LipSyncOptions()
    parser.add_argument("--timing", choices=identifiers(TIMING_CHOICES), default=defaults.timing)
    parser.add_argument("--motion", choices=identifiers(MOTION_CHOICES), default=defaults.motion)
    parser.add_argument(
        "--interpolation", choices=identifiers(INTERPOLATION_CHOICES), default=defaults.interpolation
    )
    parser.add_argument("--rate", type=float, default=defaults.rate, help="speaking-rate multiplier")
    parser.add_argument("--emotion-strength", type=float, default=defaults.emotion_strength, help="0..1")
    fps_help = f"frames per second ({FPS_RANGE[0]:g}..{FPS_RANGE[1]:g})"
    parser.add_argument("--fps", type=float, default=defaults.fps, help=fps_help)
    parser.add_argument(
        "--audio",
        type=Path,
        metavar="RECORDING",
        help="a recording of the text to align; without a text, what it says is recognised from the audio",
    )


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
    return LipSyncOptions.from_attributes(args, recording=args.audio)


def _lip_sync(args: argparse.Namespace) -> LipSyncResult:
    result = lip_sync(read_source(args.file, args.text, args.cues, args.audio), options_from(args))
    for warning in result.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    return result


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
    check_paths(args, wav=args.wav)
    result = _lip_sync(args)
    if args.wav:
        if result.synthesis is None:
            raise LipSyncError("--wav needs a speech engine: use --timing phone or word")
        from .speech import write_wav

        write_wav(args.wav, result.synthesis)
    if args.format == "json":
        data = timeline_as_dict(result.timeline, args.fps) | {"tracks": tracks_as_dict(result.tracks)}
        print(json.dumps(data, ensure_ascii=False, indent=1))
    else:
        print(timeline_as_tsv(result.timeline, args.fps))
    return 0


def _run_export(args: argparse.Namespace) -> int:
    from .interchange import export_text, write_export

    check_paths(args, out=args.out, wav=args.wav)
    result = _lip_sync(args)
    sound_file = ""
    if args.wav:
        if result.synthesis is None:
            raise LipSyncError("--wav needs speech: use --timing phone or word, or give --audio with --cues")
        from .speech import write_wav

        write_wav(args.wav, result.synthesis)
        sound_file = _relative_to(args.wav, args.out.parent if args.out else Path.cwd())
    contents, warnings = export_text(
        args.export_format,
        result.timeline,
        result.tracks,
        sound_file=sound_file,
        text=read_source(args.file, args.text, args.cues, args.audio)
        if args.export_format == "papagayo-pgo"
        else "",
    )
    for warning in warnings:
        print(f"warning: {warning}", file=sys.stderr)
    if args.out is None:
        sys.stdout.write(contents)
    else:
        write_export(args.out, contents)
    return 0


def _relative_to(path: Path, folder: Path) -> str:
    """A path as the exported file should name it: relative to the export's folder where possible."""
    try:
        return str(path.resolve().relative_to(folder.resolve()))
    except ValueError:
        return str(path.resolve())


def _run_quality(args: argparse.Namespace) -> int:
    from .motion.quality import compare_modes, format_quality

    result = _lip_sync(args)
    report = compare_modes(result.timeline, args.fps, args.emotion_strength)
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
    }


def tracks_as_dict(tracks: WeightTracks) -> dict:
    """The weight tracks as Blender keys them: frames from 0 (the scene's start frame) and weights."""
    return {
        "fps": tracks.fps,
        "frame_count": tracks.frame_count,
        "interpolation": tracks.interpolation,
        "mode": tracks.mode,
        "keys": {
            track.name: {"frames": track.frames.tolist(), "values": track.values.tolist()}
            for track in tracks.tracks
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
    return "\n".join(lines)
