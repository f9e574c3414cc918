"""Turkish syllables: one vowel per syllable, the thesis's rule (5.2.2) plus loanword clusters.

The thesis splits a word from its end: a vowel with the consonant before it forms a syllable, and
consonants after a vowel close it, so between two vowels the last consonant opens the next syllable
(ka-lem, er-dem, ilk-o-kul, fark-lı). That is also what standard Turkish hyphenation (TDK, and the TeX
hyph-tr patterns) does. Two extensions make loanwords come out as they are spoken:

- consonants before the first vowel all open the first syllable (tren, spor, stra-te-ji, psi-ko-lo-ji);
- in a run of three or more consonants between vowels, a stop or fricative followed by "r" opens the
  next syllable together (kon-trol, elek-trik, en-düs-tri, eks-tra), as it does at a word's start.
  Only "r" clusters: "l" starts native suffixes (-lar, -lık), so "türk-ler" must not become "tür-kler".
"""

from __future__ import annotations

VOWELS: frozenset[str] = frozenset("aeıioöuü")

# Circumflex vowels are folded by the normaliser, but a word given directly may still hold them.
_SYLLABLE_NUCLEI: frozenset[str] = VOWELS | frozenset("âîû")

# First letters of the loanword onset clusters "Cr" (tr, pr, kr, br, dr, gr, fr, vr).
_R_CLUSTER_FIRST: frozenset[str] = frozenset("bdfgkptv")


def syllable_vowel(syllable: str) -> str | None:
    """The syllable's vowel (its first, if given a malformed syllable), or None for a vowelless one."""
    return next((letter for letter in syllable if letter in _SYLLABLE_NUCLEI), None)


def _onset_length(consonants: str) -> int:
    """How many consonants of a run between two vowels open the second syllable."""
    if not consonants:
        return 0
    if len(consonants) >= 3 and consonants[-1] == "r" and consonants[-2] in _R_CLUSTER_FIRST:
        return 2
    return 1


def syllabify(word: str) -> tuple[str, ...]:
    """Split a lowercase Turkish word into syllables; a word without vowels is one syllable."""
    nuclei = [index for index, letter in enumerate(word) if letter in _SYLLABLE_NUCLEI]
    if len(nuclei) <= 1:
        return (word,) if word else ()
    starts = [0]
    for previous, following in zip(nuclei, nuclei[1:], strict=False):
        consonants = word[previous + 1 : following]
        starts.append(following - _onset_length(consonants))
    starts.append(len(word))
    return tuple(word[begin:end] for begin, end in zip(starts, starts[1:], strict=False))
