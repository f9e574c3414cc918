"""Turkish text as it is spoken: words of Turkish letters, each letter linked to its source index.

Numbers (numbers.py), written forms such as dates, times, money, fractions and addresses (written.py),
abbreviations, acronyms, units and symbols are expanded to words (tables in shapekeys/abbreviations.toml and
units.toml); a suffix after them is spoken on their reading (suffixes.py); casing follows Turkish rules
(I -> ı, İ -> i), foreign letters become what a Turkish speaker says, and punctuation becomes pauses (seconds
in shapekeys/pauses.toml).
"""

from __future__ import annotations

import bisect
import re
import unicodedata
from collections.abc import Iterable
from functools import cache, cached_property
from typing import NamedTuple

from ..base.errors import TextError
from ..base.model import Pause, SpokenWord, Style, TextRun
from .jsml import parse_jsml, pause_seconds
from .numbers import Words, number_words, ordinal_words
from .suffixes import Letters, proper_noun_suffix, spoken_suffix
from .tables import TURKISH_LETTERS, VOWELS, fold_letter, text_tables, turkish_lower, turkish_upper
from .written import Reading, WrittenForms

_APOSTROPHES = "'’ʼ`‘"
_HYPHENS = "-‐‑–"
_MINUS_SIGNS = "-−"
_ROMAN_LETTERS = frozenset("IVXLCDM")
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
__all__ = ["TURKISH_LETTERS", "normalize", "spoken_text", "spoken_words", "turkish_lower", "turkish_upper"]


def _is_upper_letter(char: str) -> bool:
    return char.isupper() or char == "İ"


# --------------------------------------------------------------------------- letters


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


_PLAIN_WORD = re.compile("[abcçdefgğhıijklmnoöprsştuüvyz]+")
_COMBINING = re.compile("[\u0300-\u036f\u1ab0-\u1aff\u1dc0-\u1dff\u20d0-\u20ff\ufe20-\ufe2f]")

# --------------------------------------------------------------------------- tokens

_ABBREVIATION_PATTERN: re.Pattern[str] | None = None


