"""Turkish text as it is spoken: words of Turkish letters, each letter linked to its source index.

Numbers, abbreviations, acronyms and symbols are expanded to words (tables in shapekeys/abbreviations.toml),
casing follows Turkish rules (I -> ı, İ -> i), foreign letters become what a Turkish speaker says, and
punctuation becomes pauses (seconds in shapekeys/pauses.toml).
"""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Iterable
from dataclasses import dataclass
from functools import cache, cached_property, lru_cache
from typing import NamedTuple

from ..data import DATA_DIR, load_table
from ..errors import DataError, TextError
from ..model import Pause, SpokenWord, Style, TextRun
from .jsml import pause_seconds

TURKISH_LETTERS: frozenset[str] = frozenset("abcçdefgğhıijklmnoöprsştuüvyz")
_VOWELS = frozenset("aeıioöuü")
_APOSTROPHES = "'’ʼ`‘"
_HYPHENS = "-‐‑–"
_MINUS_SIGNS = "-−"
_PUNCTUATION_PAUSES = {
    ",": "comma",
    "،": "comma",
    ";": "clause",
    ":": "clause",
    "—": "clause",
    ".": "sentence",
    "?": "question",
    "!": "exclamation",
    "…": "sentence",
}

# --------------------------------------------------------------------------- casing


def turkish_lower(text: str) -> str:
    """Lowercase by Turkish rules: I -> ı and İ -> i (Python's str.lower gives i and i + U+0307)."""
    return text.replace("I", "ı").replace("İ", "i").lower()


def turkish_upper(text: str) -> str:
    """Uppercase by Turkish rules: i -> İ and ı -> I."""
    return text.replace("i", "İ").replace("ı", "I").upper()


def _is_upper_letter(char: str) -> bool:
    return char.isupper() or char == "İ"


# --------------------------------------------------------------------------- tables


@dataclass(frozen=True)
class _Tables:
    abbreviations: dict[str, str]
    units_after_number: dict[str, str]
    read_as_words: frozenset[str]
    letter_names: dict[str, str]
    foreign_letters: dict[str, str]
    symbols: dict[str, str]
    currency: dict[str, str]
    digits: tuple[str, ...]
    tens: tuple[str, ...]
    hundred: str
    scales: tuple[str, ...]
    words: dict[str, str]  # decimal_comma, decimal_point, fraction, percent, minus, plus
    months: frozenset[str]


@cache
def _tables() -> _Tables:
    """shapekeys/abbreviations.toml, validated once: every expansion is Turkish letters and spaces."""
    table = load_table("abbreviations")
    path = DATA_DIR / "abbreviations.toml"

    def section(name: str) -> dict:
        value = table.get(name)
        if not isinstance(value, dict):
            raise DataError(f"data file {path}: section [{name}] is missing")
        return value

    def spoken(where: str, value: object) -> str:
        if not isinstance(value, str) or not value or not set(value) <= TURKISH_LETTERS | {" "}:
            raise DataError(f"data file {path}: {where} must be lowercase Turkish words, got {value!r}")
        return value

    def mapping(name: str) -> dict[str, str]:
        return {key: spoken(f"[{name}] {key!r}", value) for key, value in section(name).items()}

    numbers = section("numbers")

    def word_list(key: str, length: int) -> tuple[str, ...]:
        values = numbers.get(key)
        if not isinstance(values, list) or len(values) != length:
            raise DataError(f"data file {path}: [numbers] {key} must be a list of {length} words")
        return tuple(value and spoken(f"[numbers] {key}", value) for value in values)

    scales = numbers.get("scales")
    if not isinstance(scales, list) or len(scales) < 2:
        raise DataError(f"data file {path}: [numbers] scales must list at least '' and 'bin'")
    acronyms = section("acronyms").get("read_as_words", [])
    months = section("dates").get("months", [])
    if not isinstance(acronyms, list) or not isinstance(months, list):
        raise DataError(f"data file {path}: [acronyms] read_as_words and [dates] months must be lists")
    letter_names = mapping("letter_names")
    missing = sorted(TURKISH_LETTERS - set(letter_names))
    if missing:
        raise DataError(f"data file {path}: [letter_names] lacks {', '.join(missing)}")
    return _Tables(
        abbreviations=mapping("abbreviations"),
        units_after_number=mapping("units_after_number"),
        read_as_words=frozenset(acronyms),
        letter_names=letter_names,
        foreign_letters=mapping("foreign_letters"),
        symbols=mapping("symbols"),
        currency=mapping("currency"),
        digits=word_list("digits", 10),
        tens=word_list("tens", 10),
        hundred=spoken("[numbers] hundred", numbers.get("hundred")),
        scales=tuple(value and spoken("[numbers] scales", value) for value in scales),
        words={
            key: spoken(f"[numbers] {key}", numbers.get(key))
            for key in ("decimal_comma", "decimal_point", "fraction", "percent", "minus", "plus")
        },
        months=frozenset(months),
    )


