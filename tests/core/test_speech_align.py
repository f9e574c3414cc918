"""Letter-to-phone alignment on the symbols eSpeak NG's Turkish voice really emits."""

import pytest

from turkish_lipsync.core.speech import get_engine
from turkish_lipsync.core.speech.align import align_word, alignment_costs
from turkish_lipsync.core.speech.espeak import EspeakEngine


def aligned(word, symbols):
    return align_word(word, symbols, EspeakEngine.letter_symbols(), alignment_costs())


@pytest.mark.parametrize(
    ("word", "symbols", "expected"),
    [
        # Seen from eSpeak NG 1.52 "tr": every letter its own phone.
        ("anne", ["a", "n", "n", "E"], [[0], [1], [2], [3]]),
        ("elli", ["&", "l", "l", "I"], [[0], [1], [2], [3]]),
        ("çağdaş", ["tS", "a", "d", "a", "S"], [[0], [1], [], [2], [3], [4]]),
        ("değil", ["d", "e", "j", "I", "l"], [[0], [1], [2], [3], [4]]),  # ğ between front vowels is j
        ("gönül", ["J", "W", "n", "Y", "l"], [[0], [1], [2], [3], [4]]),
        ("anlattı", ["a", "n", "L", "a", "t", "@"], [[0], [1], [2], [3], [4], [], [5]]),  # tt as one t
        ("ağaç", ["a", "tS"], [[0], [], [], [1]]),  # a-ğ-a spoken as one long a: the first a keeps it
        ("kitab", ["k", "i", "t", "a", "p"], [[0], [1], [2], [3], [4]]),  # final devoicing
        ("yağarsa", ["j", "a", "R", "s", "a"], [[0], [1], [], [], [2], [3], [4]]),
    ],
)
def test_letters_get_the_phones_that_realise_them(word, symbols, expected):
    assert aligned(word, symbols) == expected


def test_a_phone_no_letter_explains_joins_the_letter_before_it():
    assert aligned("bir", ["b", "I", "R", "@"]) == [[0], [1], [2, 3]]
    assert aligned("on", ["h", "O", "n"]) == [[0, 1], [2]]  # at the start it joins the first letter


def test_stress_and_length_marks_are_ignored_and_pauses_are_not_phones():
    engine = get_engine("espeak")
    assert engine.bare_symbol("'a") == "a"
    assert engine.bare_symbol(",Y") == "Y"
    assert engine.bare_symbol("a:") == "a"
    assert engine.bare_symbol("_:") is None
    assert engine.bare_symbol("_!") is None


def test_every_turkish_letter_has_phone_symbols():
    symbols = EspeakEngine.letter_symbols()
    assert set("abcçdefgğhıijklmnoöprsştuüvyz") <= set(symbols)
