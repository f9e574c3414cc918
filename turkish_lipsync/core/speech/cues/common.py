"""What every cue file holds: mouth shapes A-H and X over time; the format class and the readers' checks.

A cue format is one class (`CueFormat`): its name, the file suffixes it is read from, a label for the UI,
`read` (a file to a `CueSource`) and `write` (a timeline to the file's text). Each lives in a module of its
own in this package and registers itself with `@register` in `CUE_FORMATS`; the exports (interchange/) and
the cue timing source (speech/sources/cue_file.py) find them by name or by suffix. Rhubarb's JSON and XML
are one document in two syntaxes (`RhubarbResult`): each parses and writes its own.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from ...base.errors import LipSyncError
from ...base.files import read_user_text
from ...base.model import Timeline
from ...base.registry import Registry
from .shapes import REST, SHAPES, shape_for_viseme

SHORTEST = 1e-6  # seconds: cues shorter than this carry nothing and are dropped
# A cue file holds about ten mouth changes a second: a million is more than a day of speech. Larger files
# are refused before they are parsed (a 50 MB file of 4 million cues in well under a second).
MAX_CUES = 1_000_000
MAX_FILE_BYTES = 256 * 1024 * 1024


class CueFileError(LipSyncError):
    """A cue or timing file that cannot be read."""


@dataclass(frozen=True)
class MouthCue:
    start: float  # seconds
    end: float
    shape: str  # one of SHAPES


@dataclass(frozen=True)
class CueSource:
    """What a timing file holds: cues, its length, its own text where it has one, and word spans."""

    path: Path
    cues: tuple[MouthCue, ...]
    duration: float
    text: str = ""
    sound_file: str = ""
    word_cues: tuple[tuple[str, tuple[MouthCue, ...]], ...] = ()  # per word (Papagayo): text, its cues
    warnings: tuple[str, ...] = ()


class CueFormat:
    """One cue file format: read into cues, written from a timeline."""

    name: str = ""  # the identifier of the format in the CLI, the panel and render.py --export
    suffixes: tuple[str, ...] = ()  # the first is the one written
    label: str = ""
    description: str = ""  # what it is and who reads it
    order: int = 0  # place among the formats (the panel's list)

    def read(self, path: Path, fps: float) -> CueSource:
        raise NotImplementedError

    def write(
        self, timeline: Timeline, fps: float, *, sound_file: str = "", text: str = ""
    ) -> tuple[str, tuple[str, ...]]:
        """The file's contents and warnings for what the format could not hold."""
        raise NotImplementedError


class RhubarbResult(CueFormat):
    """Rhubarb Lip Sync's result as a document (its JSON, its XML): metadata (the sound file and the
    duration) and the mouth cues, each a start, an end and a shape. A subclass parses its syntax into
    records and writes the cues in it."""

    def read(self, path: Path, fps: float) -> CueSource:
        records, duration, sound_file = self.parse(path, read_text(path))
        return source_from_records(path, records, duration, sound_file)

    def parse(self, path: Path, text: str) -> tuple[list[tuple[str, object, object, object]], object, str]:
        """The document's (where, start, end, shape) records, its duration (None where it gives none)
        and its sound file."""
        raise NotImplementedError

    def write(
        self, timeline: Timeline, fps: float, *, sound_file: str = "", text: str = ""
    ) -> tuple[str, tuple[str, ...]]:
        return self.document(mouth_cues(timeline), timeline.duration, sound_file), ()

    def document(self, cues: tuple[MouthCue, ...], duration: float, sound_file: str) -> str:
        raise NotImplementedError


CUE_FORMATS: Registry[CueFormat] = Registry("cue format", __package__, Path(__file__).parent)
register = CUE_FORMATS.register


def mouth_cues(timeline: Timeline) -> tuple[MouthCue, ...]:
    """The timeline's phones and hesitations said aloud as Rhubarb shapes: rest (X) in the silences, equal
    neighbours merged."""
    raw: list[MouthCue] = []
    time = 0.0
    sounds = sorted((*timeline.phones, *timeline.hesitations), key=lambda sound: sound.start)
    for index, sound in enumerate(sounds):
        end = sound.end if index + 1 == len(sounds) else min(sound.end, sounds[index + 1].start)
        start = max(sound.start, time)
        if start - time > SHORTEST:
            raw.append(MouthCue(time, start, REST))
        if end - start > SHORTEST:
            raw.append(MouthCue(start, end, shape_for_viseme(sound.viseme)))
            time = end
        else:
            time = max(time, start)
    if timeline.duration - time > SHORTEST or not raw:
        raw.append(MouthCue(time, max(time, timeline.duration), REST))
    return merge_cues(raw)


