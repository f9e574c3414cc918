"""KLettres' syllables to train on: spelt in Turkish letters; the languages kept for measuring left out."""

import pytest

from lab.kit.klettres_syllables import BY_NAME, LANGUAGES, spell


@pytest.mark.parametrize(
    ("language", "name", "stem", "spelt"),
    [
        ("ml", "ഞൂ", "njuu", "nyu"),  # a digraph before its letters: nj is not n + j
        ("ml", "ഭൈ", "bhai", "bay"),
        ("ml", "ഠം", "ttam", "tam"),
        ("ml", "ക:", "kaha", "kah"),
        ("lt", "DŽIU", "dz2iu", "ciu"),
        ("lt", "VĖL", "ve3l", "vel"),
        ("de", "FUß", "fusz", "fus"),
        ("he", "מי", "ad-24", "mi"),
    ],
)
def test_a_syllable_is_spelt_as_a_turkish_reader_would_write_it(language, name, stem, spelt):
    assert spell(language, name, stem) == spelt


def test_a_consonant_said_alone_or_a_name_no_table_holds_has_no_spelling():
    assert spell("ml", "ക്", "k") is None
    assert spell("da", "XYZ", "ad-99") is None


def test_every_hand_spelling_is_turkish_letters_with_a_vowel():
    for language, table in BY_NAME.items():
        for name in table:
            assert spell(language, name, "") == table[name], (language, name)


def test_the_languages_kept_for_measuring_are_not_read():
    assert not {"hu", "es", "it", "pt_BR", "ru", "uk", "tn", "fr", "cs"} & set(LANGUAGES)
    with pytest.raises(ValueError, match="hu"):
        spell("hu", "BA", "ba")
