"""JSML markup to styled text runs and pauses, with a small tokenizer of our own.

XML libraries expand entities and DTDs (the "billion laughs" bomb); this tokenizer knows only the five
predefined entities and numeric character references, and refuses any DTD at once. Every character of a
text run keeps its index in the source, so later stages can point back at what the user wrote.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace
from functools import cache

from ..base.data import DATA_DIR, load_table
from ..base.errors import DataError, MarkupError
from ..base.model import EMOTIONS, Pause, Style, TextRun

# Table 5.3's tags, the variant spellings the thesis's own text uses (ANGER, FEAR, ...) and a few more.
EMOTION_TAGS: dict[str, str] = {
    "HAPPY": "happy",
    "HAPPINESS": "happy",
    "JOY": "happy",
    "SAD": "sad",
    "SADNESS": "sad",
    "ANGRY": "angry",
    "ANGER": "angry",
    "AFRAID": "afraid",
    "FEAR": "afraid",
    "FEARFUL": "afraid",
    "SCARED": "afraid",
    "SURPRISED": "surprised",
    "SURPRISE": "surprised",
    "DISGUSTED": "disgusted",
    "DISGUST": "disgusted",
}
assert set(EMOTION_TAGS.values()) == set(EMOTIONS)

# JSML's containers that change nothing we animate; their text is spoken as usual.
_NEUTRAL_CONTAINERS = frozenset({"JSML", "ENGINE", "SAYAS", "DIV"})
_EMPTY_ELEMENTS = frozenset({"BREAK", "MARKER"})
_KNOWN_TAGS = (
    frozenset(EMOTION_TAGS) | _NEUTRAL_CONTAINERS | _EMPTY_ELEMENTS | {"SENT", "PARA", "PROS", "EMP", "VOICE"}
)
# <VOICE>: who speaks (JSML's and SSML's NAME and GENDER, JSML's VARIANT), to whom (TO: a speaker's name or
# "camera") and whether the line overlaps the end of the one before (OVERLAP: yes, or how much: 300ms).
VOICE_ATTRIBUTES = frozenset({"NAME", "GENDER", "VARIANT", "TO", "OVERLAP"})
GENDER_WORDS = {"female": "female", "kadın": "female", "male": "male", "erkek": "male", "neutral": None}
CAMERA_WORDS = frozenset({"camera", "kamera", "audience", "seyirci"})
_OVERLAP_WORDS = {"yes": True, "true": True, "evet": True, "no": False, "false": False, "hayır": False}

# The words/min JSML assumes for RATE, and the descriptive values of PROS (multipliers of the default).
DEFAULT_WORDS_PER_MINUTE = 175.0
_RATE_WORDS = {"xslow": 0.6, "slow": 0.8, "medium": 1.0, "fast": 1.25, "xfast": 1.5, "default": 1.0}
_PITCH_WORDS = {"xlow": 0.7, "low": 0.85, "medium": 1.0, "high": 1.15, "xhigh": 1.3, "default": 1.0}
_VOLUME_WORDS = {
    "silent": 0.0,
    "xsoft": 0.4,
    "soft": 0.7,
    "medium": 1.0,
    "loud": 1.3,
    "xloud": 1.6,
    "default": 1.0,
}
# An absolute PITCH is in hertz; it is taken relative to a typical speaking voice.
DEFAULT_PITCH_HZ = 120.0

# Attributes JSML defines that change nothing here; accepted and ignored so valid JSML parses.
_IGNORED_ATTRIBUTES = {
    "PROS": {"RANGE"},
    "MARKER": {"MARK"},
    "ENGINE": {"ENGID", "DATA"},
    "JSML": {"LANG", "VERSION"},
    "PARA": {"LANG", "MARK"},
    "SENT": {"LANG", "MARK"},
    "DIV": {"TYPE", "LANG", "MARK"},
    "EMP": {"MARK"},
    "BREAK": {"MARK"},
    "VOICE": {"AGE"},
}

_ENTITIES = {"lt": "<", "gt": ">", "amp": "&", "quot": '"', "apos": "'"}
_SPECIAL = re.compile(r"[<&]")
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_.\-]*")
_SPACE = re.compile(r"\s*")
_ENTITY = re.compile(r"&(#[0-9]{1,8}|#[xX][0-9A-Fa-f]{1,8}|[A-Za-z][A-Za-z0-9]{0,31});")
_UNQUOTED_VALUE = re.compile(r"[^\s>/\"'<=]+")
_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)")


@dataclass(frozen=True)
class VoiceMarkup:
    """A <VOICE> element: who speaks its text, to whom, and whether it overlaps the line before."""

    name: str
    offset: int  # source index of the element's '<'
    gender: str | None = None  # "female", "male" or None (not said)
    variant: str | None = None  # the voice asked for (VARIANT), checked against the cast's voices
    addressee: str | None = None  # a speaker's name, "camera", or None (the last speaker)
    overlaps: bool = False
    overlap: float | None = None  # seconds, where the markup says how much


@cache
def pause_seconds() -> dict[str, dict[str, float]]:
    """shapekeys/pauses.toml, validated: seconds of silence per BREAK size and per punctuation kind."""
    table = load_table("pauses")
    path = DATA_DIR / "pauses.toml"
    result: dict[str, dict[str, float]] = {}
    required = {
        "break_size": ("none", "small", "medium", "large"),
        "punctuation": ("comma", "clause", "sentence", "question", "exclamation", "paragraph"),
    }
    for section, keys in required.items():
        values = table.get(section)
        if not isinstance(values, dict):
            raise DataError(f"data file {path}: section [{section}] is missing")
        for key in keys:
            value = values.get(key)
            if isinstance(value, bool) or not isinstance(value, int | float) or not 0 <= value <= 10:
                raise DataError(
                    f"data file {path}: [{section}] {key} must be seconds in 0..10, got {value!r}"
                )
        result[section] = {key: float(value) for key, value in values.items()}
    return result


class _Open:
    """An element on the stack of open elements; a SAYAS that overrides its reading holds the new text."""

    __slots__ = ("name", "written", "offset", "style", "substitute", "voice")

    def __init__(
        self,
        name: str,
        written: str,
        offset: int,
        style: Style,
        substitute: str | None = None,
        voice: int | None = None,
    ) -> None:
        self.name = name
        self.written = written
        self.offset = offset
        self.style = style
        self.substitute = substitute
        self.voice = voice  # the index of the <VOICE> the element is in


class _Parser:
    def __init__(self, source: str) -> None:
        self.source = source
        # Plain text (no markup at all) may use '&' as a word ("Ali & Veli"); inside markup it must be &amp;.
        self.plain_text = "<" not in source
        self.items: list[TextRun | Pause] = []
        self.voices: list[VoiceMarkup] = []
        self.item_voices: list[int | None] = []  # per item: the <VOICE> it is in
        self.stack: list[_Open] = []
        self.text_parts: list[str] = []
        self.offset_parts: list[range | tuple[int, ...]] = []

    # ------------------------------------------------------------ errors

    def error(self, message: str, index: int, length: int = 20) -> MarkupError:
        return markup_error(self.source, index, message, length)

    # ------------------------------------------------------------ output

    @property
    def style(self) -> Style:
        return self.stack[-1].style if self.stack else Style()

    @property
    def voice(self) -> int | None:
        return self.stack[-1].voice if self.stack else None

    def flush_text(self) -> None:
        if not self.text_parts:
            return
        text = "".join(self.text_parts)
        offsets: list[int] = []
        for part in self.offset_parts:
            offsets.extend(part)
        self.text_parts.clear()
        self.offset_parts.clear()
        if text.strip():
            self.items.append(TextRun(text=text, offsets=tuple(offsets), style=self.style))
            self.item_voices.append(self.voice)

    def add_pause(self, seconds: float, offset: int, kind: str) -> None:
        self.flush_text()
        self.items.append(Pause(seconds=seconds, offset=offset, kind=kind))
        self.item_voices.append(self.voice)

    # ------------------------------------------------------------ scanning

    def parse(self) -> tuple[TextRun | Pause, ...]:
        source = self.source
        position = 0
        length = len(source)
        while position < length:
            match = _SPECIAL.search(source, position)
            end = match.start() if match else length
            if end > position:
                self.text_parts.append(source[position:end])
                self.offset_parts.append(range(position, end))
            if not match:
                break
            if source[end] == "&":
                character, position = self.entity(end)
                self.text_parts.append(character)
                self.offset_parts.append((end,))
            else:
                position = self.markup(end)
        if self.stack:
            unclosed = self.stack[-1]
            raise self.error(
                f"<{unclosed.written}> is never closed; add </{unclosed.written}> where it should end",
                unclosed.offset,
            )
        self.flush_text()
        return tuple(self.items)

    def entity(self, index: int) -> tuple[str, int]:
        match = _ENTITY.match(self.source, index)
        if not match and self.plain_text:
            return "&", index + 1
        if not match:
            raise self.error("a '&' that does not start an entity; write &amp; for a literal '&'", index)
        name = match.group(1)
        if name.startswith("#"):
            digits = name[2:] if name[1] in "xX" else name[1:]
            code = int(digits, 16 if name[1] in "xX" else 10)
            if code == 0 or 0xD800 <= code <= 0xDFFF or code > 0x10FFFF:
                raise self.error(f"&{name}; is not a valid character", index)
            return chr(code), match.end()
        if name not in _ENTITIES:
            raise self.error(
                f"unknown entity &{name};; only &lt; &gt; &amp; &quot; &apos; and &#NNN; are allowed", index
            )
        return _ENTITIES[name], match.end()

    def markup(self, index: int) -> int:
        source = self.source
        if source.startswith("<!--", index):
            end = source.find("-->", index + 4)
            if end < 0:
                raise self.error("a comment that is never closed; end it with -->", index)
            return end + 3
        if source.startswith("<!", index):
            if source[index + 2 : index + 9].upper().startswith(("DOCTYPE", "ENTITY", "ELEMENT", "ATTLIST")):
                raise self.error("DTDs and entity declarations are not allowed in JSML; remove them", index)
            raise self.error(
                "'<!' markup (CDATA, declarations) is not supported; write the text plainly", index
            )
        if source.startswith("<?", index):
            end = source.find("?>", index + 2)
            if end < 0:
                raise self.error("a processing instruction that is never closed; end it with ?>", index)
            return end + 2
        if source.startswith("</", index):
            return self.closing_tag(index)
        return self.opening_tag(index)

    def tag_name(self, index: int, start: int) -> tuple[str, str, int]:
        match = _NAME.match(self.source, start)
        if not match:
            raise self.error("a '<' that does not start a tag; write &lt; for a literal '<'", index)
        written = match.group()
        name = written.upper()
        if name not in _KNOWN_TAGS:
            known = ", ".join(sorted(_KNOWN_TAGS))
            raise self.error(f"unknown tag <{written}>; known tags are {known}", index)
        return name, written, match.end()

    def closing_tag(self, index: int) -> int:
        name, written, position = self.tag_name(index, index + 2)
        position = _SPACE.match(self.source, position).end()
        if not self.source.startswith(">", position):
            raise self.error(f"</{written} is not closed by '>'", index)
        end = position + 1
        if name in _EMPTY_ELEMENTS:
            return end  # <BREAK ...></BREAK>: the element is empty either way
        if not self.stack:
            raise self.error(f"</{written}> closes nothing: no <{written}> is open", index)
        top = self.stack[-1]
        if top.name != name:
            if any(element.name == name for element in self.stack):
                line = self.source.count("\n", 0, top.offset) + 1
                column = top.offset - (self.source.rfind("\n", 0, top.offset) + 1) + 1
                raise self.error(
                    f"</{written}> crosses <{top.written}> (opened at line {line}, column {column}); "
                    f"close </{top.written}> first",
                    index,
                )
            raise self.error(f"</{written}> closes nothing: no <{written}> is open", index)
        if top.substitute is not None:
            self.substitute_text(top)
        self.flush_text()
        self.stack.pop()
        if name == "SENT":
            self.add_pause(pause_seconds()["punctuation"]["sentence"], index, "sentence")
        elif name == "PARA":
            self.add_pause(pause_seconds()["punctuation"]["paragraph"], index, "paragraph")
        return end

    def opening_tag(self, index: int) -> int:
        source = self.source
        name, written, position = self.tag_name(index, index + 1)
        attributes: dict[str, tuple[str, int]] = {}
        while True:
            spaced = _SPACE.match(source, position).end()
            if source.startswith("/>", spaced):
                end, self_closing = spaced + 2, True
                break
            if source.startswith(">", spaced):
                end, self_closing = spaced + 1, False
                break
            if spaced == position:
                raise self.error(f"<{written} is not closed by '>' (or attributes are not separated)", index)
            attribute = _NAME.match(source, spaced)
            if not attribute:
                raise self.error(f"<{written}: expected an attribute name or '>'", spaced)
            key = attribute.group().upper()
            after = _SPACE.match(source, attribute.end()).end()
            if not source.startswith("=", after):
                raise self.error(
                    f'attribute {attribute.group()} has no value; write {attribute.group()}="..."', spaced
                )
            value_start = _SPACE.match(source, after + 1).end()
            value, position = self.attribute_value(value_start)
            if key in attributes:
                raise self.error(f"attribute {attribute.group()} is given twice", spaced)
            attributes[key] = (value, spaced)
        self.apply_element(name, written, index, attributes, self_closing)
        return end

    def attribute_value(self, start: int) -> tuple[str, int]:
        source = self.source
        if start < len(source) and source[start] in "\"'":
            quote = source[start]
            end = source.find(quote, start + 1)
            if end < 0:
                raise self.error("an attribute value whose quote is never closed", start)
            raw = source[start + 1 : end]
            if "<" in raw:
                raise self.error("'<' inside an attribute value; write &lt;", start)
            return self.decode_entities(raw, start + 1), end + 1
        match = _UNQUOTED_VALUE.match(source, start)
        if not match:
            raise self.error('an attribute without a value; write NAME="value"', start)
        return self.decode_entities(match.group(), start), match.end()

    def decode_entities(self, raw: str, start: int) -> str:
        if "&" not in raw:
            return raw
        parts: list[str] = []
        position = 0
        while True:
            ampersand = raw.find("&", position)
            if ampersand < 0:
                parts.append(raw[position:])
                return "".join(parts)
            parts.append(raw[position:ampersand])
            character, after = self.entity(start + ampersand)
            parts.append(character)
            position = after - start

    # ------------------------------------------------------------ elements

    def apply_element(
        self, name: str, written: str, index: int, attributes: dict[str, tuple[str, int]], self_closing: bool
    ) -> None:
        allowed = set(_IGNORED_ATTRIBUTES.get(name, ()))
        if name in EMOTION_TAGS:
            allowed |= {"WEIGHT"}
        elif name == "BREAK":
            allowed |= {"MSECS", "SIZE", "TIME"}
        elif name == "PROS":
            allowed |= {"RATE", "PITCH", "VOL"}
        elif name == "EMP":
            allowed |= {"LEVEL"}
        elif name == "SAYAS":
            allowed |= {"SUB", "CLASS"}
        elif name == "VOICE":
            allowed |= VOICE_ATTRIBUTES
        for key, (_value, where) in attributes.items():
            if key not in allowed:
                expected = ", ".join(sorted(allowed)) or "none"
                raise self.error(f"<{written}> has no attribute {key}; it accepts: {expected}", where)

        if self.stack and self.stack[-1].substitute is not None and name not in _EMPTY_ELEMENTS:
            raise self.error(
                f"<{written}> inside a <SAYAS> that gives its reading; SAYAS holds plain text", index
            )
        if name in _EMPTY_ELEMENTS:
            if name == "BREAK":
                self.add_pause(self.break_seconds(attributes), index, "break")
            return
        if self_closing:
            return  # an empty container (<SENT/>) has no text to style
        style = self.style
        if name in EMOTION_TAGS:
            weight = 1.0
            if "WEIGHT" in attributes:
                weight = self.fraction(*attributes["WEIGHT"], "WEIGHT", "a number from 0 to 1, e.g. 0.5")
            style = replace(style, emotion=EMOTION_TAGS[name], emotion_weight=weight)
        elif name == "PROS":
            style = self.prosody(style, attributes)
        elif name == "EMP":
            level = attributes.get("LEVEL", ("strong", index))
            if level[0].lower() not in ("strong", "moderate", "none", "reduced"):
                raise self.error("LEVEL must be strong, moderate, none or reduced", level[1])
            style = replace(style, emphasis=level[0].lower() in ("strong", "moderate"))
        elif name == "PARA" or name == "SENT":
            pass
        substitute = self.sayas_reading(attributes, index) if name == "SAYAS" else None
        voice = self.voice
        if name == "VOICE":
            if voice is not None:
                raise self.error(
                    "<VOICE> inside another <VOICE>: close the first speaker's line before the next begins",
                    index,
                )
            self.voices.append(self.voice_markup(attributes, index))
            voice = len(self.voices) - 1
        self.flush_text()
        self.stack.append(_Open(name, written, index, style, substitute, voice))

    def voice_markup(self, attributes: dict[str, tuple[str, int]], index: int) -> VoiceMarkup:
        """The speaker and their line's attributes of a <VOICE>, each checked."""
        name = " ".join(attributes.get("NAME", ("", index))[0].split())
        if not name:
            raise self.error('<VOICE> needs the speaker\'s name: <VOICE NAME="Ayşe">', index)
        gender = None
        if "GENDER" in attributes:
            value, where = attributes["GENDER"]
            if value.strip().lower() not in GENDER_WORDS:
                raise self.error(f"GENDER={value!r} is not valid; expected female, male or neutral", where)
            gender = GENDER_WORDS[value.strip().lower()]
        variant = attributes["VARIANT"][0].strip().lower() or None if "VARIANT" in attributes else None
        addressee = None
        if "TO" in attributes:
            value, where = attributes["TO"]
            addressee = " ".join(value.split())
            if not addressee:
                raise self.error('TO="" names nobody; give a speaker\'s name or "camera"', where)
        overlaps, overlap = False, None
        if "OVERLAP" in attributes:
            value, where = attributes["OVERLAP"]
            text = value.strip().lower()
            if text in _OVERLAP_WORDS:
                overlaps = _OVERLAP_WORDS[text]
            else:
                overlap = _seconds(text)
                if overlap is None or overlap > 10:
                    raise self.error(
                        f"OVERLAP={value!r} is not valid; expected yes, no, or how much, e.g. 300ms", where
                    )
                overlaps = overlap > 0
        return VoiceMarkup(name, index, gender, variant, addressee, overlaps, overlap)

    def sayas_reading(self, attributes: dict[str, tuple[str, int]], index: int) -> str | None:
        """What a SAYAS says instead of its text: SUB="..." (any reading), or CLASS="literal" (letter by
        letter) and CLASS="digits" (digit by digit), filled in when the element closes; other classes
        (date, time, number, currency...) are read from the text as usual."""
        if "SUB" in attributes:
            value, where = attributes["SUB"]
            if not value.strip():
                raise self.error('SUB="" says nothing; give the words to say, e.g. SUB="on beş mart"', where)
            return value
        if "CLASS" in attributes and attributes["CLASS"][0].strip().lower() in _SPELLED_CLASSES:
            return ""  # spelled from the text at the closing tag
        return None

    def substitute_text(self, element: _Open) -> None:
        """Replace the text of a SAYAS with its reading; each of its characters points at the written
        text, spread over it evenly, so the reading stays where it was written."""
        written = "".join(self.text_parts)
        offsets = [offset for part in self.offset_parts for offset in part]
        reading = element.substitute or _spelled(written)
        if not offsets:
            offsets = [element.offset]
        self.text_parts[:] = [reading]
        self.offset_parts[:] = [
            tuple(offsets[index * len(offsets) // len(reading)] for index in range(len(reading)))
        ]

    def fraction(self, value: str, where: int, key: str, expected: str) -> float:
        text = value.strip()
        try:
            number = float(text[:-1]) / 100 if text.endswith("%") else float(text)
        except ValueError:
            number = float("nan")
        if not 0.0 <= number <= 1.0:
            raise self.error(f"{key}={value!r} is not valid; expected {expected}", where)
        return number

    def break_seconds(self, attributes: dict[str, tuple[str, int]]) -> float:
        sizes = pause_seconds()["break_size"]
        if "MSECS" in attributes:
            value, where = attributes["MSECS"]
            if not value.strip().isdigit() or int(value) > 600_000:
                raise self.error(
                    f"MSECS={value!r} is not valid; expected whole milliseconds, e.g. 300", where
                )
            return int(value) / 1000.0
        if "TIME" in attributes:
            value, where = attributes["TIME"]
            seconds = _seconds(value)
            if seconds is None or seconds > 600:
                raise self.error(f"TIME={value!r} is not valid; expected e.g. 300ms or 1.5s", where)
            return seconds
        if "SIZE" in attributes:
            value, where = attributes["SIZE"]
            key = value.strip().lower()
            if key not in sizes:
                raise self.error(f"SIZE={value!r} is not valid; expected none, small, medium or large", where)
            return sizes[key]
        return sizes["medium"]

    def prosody(self, style: Style, attributes: dict[str, tuple[str, int]]) -> Style:
        for attribute, (field, words, unit, lowest, expected) in _PROSODY.items():
            if attribute not in attributes:
                continue
            value, where = attributes[attribute]
            multiplier = _relative(value, getattr(style, field), words, unit)
            if multiplier is None or not lowest <= multiplier <= 10:
                raise self.error(f"{attribute}={value!r} is not valid; expected {expected}", where)
            style = replace(style, **{field: multiplier})
        return style


# PROS attribute -> (Style field, named values, one unit as a multiplier, lowest multiplier, expected).
_PROSODY = {
    "RATE": (
        "rate",
        _RATE_WORDS,
        DEFAULT_WORDS_PER_MINUTE,
        0.1,
        "words per minute (175), +20%, -10%, or xslow, slow, medium, fast, xfast, default",
    ),
    "PITCH": (
        "pitch",
        _PITCH_WORDS,
        DEFAULT_PITCH_HZ,
        0.1,
        "hertz (120), +20%, -10%, or xlow, low, medium, high, xhigh, default",
    ),
    "VOL": (
        "volume",
        _VOLUME_WORDS,
        1.0,
        0.0,
        "0.0 to 1.0, +20%, -10%, or silent, xsoft, soft, medium, loud, xloud, default",
    ),
}


def _relative(value: str, current: float, words: dict[str, float], unit: float) -> float | None:
    """A PROS value as a multiplier: a word, "+20%"/"-10%" of the current value, "+N" units, or absolute."""
    text = value.strip().lower()
    if text in words:
        return words[text]
    percent = text.endswith("%")
    number_text = text[:-1].strip() if percent else text
    if not _NUMBER.fullmatch(number_text):
        return None
    number = float(number_text)
    if percent:
        return current * (1.0 + number / 100.0) if number_text[0] in "+-" else current * number / 100.0
    if number_text[0] in "+-":
        return current + number / unit
    return number / unit


def _seconds(value: str) -> float | None:
    """A duration written as 300ms or 1.5s (None when it is not one)."""
    match = re.fullmatch(r"\s*([0-9]+(?:\.[0-9]+)?)\s*(ms|s)\s*", value.lower())
    if not match:
        return None
    return float(match.group(1)) * (1.0 if match.group(2) == "s" else 0.001)


def markup_error(source: str, index: int, message: str, length: int = 20) -> MarkupError:
    """A MarkupError pointing at a character of the source (line and column counted from 1)."""
    line = source.count("\n", 0, index) + 1
    column = index - (source.rfind("\n", 0, index) + 1) + 1
    snippet = source[index : index + length].split("\n")[0]
    return MarkupError(message, line, column, snippet)


_SPELLED_CLASSES = frozenset({"literal", "characters", "spell", "digits"})


def _spelled(text: str) -> str:
    """Letters and digits one by one, as a SAYAS of CLASS literal or digits says them (ABC -> a be ce)."""
    from .tables import fold_letter, text_tables

    tables = text_tables()
    names = []
    for char in text:
        if char.isdigit() and char.isascii():
            names.append(tables.digits[int(char)])
        else:
            names.extend(tables.letter_names.get(letter, letter) for letter in fold_letter(char))
    return " ".join(names) or text


def parse_jsml(source: str) -> tuple[TextRun | Pause, ...]:
    """Styled text runs and pauses, in source order; plain text without markup is one run."""
    return _Parser(source).parse()


def parse_jsml_voices(
    source: str,
) -> tuple[tuple[TextRun | Pause, ...], tuple[int | None, ...], tuple[VoiceMarkup, ...]]:
    """parse_jsml's items, the <VOICE> each item is in (an index into the voices, None outside any), and
    the <VOICE> elements in source order (a script's lines: text/script.py)."""
    parser = _Parser(source)
    items = parser.parse()
    return items, tuple(parser.item_voices), tuple(parser.voices)
