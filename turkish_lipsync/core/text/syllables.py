"""Turkish syllables: one vowel per syllable, the thesis's rule (5.2.2) plus loanword clusters.

The thesis splits a word from its end: a vowel with the consonant before it forms a syllable, and
consonants after a vowel close it, so between two vowels the last consonant opens the next syllable
(ka-lem, er-dem, ilk-o-kul, fark-lı, and in loanwords kont-rol, e-lekt-rik, bank-ta). That is also what
standard Turkish hyphenation (TDK, and the TeX hyph-tr patterns) does. The thesis's algorithm breaks on
loanwords that start with several consonants (it leaves "t" of "tren" as a syllable without a vowel), so
consonants before the first vowel all open the first syllable (tren, spor, stra-te-ji, psi-ko-lo-ji).
"""

from __future__ import annotations

VOWELS: frozenset[str] = frozenset("aeıioöuü")

# Circumflex vowels are folded by the normaliser, but a word given directly may still hold them.
_SYLLABLE_NUCLEI: frozenset[str] = VOWELS | frozenset("âîû")


def syllable_vowel(syllable: str) -> str | None:
    """The syllable's vowel (its first, if given a malformed syllable), or None for a vowelless one."""
    return next((letter for letter in syllable if letter in _SYLLABLE_NUCLEI), None)


def syllabify(word: str) -> tuple[str, ...]:
    """Split a lowercase Turkish word into syllables; a word without vowels is one syllable."""
    nuclei = [index for index, letter in enumerate(word) if letter in _SYLLABLE_NUCLEI]
    if len(nuclei) <= 1:
        return (word,) if word else ()
    starts = [0]
    for previous, following in zip(nuclei, nuclei[1:], strict=False):
        # Between two vowels, only the last consonant (if any) opens the next syllable.
        starts.append(following - (1 if following - previous > 1 else 0))
    starts.append(len(word))
    return tuple(word[begin:end] for begin, end in zip(starts, starts[1:], strict=False))
