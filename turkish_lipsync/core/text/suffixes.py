"""Suffixes written after an apostrophe, spoken on the word they follow.

A suffix after a number, a unit or a currency was written for the digits or the sign ("TL'ye", "1/2'si"),
but it is spoken on their reading ("liraya", "yarısı"): it takes the reading's vowel harmony, its buffer
consonant and its d/t. A proper noun keeps its written suffix but its final p, ç, t, k softens before a
vowel (Zeynep'e -> zeynebe). Every letter keeps the source index it came from.
"""

from __future__ import annotations

import re

from .tables import VOWELS, text_tables

Letters = list[tuple[str, int]]  # (letter, source index)

_FRONT = frozenset("eiöü")
_ROUNDED = frozenset("oöuü")
_VOICELESS = frozenset("fstkçşhp")
_SOFTENED = {"p": "b", "ç": "c", "t": "d", "k": "ğ"}
_BUFFERS = frozenset("nsy")
TURKISH_WRITTEN = frozenset("abcçdefgğhıijklmnoöprsştuüvyzâîû")
_ORDINAL_SUFFIX = re.compile("[ıiuü]?nc[ıiuü]")
_ORDINAL_EXCEPTIONS = {"dört": "dördüncü"}


def harmonized_vowel(previous: str, vowel: str) -> str:
    """A suffix vowel in harmony with the vowel before it: a/e two ways, ı/i/u/ü four ways."""
    front = previous in _FRONT
    if vowel in "ae":
        return "e" if front else "a"
    if vowel in "ıiuü":
        rounded = previous in _ROUNDED
        return ("ü" if rounded else "i") if front else ("u" if rounded else "ı")
    return vowel


def _last_vowel(word: str) -> str:
    return next((letter for letter in reversed(word) if letter in VOWELS), "e")


def ordinal(word: str) -> str:
    """The ordinal of a number word: bir -> birinci, üç -> üçüncü, altı -> altıncı (vowel harmony)."""
    if word in _ORDINAL_EXCEPTIONS:
        return _ORDINAL_EXCEPTIONS[word]
    vowel = harmonized_vowel(_last_vowel(word), "i")
    return word + ("nc" if word[-1] in VOWELS else vowel + "nc") + vowel


def softens(word: str) -> bool:
    """Whether a word's final p, ç, t, k softens before a vowel: words of several syllables do, with a
    few exceptions (saat -> saate), and a few of one syllable too (dört -> dördü)."""
    tables = text_tables()
    if not word or word[-1] not in _SOFTENED or word in tables.soften_never:
        return False
    return word in tables.soften_always or sum(letter in VOWELS for letter in word) >= 2


def _soften(stem: Letters) -> Letters:
    """The stem with its final consonant softened (k after n becomes g: renk -> rengi)."""
    final, offset = stem[-1]
    softened = "g" if final == "k" and len(stem) > 1 and stem[-2][0] == "n" else _SOFTENED[final]
    return [*stem[:-1], (softened, offset)]


def _harmonize(stem: str, suffix: Letters) -> Letters:
    """Every vowel of the suffix in harmony with the one before it; "ki" (2020'deki) keeps its i."""
    previous = _last_vowel(stem)
    result: Letters = []
    for position, (letter, offset) in enumerate(suffix):
        if letter in VOWELS and not (position >= 1 and position == len(suffix) - 1 and suffix[-2][0] == "k"):
            letter = harmonized_vowel(previous, letter)
        if letter in VOWELS:
            previous = letter
        result.append((letter, offset))
    return result


def _voice(stem: str, suffix: Letters) -> Letters:
    """d/t and c/ç at the start of a suffix follow the stem's last sound: dokuzda, dörtte."""
    first, offset = suffix[0]
    voiceless = stem[-1] in _VOICELESS
    if first in "dt":
        first = "t" if voiceless else "d"
    elif first in "cç":
        first = "ç" if voiceless else "c"
    return [(first, offset), *suffix[1:]]


def spoken_suffix(stem: Letters, suffix: Letters) -> Letters:
    """A reading's last word and the suffix written after it, as one spoken word (re-harmonised)."""
    if not suffix:
        return stem
    tables = text_tables()
    stem_text = "".join(letter for letter, _ in stem)
    replacement = tables.stems_before_suffix.get(stem_text)
    if replacement is not None:  # yarım + sı -> yarısı
        stem = [(letter, stem[min(index, len(stem) - 1)][1]) for index, letter in enumerate(replacement)]
        stem_text = replacement
    text = "".join(letter for letter, _ in suffix)
    ordinal_suffix = _ORDINAL_SUFFIX.match(text)
    if ordinal_suffix:  # 5'inci, 12'nci: the ordinal of the number word, then whatever follows
        offset = suffix[0][1]
        stem_text = ordinal(stem_text)
        stem = [
            (letter, stem[index][1] if index < len(stem) else offset)
            for index, letter in enumerate(stem_text)
        ]
        suffix = suffix[ordinal_suffix.end() :]
        if not suffix:
            return stem
    buffer = None
    if len(suffix) > 1 and suffix[0][0] in _BUFFERS and suffix[1][0] in VOWELS:
        buffer, suffix = suffix[0], suffix[1:]
    elif len(suffix) > 1 and suffix[0][0] == "y" and suffix[1][0] == "l" and stem_text[-1] not in VOWELS:
        suffix = suffix[1:]  # 5'yle -> beşle
    suffix = _harmonize(stem_text, _voice(stem_text, suffix))
    if suffix[0][0] in VOWELS:
        if stem_text[-1] in VOWELS:
            # A written suffix without its buffer was written for a consonant (2/3'ü for "üç"): a high
            # vowel is then most often the possessive (üçte ikisi), a or e the dative (liraya).
            default = "s" if suffix[0][0] in "ıiuü" else "y"
            return stem + [buffer or (default, suffix[0][1])] + suffix
        if softens(stem_text):
            stem = _soften(stem)
    return stem + suffix


def proper_noun_suffix(stem: Letters, suffix: Letters, *, written: str) -> Letters:
    """A name and its written suffix: the suffix as written, the name's consonant softened before a vowel.
    Names written the foreign way keep it (Facebook'a, Microsoft'a): letters outside Turkish, a doubled
    vowel, or two consonants at the end (other than nk: Ersenk'e)."""
    name = "".join(letter for letter, _ in stem)
    foreign = (
        not set(written.lower()) <= TURKISH_WRITTEN
        or any(first == second and first in VOWELS for first, second in zip(name, name[1:], strict=False))
        or len(name) > 2
        and name[-2] not in VOWELS
        and name[-2] != "n"
    )
    if suffix and suffix[0][0] in VOWELS and not foreign and softens(name):
        stem = _soften(stem)
    return stem + suffix