# --------------------------------------------------------------------------- letters


@lru_cache(maxsize=4096)
def _fold_letter(char: str) -> str:
    """A source letter as Turkish letters: "" for letters Turkish cannot say (other scripts)."""
    lower = turkish_lower(char)
    if lower in TURKISH_LETTERS:
        return lower
    foreign = _tables().foreign_letters
    if lower in foreign:
        return foreign[lower]
    folded = []
    for base in unicodedata.normalize("NFKD", lower):
        if base in TURKISH_LETTERS:
            folded.append(base)
        elif base in foreign:
            folded.append(foreign[base])
    return "".join(folded)


def _compose(text: str, offsets: tuple[int, ...]) -> tuple[str, tuple[int, ...] | list[int]]:
    """Merge combining marks into their letter (I + U+0307 -> İ, s + U+0327 -> ş) at the letter's index."""
    if not _COMBINING.search(text):
        return text, offsets
    chars: list[str] = []
    kept: list[int] = []
    for char, offset in zip(text, offsets, strict=True):
        if chars and unicodedata.combining(char):
            combined = unicodedata.normalize("NFC", chars[-1] + char)
            if len(combined) == 1:
                chars[-1] = combined
            continue  # a mark with no precomposed letter (i + U+0307) is dropped
        chars.append(char)
        kept.append(offset)
    return "".join(chars), kept


# --------------------------------------------------------------------------- numbers


def _group_words(tables: _Tables, digits: str, positions: list[int]) -> list[tuple[str, int]]:
    """Words of a number below 1000 (given as up to three digits), each with its digit's position."""
    words: list[tuple[str, int]] = []
    padded = digits.rjust(3, "0")
    places = [None] * (3 - len(digits)) + list(positions)
    hundreds, tens, ones = (int(d) for d in padded)
    if hundreds:
        if hundreds > 1:
            words.append((tables.digits[hundreds], places[0]))
        words.append((tables.hundred, places[0]))
    if tens:
        words.append((tables.tens[tens], places[1]))
    if ones:
        words.append((tables.digits[ones], places[2]))
    return words


def _integer_words(digits: str, positions: list[int]) -> list[tuple[str, int]]:
    """Turkish words of a whole number written as digits; each word carries the source index of its digit."""
    tables = _tables()
    if len(digits) > 1 and digits[0] == "0" or len(digits) > 3 * len(tables.scales):
        # Leading zeros (007) and numbers beyond the largest scale are read digit by digit.
        return [(tables.digits[int(d)], p) for d, p in zip(digits, positions, strict=True)]
    if int(digits) == 0:
        return [(tables.digits[0], positions[0])]
    words: list[tuple[str, int]] = []
    group_count = (len(digits) + 2) // 3
    first = len(digits) - 3 * (group_count - 1)
    starts = [0] + [first + 3 * n for n in range(group_count - 1)]
    for number, (begin, end) in enumerate(zip(starts, starts[1:] + [len(digits)], strict=True)):
        group, places = digits[begin:end], positions[begin:end]
        scale = tables.scales[group_count - 1 - number]
        value = int(group)
        if not value:
            continue
        if scale == tables.scales[1] and value == 1:
            words.append((scale, places[-1]))  # 1000 is "bin", not "bir bin"
            continue
        words.extend(
            _group_words(tables, group.lstrip("0") or "0", places[len(group) - len(group.lstrip("0")) :])
        )
        if scale:
            words.append((scale, places[-1]))
    return words


