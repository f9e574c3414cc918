"""Score the text normaliser against readings of real sentences: sentences read right and word error rate.

    .venv/bin/python -m lab.measure.normalization                 # the public benchmark turkce-tts-sinav
    .venv/bin/python -m lab.measure.normalization --set held-out  # our own everyday sentences
    .venv/bin/python -m lab.measure.normalization --set FILE.tsv --wrong --groups

A case is a TSV line `written<TAB>expected reading[<TAB>group]` (lines starting with # are comments). The
spoken words (what the timeline's `words` hold) are compared with the expected reading blind to case and
punctuation: both are lowercased the Turkish way, apostrophes vanish and every other character that is no
letter separates words.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from lab.kit.readings import HELD_OUT, benchmark_path, read_cases, score


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
