"""The judgement's settings (speech/aligner_settings.py) tried on people's recordings, the tune part only.

    python -m lab.tune.judgement [--cache DIR] [--set NAME=VALUE ...] [--try NAME=V1,V2,...]

Every take of the tune part that lab/measure/people.py aligns with a text (words said alone, lists of
eight read with pauses with their own text and another speaker's, the Czech and Dutch lines with their
own spelling and with the next line's) is aligned once per pair of weights files, heard by the shipped
network and by the people's (the aligner's second hearing), and what the aligner hands the judgement (the
text and the take's two fits: recording.fit_recording, fit_again) is kept in a cache folder. Each setting
then re-runs only the judgement and the choice between the hearings (recording.judged_fit,
kept_hearing), so a sweep over its settings takes seconds per setting. Printed per set: how many takes
of their own text are refused and warned, how many takes of another text are refused or warned
(caught), and the take's mismatch and order ratio (the first hearing's) at their median and extremes,
which say where a bar can go.

NAME is a setting of AlignerSettings that the judgement reads (e.g. loose, other_text); each --try varies
one setting from the --set baseline.
"""

from __future__ import annotations

import argparse
import hashlib
import pickle
import sys
import tempfile
from collections import Counter
from pathlib import Path

import numpy as np

from lab.kit import people
from lab.kit.sweep import settings_tried
from lab.kit.takes import write_wav
from lab.measure.people import RATE, list_items, words
from lab.measure.recogniser import TUNING_CACHE
from turkish_lipsync.core.base.errors import AudioError, LipSyncError
from turkish_lipsync.core.base.model import Utterance
from turkish_lipsync.core.speech import get_engine
from turkish_lipsync.core.speech.acoustic.network import PEOPLE_WEIGHTS_FILE, WEIGHTS_FILE, load_network
from turkish_lipsync.core.speech.aligner_settings import DEFAULT_ALIGNER, AlignerSettings
from turkish_lipsync.core.speech.judgement import take_mismatch
from turkish_lipsync.core.speech.recording import (
    RecordingFit,
    fit_again,
    fit_recording,
    judged_fit,
    kept_hearing,
    without_hesitations,
)
from turkish_lipsync.core.text.utterance import build_utterance

FIRST_ALIGNER = without_hesitations(DEFAULT_ALIGNER)  # as align_recording's first alignments

LIST_SEEDS = (8, 9, 10, 11, 12)  # measure_people draws the report part's lists with seed 8
LINES_EVERY = {"fillets-cs": 3, "fillets-nl": 6}  # about 160 lines of each language


def judged(text: str, path: Path) -> tuple[Utterance, RecordingFit, RecordingFit | None] | None:
    """The take fitted to the text as the shipped network and the people's hear it, as the judgement
    reads them (None where the first alignment fails before it; the second None where it alone fails)."""
    utterance = build_utterance(text)
    try:
        first, listening = fit_recording(
            utterance, path, get_engine("espeak"), FIRST_ALIGNER, load_network(WEIGHTS_FILE)
        )
    except LipSyncError:
        return None
    try:
        second = fit_again(utterance, listening, FIRST_ALIGNER, load_network(PEOPLE_WEIGHTS_FILE))
    except LipSyncError:
        second = None
    return utterance, first, second


def tune_takes(scratch: Path) -> list[tuple[str, bool, Path, str]]:
    """(set, own text, path, text) of every take judged."""
    takes = [("words", True, r.path, r.turkish) for r in words("tune", people.FOLDER)]
    items = list_items("tune", people.FOLDER)
    lists = [
        take
        for seed in LIST_SEEDS
        for take in people.lists_of_eight(items, np.random.default_rng(seed), RATE)
    ]
    for number, take in enumerate(lists):
        path = write_wav(scratch / f"list{number}.wav", take.samples, RATE)
        takes.append(("lists", True, path, take.text))
        other = next(t for t in lists[number + 1 :] + lists if t.speaker != take.speaker)
        takes.append(("lists", False, path, other.text))
    lines = people.sentence_lines("tune")
    for source, every in LINES_EVERY.items():
        chosen = [r for r in lines if r.source.startswith(source)][::every]
        for index, line in enumerate(chosen):
            takes.append((source, True, line.path, line.turkish))
            takes.append((source, False, line.path, chosen[(index + 1) % len(chosen)].turkish))
    return takes


