"""Rhubarb-compatible mouth cues: the timeline as shapes A-H and X over time, in TSV, JSON and XML.

The files are those Rhubarb Lip Sync writes, so every tool that reads Rhubarb's output (the plugins for
Spine, Godot, Unity, After Effects, Blender's Rhubarb add-ons) animates a 2D mouth in Turkish from them.
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ElementTree
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

from ..errors import LipSyncError
from ..model import Timeline
from .shapes import REST, SHAPES, shape_for_viseme

_SHORTEST = 1e-6  # seconds: cues shorter than this carry nothing and are dropped


class CueFileError(LipSyncError):
    """A cue or timing file that cannot be read."""


@dataclass(frozen=True)
class MouthCue:
    start: float  # seconds
    end: float
    shape: str  # one of SHAPES


def mouth_cues(timeline: Timeline) -> tuple[MouthCue, ...]:
    """The timeline's phones as Rhubarb shapes: rest (X) in the silences, equal neighbours merged."""
    raw: list[MouthCue] = []
    time = 0.0
    phones = sorted(timeline.phones, key=lambda phone: phone.start)
    for index, phone in enumerate(phones):
        end = phone.end if index + 1 == len(phones) else min(phone.end, phones[index + 1].start)
        start = max(phone.start, time)
        if start - time > _SHORTEST:
            raw.append(MouthCue(time, start, REST))
        if end - start > _SHORTEST:
            raw.append(MouthCue(start, end, shape_for_viseme(phone.viseme)))
            time = end
        else:
            time = max(time, start)
    if timeline.duration - time > _SHORTEST or not raw:
        raw.append(MouthCue(time, max(time, timeline.duration), REST))
    return merge_cues(raw)


def merge_cues(cues: list[MouthCue] | tuple[MouthCue, ...]) -> tuple[MouthCue, ...]:
    merged: list[MouthCue] = []
    for cue in cues:
        if merged and merged[-1].shape == cue.shape and abs(merged[-1].end - cue.start) < _SHORTEST:
            merged[-1] = MouthCue(merged[-1].start, cue.end, cue.shape)
        else:
            merged.append(cue)
    return tuple(merged)


# ---------------------------------------------------------------- writers


def cues_as_tsv(cues: tuple[MouthCue, ...]) -> str:
    """Rhubarb's TSV: one line per cue, its start and shape; each cue lasts until the next line."""
    lines = [f"{cue.start:.3f}\t{cue.shape}" for cue in cues]
    if cues and cues[-1].shape != REST:
        lines.append(f"{cues[-1].end:.3f}\t{REST}")
    return "\n".join(lines) + "\n"


def cues_as_json(cues: tuple[MouthCue, ...], duration: float, sound_file: str = "") -> str:
    document = {
        "metadata": {"soundFile": sound_file, "duration": round(duration, 3)},
        "mouthCues": [
            {"start": round(cue.start, 3), "end": round(cue.end, 3), "value": cue.shape} for cue in cues
        ],
    }
    return json.dumps(document, indent=2) + "\n"


def cues_as_xml(cues: tuple[MouthCue, ...], duration: float, sound_file: str = "") -> str:
    lines = [
        '<?xml version="1.0" encoding="utf-8"?>',
        "<rhubarbResult>",
        "  <metadata>",
        f"    <soundFile>{escape(sound_file)}</soundFile>",
        f"    <duration>{duration:.3f}</duration>",
        "  </metadata>",
        "  <mouthCues>",
    ]
    lines += [
        f"    <mouthCue start={quoteattr(f'{cue.start:.3f}')} end={quoteattr(f'{cue.end:.3f}')}>"
        f"{cue.shape}</mouthCue>"
        for cue in cues
    ]
    lines += ["  </mouthCues>", "</rhubarbResult>"]
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------- readers


def read_text(path: Path) -> str:
    try:
        return Path(path).read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise CueFileError(f"{path}: no such file") from None
    except UnicodeDecodeError as error:
        raise CueFileError(f"{path}: not UTF-8 text (byte {error.start}); save it as UTF-8") from None
    except OSError as error:
        raise CueFileError(f"{path}: cannot read it ({error.strerror})") from None


def _checked_shape(path: Path, where: str, value: object) -> str:
    shape = str(value).strip()
    if shape not in SHAPES:
        raise CueFileError(f"{path}: {where}: mouth shape {shape!r} is not one of {', '.join(SHAPES)}")
    return shape