def merge_cues(cues: list[MouthCue] | tuple[MouthCue, ...]) -> tuple[MouthCue, ...]:
    merged: list[MouthCue] = []
    for cue in cues:
        if merged and merged[-1].shape == cue.shape and abs(merged[-1].end - cue.start) < SHORTEST:
            merged[-1] = MouthCue(merged[-1].start, cue.end, cue.shape)
        else:
            merged.append(cue)
    return tuple(merged)


def frame_of(seconds: float, fps: float) -> int:
    """The frame showing the instant `seconds` (frame 0 starts at 0 s), robust to float noise."""
    return math.floor(seconds * fps + 1e-6)


# ---------------------------------------------------------------- what the readers share


def read_text(path: Path) -> str:
    try:
        size = Path(path).stat().st_size
    except OSError:
        size = 0  # read_user_text says what is wrong with the path
    if size > MAX_FILE_BYTES:
        raise CueFileError(
            f"{path}: {size / 1e6:.0f} MB is more than a cue file of a day of speech; is it one?"
        )
    return read_user_text(path, "cue file", CueFileError)


def read_counted(path: Path) -> str:
    """The text of a file of a cue a line, refused before it is parsed where it has more lines than
    MAX_CUES."""
    text = read_text(path)
    check_cue_count(path, text.count("\n"))
    return text


def check_cue_count(path: Path, count: int) -> None:
    """Refuse a file of more cues than MAX_CUES (counted before the cues are parsed one by one)."""
    if count > MAX_CUES:
        raise CueFileError(
            f"{path}: {count:,} mouth cues are more than the {MAX_CUES:,} (over a day of speech) a cue file "
            "may hold; split the recording and its cue file"
        )


def checked_shape(path: Path, where: str, value: object) -> str:
    shape = str(value).strip()
    if shape not in SHAPES:
        raise CueFileError(f"{path}: {where}: mouth shape {shape!r} is not one of {', '.join(SHAPES)}")
    return shape


def checked_time(path: Path, where: str, value: object) -> float:
    try:
        seconds = float(value)
    except (TypeError, ValueError):
        raise CueFileError(f"{path}: {where}: time {value!r} is not a number of seconds") from None
    if not 0 <= seconds < 1e6:
        raise CueFileError(f"{path}: {where}: time {seconds} is out of range")
    return seconds


def ordered(path: Path, cues: list[MouthCue]) -> tuple[MouthCue, ...]:
    if not cues:
        raise CueFileError(f"{path}: holds no mouth cues")
    for previous, cue in zip(cues, cues[1:], strict=False):
        if cue.start < previous.start - SHORTEST:
            raise CueFileError(
                f"{path}: the cue at {cue.start:.3f} s comes before the one at {previous.start:.3f} s"
            )
        if cue.start < previous.end - SHORTEST:
            raise CueFileError(
                f"{path}: the cue at {cue.start:.3f} s begins before the one before it ends "
                f"({previous.end:.3f} s): cues may not overlap"
            )
    return tuple(cues)


def source_from_records(
    path: Path, records: list[tuple[str, object, object, object]], duration: object, sound_file: str
) -> CueSource:
    """A file's cues from its (where, start, end, shape) records, each checked, and its length (the last
    cue's end where the file does not say)."""
    cues = ordered(path, _cues_from_records(path, records))
    length = checked_time(path, "duration", cues[-1].end if duration is None else duration)
    return CueSource(path, cues, length, sound_file=sound_file)


def _cues_from_records(path: Path, records: list[tuple[str, object, object, object]]) -> list[MouthCue]:
    """Cues from (where, start, end, shape) records, each checked (an end before its start is refused)."""
    cues = []
    for where, start, end, shape in records:
        begin = checked_time(path, where, start)
        finish = checked_time(path, where, end)
        if finish < begin:
            raise CueFileError(f"{path}: {where}: ends ({finish}) before it starts ({begin})")
        cues.append(MouthCue(begin, finish, checked_shape(path, where, shape)))
    return cues
