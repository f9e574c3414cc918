"""Letters to the thesis's 36 vowel-context visemes + neutral (Table 5.1, data in shapekeys/letters.toml)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from ..base.data import DATA_DIR, load_table, require
from ..base.errors import DataError

NEUTRAL = "neutral"
BILABIAL_VISEMES = frozenset({"bpa", "bpe", "bpo", "ma", "me", "mo"})
LABIODENTAL_VISEMES = frozenset({"fvae", "fvo"})
VOWEL_VISEMES = frozenset({"a", "e", "I", "Ii", "o", "oi", "u"})


@dataclass(frozen=True)
class LetterTable:
    models: dict[str, int]  # model name -> thesis number
    vowel_groups: dict[str, int]  # vowel -> 0 (a, ı), 1 (e, i), 2 (o, ö, u, ü)
    vowels: dict[str, str]  # vowel -> its model
    consonants: dict[str, tuple[str, str, str]]  # consonant -> model per vowel group
    vowel_shaped: frozenset[str]  # letters taking the vowel's own model (ğ, h)


@cache
def letter_table() -> LetterTable:
    table = load_table("letters")
    path = DATA_DIR / "letters.toml"
    models = require(table, "models", dict, "letters")
    groups = require(table, "vowel_groups", dict, "letters")
    vowels = require(table, "vowels", dict, "letters")
    consonants = require(table, "consonants", dict, "letters")
    vowel_shaped = require(table, "vowel_shaped", list, "letters")
    group_index = {"a": 0, "e": 1, "o": 2}
    if sorted(models.values()) != list(range(37)):
        raise DataError(f"{path}: [models] must number the 37 models 0..36 once each")
    for letter, group in groups.items():
        if group not in group_index:
            raise DataError(f"{path}: vowel group of {letter!r} must be a, e or o, not {group!r}")
    for letter, row in {**{v: [m] for v, m in vowels.items()}, **consonants}.items():
        if letter not in groups and letter in vowels:
            raise DataError(f"{path}: vowel {letter!r} has no vowel group")
        for model in row:
            if model not in models:
                raise DataError(f"{path}: letter {letter!r} maps to unknown model {model!r}")
        if letter in consonants and len(row) != 3:
            raise DataError(f"{path}: consonant {letter!r} needs three models (groups a, e, o)")
    return LetterTable(
        models=dict(models),
        vowel_groups={v: group_index[g] for v, g in groups.items()},
        vowels=dict(vowels),
        consonants={c: tuple(row) for c, row in consonants.items()},
        vowel_shaped=frozenset(vowel_shaped),
    )


def viseme_names() -> tuple[str, ...]:
    """The 37 model names in the thesis's numbering (0..35, neutral 36)."""
    models = letter_table().models
    return tuple(sorted(models, key=models.get))


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
