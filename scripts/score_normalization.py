"""Score the text normaliser against readings of real sentences: sentences read right and word error rate.

    .venv/bin/python scripts/score_normalization.py                 # the public benchmark turkce-tts-sinav
    .venv/bin/python scripts/score_normalization.py --set held-out  # our own everyday sentences
    .venv/bin/python scripts/score_normalization.py --set FILE.tsv --wrong --groups

A case is a TSV line `written<TAB>expected reading[<TAB>group]` (lines starting with # are comments). The
spoken words (what the timeline's `words` hold) are compared with the expected reading blind to case and
punctuation: both are lowercased the Turkish way, apostrophes vanish and every other character that is no
letter separates words.
"""

from __future__ import annotations

import argparse
import sys
from importlib import resources
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from turkish_lipsync.core.text.normalize import spoken_words  # noqa: E402
from turkish_lipsync.core.text.tables import fold_letter  # noqa: E402

HELD_OUT = ROOT / "tests" / "core" / "data" / "normalization_held_out.tsv"


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


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--set", default="benchmark", help="benchmark, held-out, or a TSV file")
    parser.add_argument("--wrong", action="store_true", help="list the sentences read wrong")
    parser.add_argument("--groups", action="store_true", help="sentences right in each group of the set")
    args = parser.parse_args()
    path = {"benchmark": None, "held-out": HELD_OUT}.get(args.set, Path(args.set))
    cases = read_cases(path or benchmark_path())
    right, word_error_rate, wrong = score(cases)
    print(
        f"{args.set}: {right} of {len(cases)} sentences right ({100 * right / len(cases):.1f}%), "
        f"word error rate {100 * word_error_rate:.1f}%"
    )
    if args.groups:
        wrong_sentences = {written for written, _, _ in wrong}
        for group in dict.fromkeys(group for _, _, group in cases):
            members = [written for written, _, case_group in cases if case_group == group]
            right_here = sum(written not in wrong_sentences for written in members)
            print(f"  {group or '-'}: {right_here} of {len(members)}")
    if args.wrong:
        for written, ours, expected in wrong:
            print(f"  {written}\n    ours:     {ours}\n    expected: {expected}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
