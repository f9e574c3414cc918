"""The tables that say how written Turkish is spoken, read once from shapekeys/ and validated.

abbreviations.toml holds words, letters, numbers and abbreviations; units.toml units and currencies.
Every spoken form must be lowercase Turkish words, so a typo in a table fails at load with its file and key.
"""

from __future__ import annotations

import unicodedata
from dataclasses import dataclass, fields
from functools import cache, lru_cache

from ..base.data import DATA_DIR, load_table
from ..base.errors import DataError

TURKISH_LETTERS: frozenset[str] = frozenset("abcçdefgğhıijklmnoöprsştuüvyz")
VOWELS: frozenset[str] = frozenset("aeıioöuü")


def turkish_lower(text: str) -> str:
    """Lowercase by Turkish rules: I -> ı and İ -> i (Python's str.lower gives i and i + U+0307)."""
    return text.replace("I", "ı").replace("İ", "i").lower()


def turkish_upper(text: str) -> str:
    """Uppercase by Turkish rules: i -> İ and ı -> I."""
    return text.replace("i", "İ").replace("ı", "I").upper()


@dataclass(frozen=True)
class Currency:
    name: str  # lira
    subunit: str  # kuruş


@dataclass(frozen=True)
class PerTimeUnit:
    """A rate such as km/sa, spoken with the time first: "saatte yüz kilometre"."""

    before: str
    after: str


@dataclass(frozen=True)
class Tables:
    abbreviations: dict[str, str]
    units_after_number: dict[str, str]
    per_time_units: dict[str, PerTimeUnit]
    currencies: dict[str, Currency]  # signs and codes: ₺, TL, $, USD
    read_as_words: frozenset[str]
    spoken_in_full: dict[str, str]  # acronyms said as their words: KDV
    particles: frozenset[str]  # MI, DE: words, not acronyms, beside words in capitals
    letter_names: dict[str, str]
    foreign_letters: dict[str, str]
    symbols: dict[str, str]
    address_words: dict[str, str]  # separators inside e-mail and web addresses
    top_level_domains: frozenset[str]  # com, tr: a lowercase word with dots ending so is a web address
    directions: dict[str, str]  # K, G, D, B after degrees
    fixed_expressions: dict[str, str]  # 7/24
    digits: tuple[str, ...]
    tens: tuple[str, ...]
    hundred: str
    scales: tuple[str, ...]
    words: dict[str, str]  # decimal_comma, decimal_point, fraction, percent, minus, plus, ...
    months: tuple[str, ...]  # ocak .. aralık, in order
    regnal_titles: frozenset[str]
    stems_before_suffix: dict[str, str]  # yarım -> yarı (yarısı)
    soften_always: frozenset[str]  # one-syllable words that soften anyway: dört -> dördü
    soften_never: frozenset[str]  # words of several syllables that keep their consonant: saat -> saate


_NUMBER_WORDS = (
    "decimal_comma",
    "decimal_point",
    "fraction",
    "percent",
    "minus",
    "plus",
    "half",
    "quarter",
    "and_a_half",
    "whole",
    "range",
    "degree",
    "minute",
    "second",
    "latitude",
    "longitude",
    "times",
)


