"""The truth of MBROLA's Turkish takes: the text's letters paired with the voice's phones
(lab/kit/diphone_voices.py); the voices themselves are not needed to test it."""

import pytest

from lab.kit.diphone_voices import PhonesDoNotPair, paired


def test_each_letter_takes_its_phone_in_order():
    assert paired(list("kapı"), ["k", "a", "p", "@"]) == [0, 1, 2, 3]


def test_a_soft_g_and_a_doubled_letter_share_a_neighbours_phone():
    # "ağaç": eSpeak NG says one long a; "bitti": one long t.
    assert paired(list("ağaç"), ["a", "tS"]) == [0, 0, 0, 1]
    assert paired(list("bitti"), ["b", "I", "t", "I"]) == [0, 1, 2, 2, 3]
    # "doğru": the soft g lengthens the o before it.
    assert paired(list("doğru"), ["d", "o", "r", "u"]) == [0, 1, 1, 2, 3]


def test_a_text_that_pairs_only_badly_is_refused():
    with pytest.raises(PhonesDoNotPair):
        paired(list("merhaba"), ["k", "I", "t", "a", "p"])
