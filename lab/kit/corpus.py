"""The Turkish sentences the benchmark and the measuring scripts speak: examples/corpus_tr.txt.

Its first TUNING_LINES sentences tune the aligner and the recogniser's decoder; the others are held out
(the recogniser never trains on them, the measures report on them).
"""

from __future__ import annotations

from lab import REPOSITORY

CORPUS = REPOSITORY / "examples" / "corpus_tr.txt"
TUNING_LINES = 30


def corpus_sentences() -> list[str]:
    """Every sentence of the corpus, in its order."""
    return [line.strip() for line in CORPUS.read_text(encoding="utf-8").splitlines() if line.strip()]


def tuning_sentences() -> list[str]:
    return corpus_sentences()[:TUNING_LINES]


def held_out_sentences() -> list[str]:
    return corpus_sentences()[TUNING_LINES:]
