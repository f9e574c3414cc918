"""The utterance: what the text says, and what it holds that Turkish speech cannot say."""

import pytest

from turkish_lipsync.core.base.errors import TextError
from turkish_lipsync.core.text.normalize import spoken_text
from turkish_lipsync.core.text.utterance import build_utterance, unspoken_warning


def test_other_scripts_and_emoji_are_left_silent_with_a_warning_that_names_them():
    utterance = build_utterance("Merhaba Привет dünya 😀👍🏽, مرحبا. Çok güzel.")
    assert [word.text for word in utterance.words] == ["merhaba", "dünya", "çok", "güzel"]
    assert utterance.unspoken == ("Привет", "😀👍🏽", "مرحبا")
    (warning,) = unspoken_warning(utterance)
    assert "'Привет', '😀👍🏽', 'مرحبا'" in warning
    assert unspoken_warning(build_utterance("Ça va? Straße Łódź")) == ()  # Latin letters are read


def test_a_text_of_only_other_scripts_says_what_it_left_out():
    with pytest.raises(TextError, match="left out, as Turkish speech cannot say them: 'Привет'"):
        build_utterance("Привет")


@pytest.mark.parametrize(
    ("written", "spoken"),
    [("%-3", "yüzde eksi üç"), ("sıcaklık -%3", "sıcaklık eksi yüzde üç"), ("%3", "yüzde üç")],
)
def test_a_signed_percentage_keeps_both_words(written, spoken):
    assert spoken_text(written) == spoken


def test_a_text_beyond_the_limit_is_refused_at_once(monkeypatch):
    from turkish_lipsync.core.text import utterance

    monkeypatch.setattr(utterance, "MAX_SOURCE_CHARACTERS", 100)
    with pytest.raises(TextError, match="101 characters, more than the 100"):
        build_utterance("a" * 101)
    assert build_utterance("merhaba " * 12).words  # 96 characters
