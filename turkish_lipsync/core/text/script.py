"""A script with speakers: the lines of a conversation, each with its speaker, its addressee and its markup.

Two ways to write one, both read here into the same `Script`:

- JSML: every line is a `<VOICE NAME="Ayşe" GENDER="female" TO="Ali">...</VOICE>` element (JSML's and SSML's
  way of naming a voice); everything inside keeps the usual tags (emotions, BREAK, EMP, PROS, SAYAS). A BREAK
  between two VOICE elements (or at the start of a line) is the silence before the next line;
  `OVERLAP="yes"` (or `OVERLAP="300ms"`) starts the line before the previous one ends.
- A screenplay: one cue a line, `AYŞE: Merhaba, nasılsın?`; a line that starts with no cue continues the
  line before. Notes in parentheses after the name: `AYŞE (to ALİ): ...`, `ALİ (overlapping): ...`,
  `AYŞE (to camera): ...`, `ALİ (male): ...`, several separated by commas; a line entirely in parentheses is
  a stage direction and is not spoken. The text after the colon may hold the usual tags.

A text is a screenplay when its first line that is not a stage direction starts with a cue, and the name is
written in capitals or a second cue follows (so "Not: yarın tatil." stays one speaker's text). Names are the
same speaker whatever their case, folded the Turkish way (AYŞE, Ayşe; ALİ, Ali).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace

from ..base.errors import MarkupError
from ..base.model import Pause, TextRun
from .jsml import CAMERA_WORDS, GENDER_WORDS, VoiceMarkup, markup_error, parse_jsml, parse_jsml_voices
from .tables import turkish_lower, turkish_upper

CAMERA = "camera"  # the addressee of a line said to the camera (the viewer)

# A cue: a name (letters, spaces, apostrophes, dots, hyphens; at most four words), notes in parentheses,
# a colon. Digits never make a name, so "Saat 10:30" is no cue.
_CUE = re.compile(
    r"^(?P<indent>[ \t]*)(?P<name>[^\W\d_](?:[^\W\d_]|['’.\- ]){0,39}?)[ \t]*"
    r"(?:\((?P<notes>[^()\n]*)\))?[ \t]*:(?P<gap>[ \t]*)",
    re.MULTILINE,
)
_DIRECTION = re.compile(r"^[ \t]*\([^()\n]*\)[ \t]*$")
_MAX_NAME_WORDS = 4
_ADDRESS_NOTE = re.compile(r"^(?:to|için|->)\s+(?P<who>.+)$", re.IGNORECASE)
_OVERLAP_NOTES = frozenset({"overlapping", "overlap", "overlaps", "üst üste", "araya girerek"})
_CAMERA_NOTES = frozenset({"kameraya", "seyirciye"})


@dataclass(frozen=True)
class ScriptLine:
    """One speaker's turn: its markup, read as usual, with offsets into the whole script."""

    speaker: str  # the speaker's key (speaker_key)
    addressee: str | None  # a speaker's key, CAMERA, or None (the last other speaker, see Script)
    items: tuple[TextRun | Pause, ...]
    offset: int  # source index where the line begins (its cue or its <VOICE>)
    overlaps: bool = False  # starts before the previous line ends
    overlap: float | None = None  # how much (seconds); None: the usual amount
    pause_before: float | None = None  # seconds of silence the markup asks for before it; None: a usual gap


@dataclass(frozen=True)
class ScriptSpeaker:
    key: str  # speaker_key of the name
    name: str  # as first written
    gender: str | None = None  # "female", "male", or None where the script does not say
    variant: str | None = None  # a voice the markup asks for (VARIANT)
    offset: int = 0  # where the script first names them


@dataclass(frozen=True)
class Script:
    source: str
    lines: tuple[ScriptLine, ...]
    speakers: tuple[ScriptSpeaker, ...]  # in the order they first speak

    def speaker(self, key: str) -> ScriptSpeaker:
        return next(speaker for speaker in self.speakers if speaker.key == key)

    def addressees(self) -> tuple[str, ...]:
        """Whom each line is said to: as written, else the last other speaker before it, else the next
        other speaker after it, else the camera (a script of one speaker)."""
        found = []
        for index, line in enumerate(self.lines):
            if line.addressee is not None:
                found.append(line.addressee)
                continue
            before = [other.speaker for other in self.lines[:index] if other.speaker != line.speaker]
            after = [other.speaker for other in self.lines[index + 1 :] if other.speaker != line.speaker]
            found.append(before[-1] if before else after[0] if after else CAMERA)
        return tuple(found)


def speaker_key(name: str) -> str:
    """The same speaker whatever the case and spacing of the name: folded the Turkish way (İ -> i, I -> ı)."""
    return turkish_lower(" ".join(name.split()))