def _token_pattern() -> re.Pattern[str]:
    global _ABBREVIATION_PATTERN
    if _ABBREVIATION_PATTERN is None:
        keys = sorted(text_tables().abbreviations, key=len, reverse=True)
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
        self.tables = text_tables()
        self.forms = WrittenForms(self.text, self.offsets)
        self.token_starts: list[int] = []

    @cached_property
    def shouting(self) -> bool:
        """A run written all in capitals is shouting, not a row of acronyms."""
        letters = [char for char in self.text if char.isalpha()]
        capitals = sum(1 for char in letters if _is_upper_letter(char))
        return len(letters) >= 12 and capitals >= 0.8 * len(letters)

    # ------------------------------------------------------------ output

    def emit(self, letters: Letters) -> None:
        """Add a word from (letter, source index) pairs; letters already Turkish lowercase."""
        if letters:
            text, offsets = zip(*letters, strict=True)
            self.output.append(SpokenWord(text="".join(text), offsets=offsets, style=self.style))

    def emit_words(self, words: Words, suffix: Letters = (), *, harmonize: bool = False) -> None:
        """Emit expanded words (each word's letters at one source index, or one index per letter); a suffix
        joins the last word, re-harmonised to it when `harmonize` (a suffix written after digits or signs)."""
        for number, (word, offset) in enumerate(words):
            parts = word.split(" ")
            for part_number, part in enumerate(parts):
                offsets = offset if isinstance(offset, tuple) else (offset,) * len(part)
                letters = list(zip(part, offsets, strict=True))
                if suffix and number == len(words) - 1 and part_number == len(parts) - 1:
                    letters = spoken_suffix(letters, list(suffix)) if harmonize else letters + list(suffix)
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
        self.token_starts = [token.start for token in tokens]
        index = 0
        count = len(tokens)
        while index < count:
            token = tokens[index]
            kind = token.kind
            if kind == "space":
                if "\n" in token.text:  # a line break: no silence is asked for, but a place to pause
                    self.output.append(Pause(seconds=0.0, offset=self.offsets[token.start], kind="line"))
                index += 1
            elif kind == "word" and not self._may_be_written_form(token):
                self.word(token)
                index += 1
            else:
                index = self.token(tokens, index)

    def _may_be_written_form(self, token: _Token) -> bool:
        """A cheap test before the readers of Roman numerals and addresses are tried on a word."""
        first = token.text[0]
        return (
            self.text[token.end : token.end + 1] in (".", "@", ":", "_", "-", "+")
            or first in _ROMAN_LETTERS
            and set(token.text) <= _ROMAN_LETTERS
            or "\u00bc" <= first <= "\u00be"
            or "\u2150" <= first <= "\u215e"  # a vulgar fraction (½) is a word character to re
        )

    def token(self, tokens: list[_Token], index: int) -> int:
        token = tokens[index]
        kind = token.kind
        if kind == "word":
            reading = self.forms.after_letter(token.start)
            if reading is not None:
                return self.finish(reading)
            self.word(token)
        elif kind == "number":
            return self.number(tokens, index)
        elif kind == "abbreviation":
            suffix, end = self.suffix_after(tokens, index + 1)
            expansion = [(self.tables.abbreviations[token.text], self.offsets[token.start])]
            self.emit_words(expansion, suffix, harmonize=True)  # Prof.'a profesöre, spoken on its reading
            if suffix:
                return end
            if token.text.endswith(".") and self._sentence_ends_after(tokens, index, token.text):
                self.pause("sentence", token.end - 1)
        elif kind == "paragraph":
            self.pause("paragraph", token.start)
        elif kind == "other":
            return self.symbol(tokens, index)
        return index + 1

    def token_index_at(self, end: int) -> int:
        """The index of the first token that starts at or after a character index."""
        return bisect.bisect_left(self.token_starts, end)

    def finish(self, reading: Reading) -> int:
        """Emit a reading with the unit and the suffix written after it; the index of the next token."""
        words, end = list(reading.words), reading.end
        if reading.takes_unit:
            unit = _unit_pattern().match(self.text, end)
            if unit is not None:
                words, end = self.with_unit(words, unit), unit.end()
        suffix, end = self.suffix_at(end)
        self.emit_words(words, suffix, harmonize=True)
        return self.token_index_at(end)

    def with_unit(self, words: Words, unit: re.Match[str]) -> Words:
        """A number's words with its unit: 5 km beş kilometre, 120 km/sa saatte yüz yirmi kilometre."""
        tables = self.tables
        written, at = unit.group("unit"), self.offsets[unit.start("unit")]
        if written in tables.per_time_units:
            per_time = tables.per_time_units[written]
            slash = self.offsets[unit.start("unit") + written.index("/")]
            return [(per_time.before, slash), *words, (per_time.after, at)]
        if written in tables.currencies:
            return [*words, (tables.currencies[written].name, at)]
        return [*words, (tables.units_after_number[written], at)]

    def suffix_at(self, index: int) -> tuple[Letters, int]:
        """A suffix written after an apostrophe at a character index (09:00'da), and where it ends."""
        match = _SUFFIX.match(self.text, index)
        if match is None:
            return [], index
        return self.letters(match.group(1), match.start(1)), match.end()

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
        reading = self.forms.after_symbol(token.start)
        if reading is not None:
            return self.finish(reading)
        stands_alone = previous is None or previous.kind in ("space", "paragraph", "other")
        if following is not None and following.kind == "number":
            if char in _MINUS_SIGNS and stands_alone:
                self.emit_words([(tables.words["minus"], self.offsets[token.start])])
                return self.number(tokens, index + 1)
        if char in _MINUS_SIGNS and stands_alone and following is not None and following.text == "%":
            after = tokens[index + 2] if index + 2 < len(tokens) else None
            if after is not None and after.kind == "number":  # -%3: eksi yüzde üç
                self.emit_words([(tables.words["minus"], self.offsets[token.start])])
                return index + 1
        if char in _PUNCTUATION_PAUSES:
            if char == "." and index + 2 < len(tokens) and tokens[index + 1].text == ".":
                return index + 1  # "..." pauses once, at its last dot
            self.pause(_PUNCTUATION_PAUSES[char], token.start)
        elif char in _HYPHENS and previous is not None and following is not None:
            if previous.kind == "space" and following.kind == "space":
                self.pause("clause", token.start)  # a dash between words; inside a word it only splits
        elif char in tables.symbols:
            self.emit_words([(tables.symbols[char], self.offsets[token.start])])
        elif char in tables.currencies:
            self.emit_words([(tables.currencies[char].name, self.offsets[token.start])])
        # Anything else (emoji, brackets, quotes, other symbols) is not spoken.
        return index + 1

    def number(self, tokens: list[_Token], index: int) -> int:
        token = tokens[index]
        reading = self.forms.after_digit(token.start)
        if reading is not None:
            return self.finish(reading)
        words = number_words(token.text, list(self.offsets[token.start : token.end]))
        end = token.end
        following = tokens[index + 1] if index + 1 < len(tokens) else None
        if following is not None and following.text == "." and re.fullmatch(r"[0-9]+", token.text):
            if self._is_ordinal_dot(tokens, index, index + 1):
                self.emit_words(ordinal_words(words))
                return index + 2  # the dot marks the ordinal; it is no sentence end
        elif following is not None and following.text == "%":
            words.insert(0, (self.tables.words["percent"], self.offsets[following.start]))
            end = following.end
        return self.finish(Reading(words, end, takes_unit=True))

    def suffix_after(self, tokens: list[_Token], index: int) -> tuple[Letters, int]:
        """A case suffix after an apostrophe (Dr.'a), and the index of the token after it."""
        if (
            index + 1 < len(tokens)
            and tokens[index].text in _APOSTROPHES
            and tokens[index + 1].kind == "word"
        ):
            after = tokens[index + 1]
            return self.letters(after.text, after.start), index + 2
        return [], index

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

    def letters(self, text: str, start: int) -> Letters:
        """Letters of a written word as Turkish lowercase letters with source indices; apostrophes vanish."""
        letters: Letters = []
        for position, char in enumerate(text, start):
            for letter in fold_letter(char):
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
        suffix = self.letters(text[len(base) :], token.start + len(base))
        tables = self.tables
        if base in tables.currencies and self._after_a_number():  # 1,5 milyon TL
            self.emit_words(
                [(tables.currencies[base].name, self.offsets[token.start])], suffix, harmonize=True
            )
            return
        if base in tables.spoken_in_full:  # KDV katma değer vergisi, each word at its letter
            said = tables.spoken_in_full[base].split(" ")
            starts = [self.offsets[token.start + min(index, len(base) - 1)] for index in range(len(said))]
            self.emit_words(list(zip(said, starts, strict=True)), suffix, harmonize=True)
            return
        if self._is_acronym(base, token.start):
            self.emit_words(self.letter_names(base, token.start), suffix)
            return
        letters = self.letters(base, token.start)
        if len(base) == 1 and len(letters) == 1 and letters[0][0] not in VOWELS and not suffix:
            self.emit_words(self.letter_names(base, token.start))  # a lone letter: "B planı", "3D"
            return
        if suffix and _is_upper_letter(text[0]):
            self.emit(proper_noun_suffix(letters, suffix, written=turkish_lower(base)))  # Zeynep'e zeynebe
            return
        self.emit(letters + suffix)

    def _after_a_number(self) -> bool:
        """Whether the last spoken word reads a number (a scale word such as milyon ends one)."""
        last = self.output[-1] if self.output else None
        return isinstance(last, SpokenWord) and last.text in self.tables.scales[1:]

    def letter_names(self, text: str, start: int) -> Words:
        """Each letter by its name (TBMM -> te be me me), at its source index."""
        names = self.tables.letter_names
        spelled: Words = []
        for position, char in enumerate(text, start):
            lower = turkish_lower(char)
            letters = [lower] if lower in names else list(fold_letter(char))
            spelled.extend((names.get(letter, letter), self.offsets[position]) for letter in letters)
        return spelled

    def _is_acronym(self, base: str, start: int) -> bool:
        """TBMM, ABD, THY: two or more capitals, spelled unless they read like a word (NATO, TÜBİTAK), or
        are a particle beside a word in capitals (GELDİ MI)."""
        if len(base) < 2 or not all(_is_upper_letter(char) for char in base):
            return False
        if base in self.tables.read_as_words:
            return False
        if base in self.tables.particles and self._capital_word_before(start):
            return False
        folded = "".join(fold_letter(char) for char in base)
        if not any(letter in VOWELS for letter in folded):
            return True
        if self.shouting:
            return False
        return not _reads_as_word(folded)

    def _capital_word_before(self, start: int) -> bool:
        before = self.forms.word_before(start)
        return before is not None and len(before) > 1 and all(_is_upper_letter(char) for char in before)


