"""Readings of written Turkish to score the text normaliser on: the cases (written, expected reading) and the
score (sentences read right, word error rate), blind to case and punctuation.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from lab import REPOSITORY
from turkish_lipsync.core.text.normalize import spoken_words
from turkish_lipsync.core.text.tables import fold_letter

HELD_OUT = REPOSITORY / "tests" / "core" / "data" / "normalization_held_out.tsv"


def benchmark_path() -> Path:
    """The public benchmark's cases, shipped inside the turkce-tts-sinav package."""
    return Path(str(resources.files("turkce_tts_sinav") / "veri" / "normalizasyon.tsv"))


def read_cases(path: Path) -> list[tuple[str, str, str]]:
    cases = []
    for line in path.read_text(encoding="utf-8").splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        written, expected, *group = line.split("\t")
        cases.append((written, expected, group[0] if group else ""))
    return cases


def reading_words(text: str) -> list[str]:
    """A reading as words of Turkish letters: case and punctuation do not count."""
    return "".join(fold_letter(char) or ("" if char in "'’" else " ") for char in text).split()


def edit_distance(first: list[str], second: list[str]) -> int:
    previous = list(range(len(second) + 1))
    for row, word in enumerate(first, 1):
        current = [row]
        for column, other in enumerate(second, 1):
            current.append(min(previous[column] + 1, current[-1] + 1, previous[column - 1] + (word != other)))
        previous = current
    return previous[-1]


def score(cases: list[tuple[str, str, str]]) -> tuple[int, float, list[tuple[str, str, str]]]:
    """Sentences read right, the word error rate, and the wrong ones (written, ours, expected)."""
    right = errors = total = 0
    wrong = []
    for written, expected, _group in cases:
        ours = reading_words(" ".join(spoken_words(written)))
        reference = reading_words(expected)
        distance = edit_distance(ours, reference)
        errors += distance
        total += len(reference)
        right += distance == 0
        if distance:
            wrong.append((written, " ".join(ours), " ".join(reference)))
    return right, errors / max(total, 1), wrong
