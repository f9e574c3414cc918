"""The normaliser on sentences it was not tuned on, and on the public benchmark turkce-tts-sinav."""

from __future__ import annotations

import importlib.util
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "score_normalization.py"


def _scorer():
    spec = importlib.util.spec_from_file_location("score_normalization", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_held_out_everyday_sentences_are_read_right() -> None:
    scorer = _scorer()
    cases = scorer.read_cases(scorer.HELD_OUT)
    assert len(cases) >= 60
    right, word_error_rate, wrong = scorer.score(cases)
    assert right >= 0.95 * len(cases), wrong
    assert word_error_rate < 0.02


def test_public_benchmark() -> None:
    scorer = _scorer()
    cases = scorer.read_cases(scorer.benchmark_path())
    assert len(cases) == 128
    right, word_error_rate, wrong = scorer.score(cases)
    assert right >= 0.90 * len(cases), wrong
    assert word_error_rate < 0.05


def test_the_score_is_blind_to_case_and_punctuation_only() -> None:
    scorer = _scorer()
    assert scorer.reading_words("Ankara'da, İZMİR'de.") == ["ankarada", "izmirde"]
    right, _, wrong = scorer.score([("Saat 09:30'da.", "saat dokuz otuzda", ""), ("3 elma", "dört elma", "")])
    assert right == 1 and wrong == [("3 elma", "üç elma", "dört elma")]
