"""Letters to the thesis's 36 vowel-context visemes + neutral (Table 5.1, data in shapekeys/letters.toml).

The visemes themselves (names, numbers, kinds) are the viseme set's (core/base/visemes.py); this table says
which letter in which vowel context becomes which of them, and is checked against the set when it loads.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from ..base.data import DATA_DIR, load_table, require
from ..base.errors import DataError
from ..base.visemes import NEUTRAL, VISEME_NAMES, visemes_of_kind


@dataclass(frozen=True)
class LetterTable:
    vowel_groups: dict[str, int]  # vowel -> 0 (a, ı), 1 (e, i), 2 (o, ö, u, ü)
    vowels: dict[str, str]  # vowel -> its model
    consonants: dict[str, tuple[str, str, str]]  # consonant -> model per vowel group
    vowel_shaped: frozenset[str]  # letters taking the vowel's own model (ğ, h)


@cache
def letter_table() -> LetterTable:
    table = load_table("letters")
    path = DATA_DIR / "letters.toml"
    groups = require(table, "vowel_groups", dict, "letters")
    vowels = require(table, "vowels", dict, "letters")
    consonants = require(table, "consonants", dict, "letters")
    vowel_shaped = require(table, "vowel_shaped", list, "letters")
    group_index = {"a": 0, "e": 1, "o": 2}
    for letter, group in groups.items():
        if group not in group_index:
            raise DataError(f"{path}: vowel group of {letter!r} must be a, e or o, not {group!r}")
    for letter, row in {**{v: [m] for v, m in vowels.items()}, **consonants}.items():
        if letter not in groups and letter in vowels:
            raise DataError(f"{path}: vowel {letter!r} has no vowel group")
        for model in row:
            if model not in VISEME_NAMES:
                raise DataError(
                    f"{path}: letter {letter!r} maps to {model!r}, which is not in the viseme set"
                )
        if letter in consonants and len(row) != 3:
            raise DataError(f"{path}: consonant {letter!r} needs three models (groups a, e, o)")
    reached = set(vowels.values()) | {model for row in consonants.values() for model in row}
    unreached = sorted(set(VISEME_NAMES) - reached - {NEUTRAL})
    if unreached:
        raise DataError(f"{path}: no letter becomes the viseme(s) {', '.join(unreached)} of the viseme set")
    for letter, model in vowels.items():
        if model not in visemes_of_kind("vowel"):
            raise DataError(
                f"{path}: vowel {letter!r} maps to {model!r}, which the viseme set calls no vowel"
            )
    return LetterTable(
        vowel_groups={v: group_index[g] for v, g in groups.items()},
        vowels=dict(vowels),
        consonants={c: tuple(row) for c, row in consonants.items()},
        vowel_shaped=frozenset(vowel_shaped),
    )


def viseme_for_letter(letter: str, syllable_vowel: str | None) -> str:
    """The model of a letter spoken in a syllable whose vowel is syllable_vowel (None: no vowel)."""
    table = letter_table()
    if letter in table.vowels:
        return table.vowels[letter]
    if letter in table.vowel_shaped:
        return table.vowels[syllable_vowel] if syllable_vowel else NEUTRAL
    row = table.consonants.get(letter)
    if row is None:
        raise DataError(f"no viseme for the letter {letter!r}: it is not a Turkish letter")
    # A syllable without a vowel (an interjection like "hmm") is spoken with spread, unrounded lips.
    group = table.vowel_groups[syllable_vowel] if syllable_vowel else 1
    return row[group]