_SUFFIX = re.compile(rf"[{_APOSTROPHES}]([^\W\d_]+)")


@cache
def _unit_pattern() -> re.Pattern[str]:
    """A unit or currency right after a number (5 km, 5km, 120 km/sa, 100 TL, 10€)."""
    tables = text_tables()
    units = [*tables.units_after_number, *tables.per_time_units, *tables.currencies]
    alternatives = "|".join(re.escape(unit) for unit in sorted(units, key=len, reverse=True))
    return re.compile(rf"[^\S\n]?(?P<unit>{alternatives})(?![^\W\d_])")


def _reads_as_word(word: str) -> bool:
    """Whether a capitalised letter string reads as one word: 3 letters shaped CVC or VCV (MEB, YÖK, İYİ),
    or 4+ letters in Turkish syllable shapes (NATO, TÜBİTAK); ABD, AKP, DNA are spelled."""
    if len(word) < 3 or word[0] == "ğ":  # no Turkish word starts with ğ (ĞÜŞ is spelled)
        return False
    shape = "".join("V" if letter in VOWELS else "C" for letter in word)
    if len(word) == 3:
        return shape in ("CVC", "VCV")
    if word[0] not in VOWELS and word[1] not in VOWELS:
        return False  # no Turkish word starts with two consonants
    if word[-1] not in VOWELS and word[-2] not in VOWELS and word[-3] not in VOWELS:
        return False
    # Three consonants together join the parts of a long name (TÜRKSAT, KENTGIS); four never.
    longest = 3 if len(word) >= 6 and sum(letter in VOWELS for letter in word) >= 2 else 2
    run = 0
    for letter in word:
        run = 0 if letter in VOWELS else run + 1
        if run > longest:
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


_PAUSE_MARKS = {
    "comma": ",",
    "clause": ",",
    "break": ",",
    "sentence": ".",
    "question": "?",
    "exclamation": "!",
}


def spoken_words(source: str) -> list[str]:
    """The words a JSML or plain text is spoken as, in order (what the timeline's words hold)."""
    return [item.text for item in normalize(parse_jsml(source)) if isinstance(item, SpokenWord)]


def spoken_text(source: str) -> str:
    """The text as it is spoken, pauses shown as punctuation and paragraphs as blank lines: a script can
    be checked before it is animated."""
    parts: list[str] = []
    for item in normalize(parse_jsml(source)):
        if isinstance(item, SpokenWord):
            parts.append((" " if parts and not parts[-1].endswith("\n") else "") + item.text)
        elif parts and item.kind == "paragraph":
            parts.append(".\n\n")
        elif parts and item.kind in _PAUSE_MARKS:
            parts.append(_PAUSE_MARKS[item.kind])
    return "".join(parts).strip()