def _checked_time(path: Path, where: str, value: object) -> float:
    try:
        seconds = float(value)
    except (TypeError, ValueError):
        raise CueFileError(f"{path}: {where}: time {value!r} is not a number of seconds") from None
    if not 0 <= seconds < 1e6:
        raise CueFileError(f"{path}: {where}: time {seconds} is out of range")
    return seconds


def _ordered(path: Path, cues: list[MouthCue]) -> tuple[MouthCue, ...]:
    if not cues:
        raise CueFileError(f"{path}: holds no mouth cues")
    for previous, cue in zip(cues, cues[1:], strict=False):
        if cue.start < previous.start - _SHORTEST:
            raise CueFileError(
                f"{path}: the cue at {cue.start:.3f} s comes before the one at {previous.start:.3f} s"
            )
    return tuple(cues)


def read_rhubarb_tsv(path: Path) -> tuple[tuple[MouthCue, ...], float]:
    """Cues and duration of a Rhubarb TSV file (the last cue ends where the file's last line starts)."""
    starts: list[tuple[float, str]] = []
    for number, line in enumerate(read_text(path).splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        fields = line.split("\t") if "\t" in line else line.split()
        if len(fields) < 2:
            raise CueFileError(f"{path}: line {number}: expected 'START<TAB>SHAPE', got {line!r}")
        where = f"line {number}"
        starts.append((_checked_time(path, where, fields[0]), _checked_shape(path, where, fields[1])))
    if not starts:
        raise CueFileError(f"{path}: holds no mouth cues")
    cues = [MouthCue(start, end, shape) for (start, shape), (end, _) in zip(starts, starts[1:], strict=False)]
    last_start, last_shape = starts[-1]
    if last_shape != REST or not cues:
        cues.append(MouthCue(last_start, last_start, last_shape))
    return _ordered(path, cues), last_start


def _cues_from_records(path: Path, records: list[tuple[str, object, object, object]]) -> list[MouthCue]:
    cues = []
    for where, start, end, shape in records:
        begin = _checked_time(path, where, start)
        finish = _checked_time(path, where, end)
        if finish < begin:
            raise CueFileError(f"{path}: {where}: ends ({finish}) before it starts ({begin})")
        cues.append(MouthCue(begin, finish, _checked_shape(path, where, shape)))
    return cues


def read_rhubarb_json(path: Path) -> tuple[tuple[MouthCue, ...], float, str]:
    """Cues, duration and sound file of a Rhubarb JSON file."""
    try:
        document = json.loads(read_text(path))
    except json.JSONDecodeError as error:
        raise CueFileError(f"{path}: line {error.lineno}: not valid JSON ({error.msg})") from None
    entries = document.get("mouthCues") if isinstance(document, dict) else None
    if not isinstance(entries, list):
        raise CueFileError(f"{path}: no 'mouthCues' list: is this a Rhubarb JSON file?")
    records = []
    for index, entry in enumerate(entries):
        if not isinstance(entry, dict):
            raise CueFileError(f"{path}: mouthCues[{index}] must be an object with start, end and value")
        records.append((f"mouthCues[{index}]", entry.get("start"), entry.get("end"), entry.get("value")))
    cues = _ordered(path, _cues_from_records(path, records))
    metadata = document.get("metadata") if isinstance(document.get("metadata"), dict) else {}
    duration = metadata.get("duration", cues[-1].end)
    return cues, _checked_time(path, "metadata.duration", duration), str(metadata.get("soundFile", ""))


def read_rhubarb_xml(path: Path) -> tuple[tuple[MouthCue, ...], float, str]:
    """Cues, duration and sound file of a Rhubarb XML file (documents with a DTD or entities are refused)."""
    text = read_text(path)
    if "<!DOCTYPE" in text or "<!ENTITY" in text:
        raise CueFileError(f"{path}: XML with a DTD or entities is not read; Rhubarb never writes them")
    try:
        root = ElementTree.fromstring(text)
    except ElementTree.ParseError as error:
        line, column = error.position
        raise CueFileError(f"{path}: line {line}, column {column}: not valid XML") from None
    records = [
        (f"mouthCue {index + 1}", element.get("start"), element.get("end"), (element.text or "").strip())
        for index, element in enumerate(root.iter("mouthCue"))
    ]
    cues = _ordered(path, _cues_from_records(path, records))
    duration = root.findtext("metadata/duration") or cues[-1].end
    return cues, _checked_time(path, "duration", duration), root.findtext("metadata/soundFile") or ""