def cached_judgements(cache: Path) -> list:
    """(set, own text, the judge's arguments) of every take, computed once per pair of weights files."""
    digest = hashlib.sha1(WEIGHTS_FILE.read_bytes() + PEOPLE_WEIGHTS_FILE.read_bytes()).hexdigest()[:12]
    file = cache / f"judgement_fits_{digest}.pickle"
    if file.exists():
        return pickle.loads(file.read_bytes())
    found = []
    with tempfile.TemporaryDirectory() as scratch:
        takes = tune_takes(Path(scratch))
        for number, (name, own, path, text) in enumerate(takes):
            arguments = judged(text, path)
            if arguments is not None:
                found.append((name, own, arguments))
            print(f"  judged {number + 1} of {len(takes)}", end="\r", file=sys.stderr, flush=True)
    cache.mkdir(parents=True, exist_ok=True)
    file.write_bytes(pickle.dumps(found))
    return found


def verdict(arguments: tuple[Utterance, RecordingFit, RecordingFit | None], settings: AlignerSettings) -> str:
    """The aligner's verdict on the take: the hearing it keeps, judged with these settings."""
    utterance, first, second = arguments

    def heard_again():
        return AudioError("not fitted") if second is None else judged_fit(utterance, second, settings)

    kept = kept_hearing(judged_fit(utterance, first, settings), heard_again, settings)
    if isinstance(kept, AudioError):
        return "refused"
    return "warned" if kept.warnings else "clean"


def figures(takes: list, settings: AlignerSettings) -> dict[str, str]:
    """Per set: own text refused / warned, another text caught."""
    results = {}
    for name in dict.fromkeys(name for name, _, _ in takes):
        own, other = Counter(), Counter()
        for set_name, is_own, arguments in takes:
            if set_name == name:
                (own if is_own else other)[verdict(arguments, settings)] += 1
        text = f"refused {own['refused']}, warned {own['warned']} of {own.total()}"
        if other.total():
            caught = other["refused"] + other["warned"]
            text += f"; other caught {100 * caught / other.total():.0f} % ({other['refused']} refused)"
        results[name] = text
    return results


def spread(takes: list) -> None:
    """The take mismatch and order ratio of own and other texts, per set."""
    for name in dict.fromkeys(name for name, _, _ in takes):
        for is_own in (True, False):
            fits = [
                (take_mismatch(arguments[1].fit), arguments[1].fit.order_ratio)
                for set_name, own, arguments in takes
                if set_name == name and own == is_own
            ]
            if fits:
                mismatch, order = (
                    "/".join(f"{value:.2f}" for value in np.percentile(column, (5, 50, 95)))
                    for column in np.array(fits).T
                )
                label = "own" if is_own else "other"
                print(f"  {name} {label} ({len(fits)}): mismatch p5/50/95 {mismatch}, order ratio {order}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cache", type=Path, default=TUNING_CACHE)
    parser.add_argument("--set", action="append", default=[], help="NAME=VALUE: the baseline")
    parser.add_argument("--try", dest="tries", action="append", default=[], help="NAME=V1,V2,...")
    arguments = parser.parse_args(argv)
    takes = cached_judgements(arguments.cache)
    print(f"{len(takes)} takes judged (weights {WEIGHTS_FILE.name}, {PEOPLE_WEIGHTS_FILE.name})")
    spread(takes)
    for label, settings in settings_tried(DEFAULT_ALIGNER, arguments.set, arguments.tries):
        print(label)
        for name, text in figures(takes, settings).items():
            print(f"  {name}: {text}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