class _TableFile:
    """One data file's sections read as spoken Turkish; what is not is refused with the file and key."""

    def __init__(self, name: str) -> None:
        self.file = f"{name}.toml"
        self.table = load_table(name)

    def error(self, message: str) -> DataError:
        return DataError(f"data file {DATA_DIR / self.file}: {message}")

    def section(self, name: str) -> dict:
        value = self.table.get(name)
        if not isinstance(value, dict):
            raise self.error(f"section [{name}] is missing")
        return value

    def spoken(self, where: str, value: object) -> str:
        if not isinstance(value, str) or not value or not set(value) <= TURKISH_LETTERS | {" "}:
            raise self.error(f"{where} must be lowercase Turkish words, got {value!r}")
        return value

    def mapping(self, name: str) -> dict[str, str]:
        return {key: self.spoken(f"[{name}] {key!r}", value) for key, value in self.section(name).items()}

    def word_list(self, name: str, key: str, length: int | None = None) -> tuple[str, ...]:
        values = self.section(name).get(key)
        if not isinstance(values, list) or length is not None and len(values) != length:
            count = f"{length} " if length is not None else ""
            raise self.error(f"[{name}] {key} must be a list of {count}words")
        return tuple(value and self.spoken(f"[{name}] {key}", value) for value in values)

    def records(self, name: str, kind: type) -> dict:
        """A section of inline tables, each giving the spoken fields of kind (a dataclass)."""
        names = tuple(field.name for field in fields(kind))
        found = {}
        for key, value in self.section(name).items():
            if not isinstance(value, dict):
                raise self.error(f"[{name}] {key!r} must be {{ {', '.join(names)} }}")
            found[key] = kind(
                **{field: self.spoken(f"[{name}] {key!r} {field}", value.get(field)) for field in names}
            )
        return found


@cache
def text_tables() -> Tables:
    """shapekeys/abbreviations.toml and shapekeys/units.toml, validated once."""
    main, units = _TableFile("abbreviations"), _TableFile("units")
    numbers = main.section("numbers")
    scales = main.word_list("numbers", "scales")
    if len(scales) < 2:
        raise main.error("[numbers] scales must list at least '' and 'bin'")
    acronyms = main.section("acronyms")
    for key in ("read_as_words", "particles"):
        if not isinstance(acronyms.get(key, []), list):
            raise main.error(f"[acronyms] {key} must be a list")
    letter_names = main.mapping("letter_names")
    missing = sorted(TURKISH_LETTERS - set(letter_names))
    if missing:
        raise main.error(f"[letter_names] lacks {', '.join(missing)}")
    currencies = units.records("currencies", Currency)
    per_time = units.records("per_time", PerTimeUnit)
    return Tables(
        abbreviations=main.mapping("abbreviations"),
        units_after_number=units.mapping("after_number"),
        per_time_units=per_time,
        currencies=currencies,
        read_as_words=frozenset(acronyms.get("read_as_words", [])),
        spoken_in_full=main.mapping("spoken_in_full"),
        particles=frozenset(acronyms.get("particles", [])),
        letter_names=letter_names,
        foreign_letters=main.mapping("foreign_letters"),
        symbols=main.mapping("symbols"),
        address_words=main.mapping("address_words"),
        top_level_domains=frozenset(main.word_list("addresses", "top_level_domains")),
        directions=units.mapping("directions"),
        fixed_expressions=main.mapping("fixed_expressions"),
        digits=main.word_list("numbers", "digits", 10),
        tens=main.word_list("numbers", "tens", 10),
        hundred=main.spoken("[numbers] hundred", numbers.get("hundred")),
        scales=scales,
        words={key: main.spoken(f"[numbers] {key}", numbers.get(key)) for key in _NUMBER_WORDS},
        months=main.word_list("dates", "months", 12),
        regnal_titles=frozenset(main.word_list("roman_numerals", "titles")),
        stems_before_suffix=main.mapping("stems_before_suffix"),
        soften_always=frozenset(main.word_list("suffixes", "soften_always")),
        soften_never=frozenset(main.word_list("suffixes", "soften_never")),
    )


@lru_cache(maxsize=4096)
def fold_letter(char: str) -> str:
    """A source letter as Turkish letters: "" for letters Turkish cannot say (other scripts)."""
    lower = turkish_lower(char)
    if lower in TURKISH_LETTERS:
        return lower
    foreign = text_tables().foreign_letters
    if lower in foreign:
        return foreign[lower]
    folded = []
    for base in unicodedata.normalize("NFKD", lower):
        if base in TURKISH_LETTERS:
            folded.append(base)
        elif base in foreign:
            folded.append(foreign[base])
    return "".join(folded)