def display_name(name: str) -> str:
    """A speaker's name as the panel and the strips show it: as written, capitals made a name (AYŞE ->
    Ayşe), the Turkish way."""
    words = " ".join(name.split()).split(" ")
    if all(word == turkish_upper(word) for word in words):
        return " ".join(turkish_upper(word[:1]) + turkish_lower(word[1:]) for word in words)
    return " ".join(words)


def read_script(source: str) -> Script | None:
    """The script's lines and speakers, or None for a text with no speakers (one head speaks it all)."""
    if _VOICE_TAG.search(source):
        return _read_voices(source)
    cues = _screenplay_cues(source)
    return _read_screenplay(source, cues) if cues else None


def has_speakers(source: str) -> bool:
    """Whether the text is a script with speakers (without reading its lines: cheap enough for a panel's
    redraw; read_script says what is wrong with it)."""
    return bool(_VOICE_TAG.search(source) or _screenplay_cues(source))


_VOICE_TAG = re.compile(r"<\s*voice[\s>/]", re.IGNORECASE)


# ---------------------------------------------------------------- JSML with VOICE elements


def _read_voices(source: str) -> Script:
    items, voice_of_item, voices = parse_jsml_voices(source)
    grouped: dict[int, list[TextRun | Pause]] = {index: [] for index in range(len(voices))}
    pending: dict[int, float] = {}  # BREAKs outside any VOICE, before the VOICE that follows them
    for item, voice in zip(items, voice_of_item, strict=True):
        if voice is not None:
            grouped[voice].append(item)
        elif isinstance(item, TextRun):
            start = next(
                (o for o, c in zip(item.offsets, item.text, strict=True) if not c.isspace()), item.offsets[0]
            )
            raise markup_error(
                source,
                start,
                "text outside any <VOICE> in a script with speakers: every word has a speaker; put it in "
                '<VOICE NAME="...">',
            )
        elif item.kind == "break":
            following = next(
                (index for index, markup in enumerate(voices) if markup.offset > item.offset), None
            )
            if following is not None:
                pending[following] = pending.get(following, 0.0) + item.seconds
    speakers: dict[str, ScriptSpeaker] = {}
    lines = []
    for index, markup in enumerate(voices):
        _check_speaker(source, markup, speakers)
        lines.append(
            _line(
                speaker_key(markup.name),
                _addressee(markup.addressee),
                grouped[index],
                markup.offset,
                markup.overlaps,
                markup.overlap,
                pending.get(index),
            )
        )
    return _script(source, lines, speakers)


def _check_speaker(source: str, markup: VoiceMarkup, speakers: dict[str, ScriptSpeaker]) -> None:
    """Record a speaker the first time they speak; later lines may repeat their gender and voice, never
    contradict them."""
    key = speaker_key(markup.name)
    known = speakers.get(key)
    if known is None:
        speakers[key] = ScriptSpeaker(key, markup.name, markup.gender, markup.variant, markup.offset)
        return
    for what, before, now in (
        ("GENDER", known.gender, markup.gender),
        ("VARIANT", known.variant, markup.variant),
    ):
        if now is not None and before is not None and now != before:
            raise markup_error(
                source,
                markup.offset,
                f"{markup.name} was given {what}={before!r} before and {now!r} here; a speaker keeps one "
                "voice",
            )
    speakers[key] = ScriptSpeaker(
        key, known.name, known.gender or markup.gender, known.variant or markup.variant, known.offset
    )


def _addressee(written: str | None) -> str | None:
    if written is None:
        return None
    return CAMERA if turkish_lower(written) in CAMERA_WORDS else speaker_key(written)


def _line(speaker, addressee, items, offset, overlaps, overlap, pause_before) -> ScriptLine:
    """A line's items with its leading and trailing BREAKs taken as the silence before it (trailing ones
    go to the next line: _script moves them)."""
    items = list(items)
    while items and isinstance(items[0], Pause):
        pause = items.pop(0)
        if pause.kind == "break":
            pause_before = (pause_before or 0.0) + pause.seconds
    return ScriptLine(speaker, addressee, tuple(items), offset, overlaps, overlap, pause_before)


