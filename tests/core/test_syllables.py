"""Turkish syllables: the thesis's examples, loanword clusters, and agreement with TeX hyphenation."""

from __future__ import annotations

import functools
import os
import re
import sys
from pathlib import Path

import pytest

from turkish_lipsync.core.text.syllables import VOWELS, syllabify, syllable_vowel


@pytest.mark.parametrize(
    ("word", "expected"),
    [
        # The thesis's syllable shapes (5.2.2): a, ab, ba, abb, bab, babb.
        ("uğur", "u-ğur"),
        ("erdem", "er-dem"),
        ("kalem", "ka-lem"),
        ("yağmur", "yağ-mur"),
        ("farklı", "fark-lı"),
        ("merhaba", "mer-ha-ba"),
        ("akagündüz", "a-ka-gün-düz"),
        # Vowels in a row each make a syllable.
        ("saat", "sa-at"),
        ("şiir", "şi-ir"),
        # Loanword clusters: at the start they stay together; inside a word only the last consonant opens
        # the next syllable, as in TDK's and TeX's hyphenation (kont-rol, sant-ral).
        ("tren", "tren"),
        ("spor", "spor"),
        ("strateji", "stra-te-ji"),
        ("psikoloji", "psi-ko-lo-ji"),
        ("kontrol", "kont-rol"),
        ("elektrik", "e-lekt-rik"),
        ("endüstri", "en-düst-ri"),
        ("ekstra", "ekst-ra"),
        ("bankta", "bank-ta"),
        # Native suffixes that start with l must not pull a consonant along (not "tür-kler").
        ("türkler", "türk-ler"),
        ("dostlar", "dost-lar"),
        # Two consonants between vowels are split, as TDK and TeX do (met-ro, prog-ram).
        ("metro", "met-ro"),
        ("program", "prog-ram"),
    ],
)
def test_known_words(word: str, expected: str) -> None:
    assert "-".join(syllabify(word)) == expected


def test_thesis_sentence() -> None:
    words = "merhaba benim adım erdem akagündüz".split()
    assert [("-".join(syllabify(word))) for word in words] == [
        "mer-ha-ba",
        "be-nim",
        "a-dım",
        "er-dem",
        "a-ka-gün-düz",
    ]


def test_words_without_vowels_stay_whole() -> None:
    assert syllabify("hmm") == ("hmm",)
    assert syllabify("ş") == ("ş",)
    assert syllabify("") == ()
    assert syllable_vowel("hmm") is None


def test_vowels_and_syllable_vowel() -> None:
    assert VOWELS == frozenset("aeıioöuü")
    assert syllable_vowel("gün") == "ü"
    assert syllable_vowel("stra") == "a"
    assert syllable_vowel("kâ") == "â"  # a circumflex vowel given directly is still the nucleus


# ----------------------------------------------------------------------------- the hyphenation oracle
#
# The oracle is standard Turkish hyphenation: the TeX hyph-tr patterns (hyph-utf8, generated from the
# TDK rules), applied by pyphen. pyphen ships no Turkish dictionary, so the patterns come from TeX Live's
# hyph-tr.pat.txt (Debian package texlive-lang-european); `make setup` puts a copy at
# <venv>/share/hyph-tr.pat.txt. The word list is wordfreq's Turkish list (words from subtitles, Wikipedia,
# news and the web), so neither the words nor the expected answers are ours.
#
# How we compare: TeX hyphenation is typesetting, not syllabification. It refuses breaks near word edges
# (lefthyphenmin/righthyphenmin 2), and with the edge limits lifted it would split word-initial and
# word-final clusters (s-por, teks-t) that are not syllable boundaries. So we compare what decides
# syllables: for every pair of neighbouring vowels in a word, the boundary between them. TeX places
# exactly one break in each such gap, except where a pattern forbids it for typographic reasons
# (2e2cek. keeps the future suffix "-ecek" whole, tu4r4k): there TeX abstains and the gap is not compared.
# A word agrees when all its compared gaps agree.

_TURKISH_WORD = re.compile("[abcçdefgğhıijklmnoöprsştuüvyz]+")
_TEX_PATTERN_PLACES = [
    os.environ.get("TURKISH_HYPHENATION_PATTERNS", ""),
    str(Path(sys.prefix) / "share" / "hyph-tr.pat.txt"),
    "/usr/share/texlive/texmf-dist/tex/generic/hyph-utf8/patterns/txt/hyph-tr.pat.txt",
]


def _tex_hyphenator(tmp_path_factory: pytest.TempPathFactory):
    pyphen = pytest.importorskip("pyphen")
    source = next((Path(place) for place in _TEX_PATTERN_PLACES if place and Path(place).is_file()), None)
    if source is None:
        pytest.skip(
            "the TeX Turkish hyphenation patterns (hyph-tr.pat.txt) are not installed; run `make setup` "
            "or set TURKISH_HYPHENATION_PATTERNS to the file"
        )
    patterns = source.read_text(encoding="utf-8").split()
    dictionary = tmp_path_factory.mktemp("hyphenation") / "hyph_tr_TR.dic"
    dictionary.write_text("UTF-8\n" + "\n".join(patterns) + "\n", encoding="utf-8")
    return pyphen.Pyphen(filename=str(dictionary), left=1, right=1)


@functools.cache
def _turkish_words() -> list[str]:
    wordfreq = pytest.importorskip("wordfreq")
    words = sorted({word for word in wordfreq.top_n_list("tr", 100_000) if _TURKISH_WORD.fullmatch(word)})
    assert len(words) > 20_000
    return words


def test_agrees_with_tex_hyphenation_on_a_large_word_list(tmp_path_factory: pytest.TempPathFactory) -> None:
    hyphenator = _tex_hyphenator(tmp_path_factory)
    words = _turkish_words()
    disagreeing: list[str] = []
    compared_gaps = abstained_gaps = 0
    for word in words:
        parts = syllabify(word)
        assert "".join(parts) == word
        if any(letter in VOWELS for letter in word):
            assert all(sum(letter in VOWELS for letter in part) == 1 for part in parts), parts
        ours: set[int] = set()
        position = 0
        for part in parts[:-1]:
            position += len(part)
            ours.add(position)
        tex = set(hyphenator.positions(word))
        nuclei = [index for index, letter in enumerate(word) if letter in VOWELS]
        agrees = True
        for left, right in zip(nuclei, nuclei[1:], strict=False):
            gap = set(range(left + 1, right + 1))  # break positions between the two vowels
            if not tex & gap:
                abstained_gaps += 1
                continue
            compared_gaps += 1
            agrees = agrees and (tex & gap) == (ours & gap)
        if not agrees:
            disagreeing.append(word)
    agreement = 1 - len(disagreeing) / len(words)
    print(
        f"{len(words)} words, {compared_gaps} gaps compared, {abstained_gaps} where TeX abstains, "
        f"agreement {agreement:.5f}; disagreeing: {disagreeing[:20]}"
    )
    assert compared_gaps > 100_000
    assert agreement >= 0.999, disagreeing[:50]
