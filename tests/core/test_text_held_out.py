"""The normaliser on sentences it was not tuned on, and on the public benchmark turkce-tts-sinav."""

from __future__ import annotations

from lab.kit import readings as scorer


def test_held_out_everyday_sentences_are_read_right() -> None:
    cases = scorer.read_cases(scorer.HELD_OUT)
    assert len(cases) >= 60
    right, word_error_rate, wrong = scorer.score(cases)
    assert right >= 0.95 * len(cases), wrong
    assert word_error_rate < 0.02


def test_public_benchmark() -> None:
    cases = scorer.read_cases(scorer.benchmark_path())
    assert len(cases) == 128
    right, word_error_rate, wrong = scorer.score(cases)
    assert right >= 0.90 * len(cases), wrong
    assert word_error_rate < 0.05


def test_the_score_is_blind_to_case_and_punctuation_only() -> None:
    assert scorer.reading_words("Ankara'da, İZMİR'de.") == ["ankarada", "izmirde"]
    right, _, wrong = scorer.score([("Saat 09:30'da.", "saat dokuz otuzda", ""), ("3 elma", "dört elma", "")])
    assert right == 1 and wrong == [("3 elma", "üç elma", "dört elma")]