def _fraction_words(digits: str, positions: list[int]) -> list[tuple[str, int]]:
    """The digits after a decimal separator: leading zeros one by one, then the rest as a number."""
    tables = _tables()
    stripped = digits.lstrip("0")
    zeros = len(digits) - len(stripped)
    words = [(tables.digits[0], p) for p in positions[:zeros]]
    if stripped:
        words.extend(_integer_words(stripped, positions[zeros:]))
    return words


_ORDINAL_EXCEPTIONS = {"dört": "dördüncü"}


def _ordinal(word: str) -> str:
    """The ordinal of a number word: bir -> birinci, üç -> üçüncü, altı -> altıncı (vowel harmony)."""
    if word in _ORDINAL_EXCEPTIONS:
        return _ORDINAL_EXCEPTIONS[word]
    last_vowel = next(letter for letter in reversed(word) if letter in _VOWELS)
    vowel = {"a": "ı", "ı": "ı", "e": "i", "i": "i", "o": "u", "u": "u", "ö": "ü", "ü": "ü"}[last_vowel]
    return word + ("nc" if word[-1] in _VOWELS else vowel + "nc") + vowel


_SEPARATOR_WORDS = {".": "decimal_point", ",": "decimal_comma", "/": "fraction"}
_PLAIN_WORD = re.compile("[abcçdefgğhıijklmnoöprsştuüvyz]+")
_COMBINING = re.compile("[\u0300-\u036f\u1ab0-\u1aff\u1dc0-\u1dff\u20d0-\u20ff\ufe20-\ufe2f]")
# An integer (with "." between thousands, Turkish style) and an optional decimal part after ","; or a
# decimal with one "." that is no thousands separator (3.5, but 1.000 is a thousand).
_DECIMAL_COMMA = re.compile(
    r"(?P<integer>[0-9]{1,3}(?:\.[0-9]{3})+|[0-9]+)(?:(?P<separator>,)(?P<fraction>[0-9]+))?"
)
_DECIMAL_POINT = re.compile(r"(?P<integer>[0-9]+)(?P<separator>\.)(?P<fraction>[0-9]+)")

_DATE = re.compile(r"([0-9]{1,2})[./]([0-9]{1,2})[./]([0-9]{4})")
_TIME = re.compile(r"([0-9]{1,2}):([0-9]{2})")


def _number_words(number: str, positions: list[int]) -> list[tuple[str, int]]:
    """Words for a number token: integers, "1.000.000", decimals "3,5" / "3.5", dates, times, versions."""
    tables = _tables()
    date = _DATE.fullmatch(number) or _TIME.fullmatch(number)
    if date:
        words: list[tuple[str, int]] = []
        for index in range(1, date.lastindex + 1):
            words.extend(_integer_words(date.group(index), positions[date.start(index) : date.end(index)]))
        return words
    decimal = _DECIMAL_COMMA.fullmatch(number) or _DECIMAL_POINT.fullmatch(number)
    if not decimal:
        return _grouped_number_words(number, positions)
    integer, separator, fraction = (
        decimal.group("integer"),
        decimal.group("separator"),
        decimal.group("fraction"),
    )
    if "." in integer:  # thousands separators: 1.000.000
        kept = [index for index, char in enumerate(integer) if char != "."]
        words = _integer_words(integer.replace(".", ""), [positions[index] for index in kept])
    else:
        words = _integer_words(integer, positions[: len(integer)])
    if separator:
        separator_index = len(integer)
        words.append((tables.words[_SEPARATOR_WORDS[separator]], positions[separator_index]))
        words.extend(_fraction_words(fraction, positions[separator_index + 1 :]))
    return words


def _grouped_number_words(number: str, positions: list[int]) -> list[tuple[str, int]]:
    """Separators in no known format (192.168.1.1, 1/2, 3:2): the digit groups one by one."""
    words: list[tuple[str, int]] = []
    start = 0
    for part in re.split(r"([.,:/])", number):
        if part in _SEPARATOR_WORDS:
            words.append((_tables().words[_SEPARATOR_WORDS[part]], positions[start]))
        elif part and part != ":":
            words.extend(_integer_words(part, positions[start : start + len(part)]))
        start += len(part)
    return words


# --------------------------------------------------------------------------- tokens

_ABBREVIATION_PATTERN: re.Pattern[str] | None = None