def _script(source: str, lines: list[ScriptLine], speakers: dict[str, ScriptSpeaker]) -> Script:
    """The script, every line's trailing BREAKs moved to the silence before the next line, and each
    addressee checked to be a speaker or the camera."""
    moved = []
    carried = None
    for line in lines:
        if carried is not None:
            line = replace(line, pause_before=(line.pause_before or 0.0) + carried)
        items = list(line.items)
        carried = None
        while items and isinstance(items[-1], Pause) and items[-1].kind == "break":
            carried = (carried or 0.0) + items.pop().seconds
        if not any(isinstance(item, TextRun) for item in items):
            raise markup_error(
                source, line.offset, f"{speakers[line.speaker].name}'s line says nothing; give it some text"
            )
        moved.append(replace(line, items=tuple(items)))
    for line in moved:
        if line.addressee not in (None, CAMERA) and line.addressee not in speakers:
            known = ", ".join(speaker.name for speaker in speakers.values())
            raise markup_error(
                source,
                line.offset,
                f"the line is said to {line.addressee!r}, who never speaks; name one of {known} or the "
                "camera",
            )
    return Script(source, tuple(moved), tuple(speakers.values()))


# ---------------------------------------------------------------- screenplay


def _screenplay_cues(source: str) -> list[re.Match]:
    """The cue of every line that has one, when the text is a screenplay (see the module's text)."""
    cues = []
    first_seen = False
    position = 0
    for raw in source.splitlines(keepends=True):
        text = raw.rstrip("\r\n")
        if text.strip() and not _DIRECTION.match(text):
            match = _CUE.match(source, position, position + len(text))
            if match and len(match.group("name").split()) > _MAX_NAME_WORDS:
                match = None
            if not first_seen:
                if match is None:
                    return []
                first_seen = True
            if match is not None:
                cues.append(match)
        position += len(raw)
    if not cues:
        return []
    first = cues[0].group("name")
    in_capitals = first == turkish_upper(first) and first != turkish_lower(first)
    return cues if in_capitals or len(cues) >= 2 else []


def _read_screenplay(source: str, cues: list[re.Match]) -> Script:
    speakers: dict[str, ScriptSpeaker] = {}
    lines = []
    for number, cue in enumerate(cues):
        end = cues[number + 1].start() if number + 1 < len(cues) else len(source)
        text_start = cue.end()
        text = _without_directions(source[text_start:end])
        name = " ".join(cue.group("name").split())
        addressee, overlaps, gender = _notes(source, cue)
        key = speaker_key(name)
        if key not in speakers:
            speakers[key] = ScriptSpeaker(key, display_name(name), gender, None, cue.start("name"))
        elif gender is not None and speakers[key].gender not in (None, gender):
            raise markup_error(
                source,
                cue.start("notes"),
                f"{name} was given another gender before; a speaker keeps one voice",
            )
        elif gender is not None:
            speakers[key] = ScriptSpeaker(key, speakers[key].name, gender, None, speakers[key].offset)
        try:
            items = parse_jsml(text)
        except MarkupError as error:
            raise _moved_error(source, text_start, text, error) from None
        items = tuple(_shifted(item, text_start) for item in items)
        lines.append(_line(key, addressee, items, cue.start("name"), overlaps, None, None))
    return _script(source, lines, speakers)


def _without_directions(text: str) -> str:
    """The text with stage directions (lines entirely in parentheses) blanked, offsets kept."""
    return "".join(
        " " * len(line.rstrip("\r\n")) + line[len(line.rstrip("\r\n")) :] if _DIRECTION.match(line) else line
        for line in text.splitlines(keepends=True)
    )


def _notes(source: str, cue: re.Match) -> tuple[str | None, bool, str | None]:
    """(addressee, overlaps, gender) of a cue's notes in parentheses."""
    addressee, overlaps, gender = None, False, None
    notes = cue.group("notes")
    if not notes:
        return addressee, overlaps, gender
    position = cue.start("notes")
    for note in notes.split(","):
        word = turkish_lower(" ".join(note.split()))
        where = position + (len(note) - len(note.lstrip()))
        position += len(note) + 1
        address = _ADDRESS_NOTE.match(word)
        if address:
            addressee = _addressee(address.group("who"))
        elif word in _CAMERA_NOTES:
            addressee = CAMERA
        elif word in _OVERLAP_NOTES:
            overlaps = True
        elif word in GENDER_WORDS:
            gender = GENDER_WORDS[word]
        elif word:
            raise markup_error(
                source,
                where,
                f"({note.strip()}) is not a note this reader knows: write (to NAME), (to camera), "
                "(overlapping), (female) or (male), several separated by commas",
            )
    return addressee, overlaps, gender


def _shifted(item: TextRun | Pause, offset: int) -> TextRun | Pause:
    if isinstance(item, TextRun):
        return TextRun(item.text, tuple(o + offset for o in item.offsets), item.style)
    return Pause(item.seconds, item.offset + offset, item.kind)


def _moved_error(source: str, start: int, text: str, error: MarkupError) -> MarkupError:
    """A markup error in a line's text, pointed at in the whole script."""
    lines = text.split("\n")
    index = sum(len(line) + 1 for line in lines[: error.line - 1]) + error.column - 1
    return markup_error(source, start + index, error.message)