def _token_pattern() -> re.Pattern[str]:
    global _ABBREVIATION_PATTERN
    if _ABBREVIATION_PATTERN is None:
        keys = sorted(_tables().abbreviations, key=len, reverse=True)
        alternatives = "|".join(re.escape(key) for key in keys)
        _ABBREVIATION_PATTERN = re.compile(
            rf"(?P<abbreviation>(?<![^\W\d_])(?:{alternatives})(?![^\W\d_]))"
            r"|(?P<number>[0-9]+(?:[.,:/][0-9]+)*)"
            rf"|(?P<word>[^\W\d_]+(?:[{_APOSTROPHES}][^\W\d_]+)*)"
            r"|(?P<paragraph>\n[^\S\n]*\n\s*)"
            r"|(?P<space>\s+)"
            r"|(?P<other>.)",
            re.DOTALL,
        )
    return _ABBREVIATION_PATTERN


# Punctuation after which a new sentence starts.
_SENTENCE_ENDS = frozenset(".!?…")


class _Token(NamedTuple):
    kind: str
    text: str
    start: int  # index into the composed run text
    end: int


class _RunNormalizer:
    """Turns one text run into spoken words and pauses."""

    def __init__(self, run: TextRun, output: list[SpokenWord | Pause]) -> None:
        self.text, self.offsets = _compose(run.text, run.offsets)
        self.style: Style = run.style
        self.output = output
        self.tables = _tables()

    @cached_property
    def shouting(self) -> bool:
        """A run written all in capitals is shouting, not a row of acronyms."""
        letters = [char for char in self.text if char.isalpha()]
        capitals = sum(1 for char in letters if _is_upper_letter(char))
        return len(letters) >= 12 and capitals >= 0.8 * len(letters)

    # ------------------------------------------------------------ output

    def emit(self, letters: list[tuple[str, int]]) -> None:
        """Add a word from (letter, source index) pairs; letters already Turkish lowercase."""
        if letters:
            text, offsets = zip(*letters, strict=True)
            self.output.append(SpokenWord(text="".join(text), offsets=offsets, style=self.style))

    def emit_words(self, words: list[tuple[str, int]], suffix: list[tuple[str, int]] = ()) -> None:
        """Emit expanded words (each word's letters at one source index); a suffix joins the last word."""
        for number, (word, offset) in enumerate(words):
            for part_number, part in enumerate(word.split(" ")):
                letters = [(letter, offset) for letter in part]
                if number == len(words) - 1 and part_number == len(word.split(" ")) - 1:
                    letters.extend(suffix)
                self.emit(letters)

    def pause(self, kind: str, index: int) -> None:
        seconds = pause_seconds()["punctuation"][kind]
        self.output.append(Pause(seconds=seconds, offset=self.offsets[index], kind=kind))

    # ------------------------------------------------------------ scanning

    def run(self) -> None:
        make = _Token._make
        tokens = [
            make((match.lastgroup, match.group(), match.start(), match.end()))
            for match in _token_pattern().finditer(self.text)
        ]
        index = 0
        count = len(tokens)
        while index < count:
            kind = tokens[index].kind
            if kind == "space":
                index += 1
            elif kind == "word":
                self.word(tokens[index])
                index += 1
            else:
                index = self.token(tokens, index)

    def token(self, tokens: list[_Token], index: int) -> int:
        token = tokens[index]
        kind = token.kind
        if kind == "word":
            self.word(token)
        elif kind == "number":
            return self.number(tokens, index)
        elif kind == "abbreviation":
            suffix, end = self.suffix_after(tokens, index + 1)
            self.emit_words([(self.tables.abbreviations[token.text], self.offsets[token.start])], suffix)
            if suffix:
                return end
            if token.text.endswith(".") and self._sentence_ends_after(tokens, index, token.text):
                self.pause("sentence", token.end - 1)
        elif kind == "paragraph":
            self.pause("paragraph", token.start)
        elif kind == "other":
            return self.symbol(tokens, index)
        return index + 1

    @staticmethod
    def _sentence_ends_after(tokens: list[_Token], index: int, abbreviation: str) -> bool:
        """Whether an abbreviation's dot also ends the sentence: the run ends, or a lowercase one (vb., vs.)
        is followed by a capital. Capitalised ones (Dr., Prof., T.C.) stand before names."""
        rest = [token for token in tokens[index + 1 : index + 3] if token.kind != "space"]
        if not rest:
            return True
        return abbreviation[0].islower() and rest[0].kind == "word" and _is_upper_letter(rest[0].text[0])

    def symbol(self, tokens: list[_Token], index: int) -> int:
        token = tokens[index]
        char = token.text
        following = tokens[index + 1] if index + 1 < len(tokens) else None
        previous = tokens[index - 1] if index else None
        tables = self.tables
        if following is not None and following.kind == "number":
            if char == "%":
                self.emit_words([(tables.words["percent"], self.offsets[token.start])])
                return self.number(tokens, index + 1)
            if char in _MINUS_SIGNS and (
                previous is None or previous.kind in ("space", "paragraph", "other")
            ):
                self.emit_words([(tables.words["minus"], self.offsets[token.start])])
                return self.number(tokens, index + 1)
            if char in tables.currency:
                end = self.number(tokens, index + 1)
                self.emit_words([(tables.currency[char], self.offsets[token.start])])
                return end
        if char in _PUNCTUATION_PAUSES:
            if char == "." and index + 2 < len(tokens) and tokens[index + 1].text == ".":
                return index + 1  # "..." pauses once, at its last dot
            self.pause(_PUNCTUATION_PAUSES[char], token.start)
        elif char in _HYPHENS and previous is not None and following is not None:
            if previous.kind == "space" and following.kind == "space":
                self.pause("clause", token.start)  # a dash between words; inside a word it only splits
        elif char in tables.symbols:
            self.emit_words([(tables.symbols[char], self.offsets[token.start])])
        elif char in tables.currency:
            self.emit_words([(tables.currency[char], self.offsets[token.start])])
        # Anything else (emoji, brackets, quotes, other symbols) is not spoken.
        return index + 1

    def number(self, tokens: list[_Token], index: int) -> int:
        token = tokens[index]
        positions = list(self.offsets[token.start : token.end])
        words = _number_words(token.text, positions)
        end = index + 1
        following = tokens[end] if end < len(tokens) else None
        suffix: list[tuple[str, int]] = []
        if following is not None and following.kind == "other" and following.text in _APOSTROPHES:
            suffix, end = self.suffix_after(tokens, end)
        elif following is not None and following.text == "." and re.fullmatch(r"[0-9]+", token.text):
            if self._is_ordinal_dot(tokens, index, end):
                last_word, last_offset = words[-1]
                words[-1] = (_ordinal(last_word), last_offset)
                end += 1  # the dot marks the ordinal; it is no sentence end
        elif following is not None and following.text == "%":
            words.insert(0, (self.tables.words["percent"], self.offsets[following.start]))
            end += 1
        else:
            unit = self._unit_after(tokens, end)
            if unit is not None:
                self.emit_words(words)
                unit_token = tokens[unit]
                self.emit_words(
                    [(self.tables.units_after_number[unit_token.text], self.offsets[unit_token.start])]
                )
                return unit + 1
        self.emit_words(words, suffix)
        return end

    def suffix_after(self, tokens: list[_Token], index: int) -> tuple[list[tuple[str, int]], int]:
        """A case suffix after an apostrophe (2024'te, km'den), and the index after it."""
        if (
            index + 1 < len(tokens)
            and tokens[index].text in _APOSTROPHES
            and tokens[index + 1].kind == "word"
        ):
            after = tokens[index + 1]
            return self.letters(after.text, after.start), index + 2
        return [], index

    def _unit_after(self, tokens: list[_Token], index: int) -> int | None:
        position = index + 1 if index < len(tokens) and tokens[index].kind == "space" else index
        if position < len(tokens) and tokens[position].kind == "word":
            text = tokens[position].text
            if text in self.tables.units_after_number:
                return position
        return None

    def _is_ordinal_dot(self, tokens: list[_Token], number: int, dot: int) -> bool:
        """A dot after a number is ordinal before a lowercase word or a month ("3. sınıf", "19. yüzyıl"),
        and before any word when the number opens a sentence ("1. Dünya Savaşı başladı", "2. Madde")."""
        rest = [token for token in tokens[dot + 1 : dot + 3] if token.kind != "space"]
        if not rest or rest[0].kind not in ("word", "abbreviation"):
            return False
        if tokens[dot + 1].kind != "space":
            return False
        first = rest[0].text
        if first[0].islower() or turkish_lower(first) in self.tables.months:
            return True
        before = next((token for token in reversed(tokens[:number]) if token.kind != "space"), None)
        return before is None or before.kind == "paragraph" or before.text in _SENTENCE_ENDS

    # ------------------------------------------------------------ words

    def letters(self, text: str, start: int) -> list[tuple[str, int]]:
        """Letters of a written word as Turkish lowercase letters with source indices; apostrophes vanish."""
        letters: list[tuple[str, int]] = []
        for position, char in enumerate(text, start):
            for letter in _fold_letter(char):
                letters.append((letter, self.offsets[position]))
        return letters

    def word(self, token: _Token) -> None:
        text = token.text
        # The common case: Turkish letters, not all capitals (so no acronym), one letter per letter.
        if len(text) > 1 and not _is_upper_letter(text[-1]):
            lowered = text if text.islower() else turkish_lower(text)
            if len(lowered) == len(text) and _PLAIN_WORD.fullmatch(lowered):
                self.output.append(
                    SpokenWord(lowered, tuple(self.offsets[token.start : token.end]), self.style)
                )
                return
        base = text
        for apostrophe in _APOSTROPHES:
            base = base.split(apostrophe)[0]
        if self._is_acronym(base):
            self.emit_words(
                self.letter_names(base, token.start), self.letters(text[len(base) :], token.start + len(base))
            )
            return
        letters = self.letters(text, token.start)
        if len(base) == 1 and len(letters) == 1 and letters[0][0] not in _VOWELS:
            self.emit_words(self.letter_names(base, token.start))  # a lone letter: "B planı", "3D"
            return
        self.emit(letters)

    def letter_names(self, text: str, start: int) -> list[tuple[str, int]]:
        """Each letter by its name (TBMM -> te be me me), at its source index."""
        names = self.tables.letter_names
        spelled: list[tuple[str, int]] = []
        for position, char in enumerate(text, start):
            lower = turkish_lower(char)
            letters = [lower] if lower in names else list(_fold_letter(char))
            spelled.extend((names.get(letter, letter), self.offsets[position]) for letter in letters)
        return spelled

    def _is_acronym(self, base: str) -> bool:
        """TBMM, ABD, THY: two or more capitals, spelled unless they read like a word (NATO, TÜBİTAK)."""
        if len(base) < 2 or not all(_is_upper_letter(char) for char in base):
            return False
        if base in self.tables.read_as_words:
            return False
        folded = "".join(_fold_letter(char) for char in base)
        if not any(letter in _VOWELS for letter in folded):
            return True
        if self.shouting:
            return False
        return not _reads_as_word(folded)


def _reads_as_word(word: str) -> bool:
    """Whether a capitalised letter string reads as one word: 3 letters shaped CVC or VCV (MEB, YÖK, İYİ),
    or 4+ letters in Turkish syllable shapes (NATO, TÜBİTAK); ABD, AKP, DNA are spelled."""
    if len(word) < 3:
        return False
    shape = "".join("V" if letter in _VOWELS else "C" for letter in word)
    if len(word) == 3:
        return shape in ("CVC", "VCV")
    if word[0] not in _VOWELS and word[1] not in _VOWELS:
        return False  # no Turkish word starts with two consonants
    if word[-1] not in _VOWELS and word[-2] not in _VOWELS and word[-3] not in _VOWELS:
        return False
    run = 0
    for letter in word:
        run = 0 if letter in _VOWELS else run + 1
        if run > 2:
            return False
    return True


# --------------------------------------------------------------------------- entry point


def normalize(items: Iterable[TextRun | Pause]) -> tuple[SpokenWord | Pause, ...]:
    """Spoken words and pauses in order; neighbouring pauses merge into the longest one."""
    output: list[SpokenWord | Pause] = []
    for item in items:
        if isinstance(item, Pause):
            output.append(item)
        else:
            _RunNormalizer(item, output).run()
    merged: list[SpokenWord | Pause] = []
    for item in output:
        if isinstance(item, Pause) and merged and isinstance(merged[-1], Pause):
            if item.seconds > merged[-1].seconds:
                merged[-1] = item
            continue
        merged.append(item)
    if not any(isinstance(item, SpokenWord) for item in merged):
        raise TextError(
            "nothing to speak: the text has no Turkish words, numbers or letters after normalisation; "
            "write some Turkish text"
        )
    return tuple(merged)
