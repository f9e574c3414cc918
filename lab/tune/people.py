"""The audio-only recogniser's constants tried on people's recordings: the **tune** part only.

    python -m lab.tune.people [--sentences N] [--set NAME=VALUE ...] [--try NAME=V1,V2,...]

Both hearings' posteriors (and the text-aligned mouth of each sentence, the reference) are computed once
per weights file and kept in a cache folder (--cache); each setting then re-runs only the decoder and the
recogniser's rules, so a sweep over constants takes seconds per setting. What is measured is what
lab/measure/people.py measures (syllables: the vowel heard in its class, a b/m/p heard before it;
sentences: the mouth's opening r against the text-aligned mouth, the aligned b/m/p heard), but on the
tune part (klettres-ru and klettres-tn syllables, the Czech and Dutch lines of the tuning levels): the
report part stays for reporting. A syllable counts where the recogniser hears any letter (whether the
take holds speech at all is the speech detector's decision, not measured here).

NAME is a setting of recognition/settings.py's RecogniserSettings (e.g. prior_weight, bilabial_sure);
each --try varies one setting from the --set baseline.
"""

from __future__ import annotations

import argparse
import pickle
import sys
from pathlib import Path

import numpy as np

from lab.kit import people
from lab.kit.scores import bilabial_scores, correlation, opening_trajectory
from lab.kit.sweep import settings_tried
from lab.measure.people import BILABIALS, VOWEL_CLASSES
from lab.measure.recogniser import TUNING_CACHE, weights_digest
from turkish_lipsync.core.base.errors import LipSyncError
from turkish_lipsync.core.base.visemes import BILABIAL_VISEMES
from turkish_lipsync.core.speech import synthesize_timeline
from turkish_lipsync.core.speech.audio import MAX_OUTPUT_RATE, read_audio, resample, resampled_pcm
from turkish_lipsync.core.speech.features import ANALYSIS_RATE
from turkish_lipsync.core.speech.recognition import recogniser
from turkish_lipsync.core.speech.recognition.settings import DEFAULT_RECOGNISER, RecogniserSettings
from turkish_lipsync.core.speech.recognition.transcript import heard_timeline, heard_utterance
from turkish_lipsync.core.text.utterance import build_utterance


def heard_posteriors(path: Path) -> tuple[tuple[np.ndarray, np.ndarray], float]:
    """Both hearings' log posteriors of a recording (recogniser.hearings), read as speech_from_audio
    reads it, and its length."""
    native, native_rate = read_audio(path)
    output_rate = min(native_rate, MAX_OUTPUT_RATE)
    output = resampled_pcm(native, native_rate, output_rate)
    samples = resample(output, output_rate, ANALYSIS_RATE, 1 / 32768)
    return recogniser.hearings(samples), output.size / output_rate


def cached_takes(part: str, sentences_every: int, cache: Path) -> tuple[list, list]:
    """(syllables, sentences): per recording its posteriors and length (and the reference)."""
    digest = weights_digest()
    file = cache / f"people_{part}_{digest}_{sentences_every}.pickle"
    if file.exists():
        return pickle.loads(file.read_bytes())
    syllables, sentences = [], []
    for recording in people.recordings(people.FOLDER, part, "syllable"):
        posteriors, duration = heard_posteriors(recording.path)
        syllables.append((recording, posteriors, duration))
    lines = people.sentence_lines(part)
    for source in ("fillets-cs", "fillets-nl"):
        for recording in [r for r in lines if r.source.startswith(source)][::sentences_every]:
            try:
                aligned = synthesize_timeline(build_utterance(recording.turkish), recording=recording.path)
            except LipSyncError:
                continue
            posteriors, duration = heard_posteriors(recording.path)
            sentences.append((recording, posteriors, duration, aligned.timeline))
            print(f"  cached {len(sentences)} sentences", end="\r", file=sys.stderr, flush=True)
    cache.mkdir(parents=True, exist_ok=True)
    file.write_bytes(pickle.dumps((syllables, sentences)))
    return syllables, sentences


def heard(posteriors: tuple[np.ndarray, np.ndarray], duration: float, settings: RecogniserSettings):
    """The timeline the recogniser makes of both hearings' posteriors (None where it hears no letter) and
    its confidence (what the low-confidence warning compares with doubtful_confidence)."""
    recognition = recogniser.recognise_posteriors(*posteriors, settings)
    if not recognition.phrases:
        return None, recognition.confidence
    timeline = heard_timeline(heard_utterance(recognition), recognition, duration, settings)
    return timeline, recognition.confidence


def syllable_figures(syllables: list, settings: RecogniserSettings) -> dict:
    vowel_right = with_timeline = bilabial_heard = bilabial_total = stray_heard = stray_total = 0
    confidences = []
    for recording, posteriors, duration in syllables:
        timeline, confidence = heard(posteriors, duration, settings)
        confidences.append(confidence)
        if timeline is None:
            continue
        with_timeline += 1
        spelt_vowels = [letter for letter in recording.turkish if letter in VOWEL_CLASSES]
        heard_vowels = [p for p in timeline.phones if p.letter in VOWEL_CLASSES]
        longest = max(heard_vowels, key=lambda p: p.end - p.start) if heard_vowels else None
        if spelt_vowels and longest is not None:
            vowel_right += VOWEL_CLASSES[longest.letter] == VOWEL_CLASSES[spelt_vowels[0]]
        found = any(
            p.letter in BILABIALS for p in timeline.phones if longest is None or p.start < longest.start
        )
        starts_bilabial = recording.turkish[0] in BILABIALS
        bilabial_total += starts_bilabial
        stray_total += not starts_bilabial
        bilabial_heard += found and starts_bilabial
        stray_heard += found and not starts_bilabial
    return {
        "timeline": f"{with_timeline}/{len(syllables)}",
        "vowel": vowel_right / max(with_timeline, 1),
        "bmp": bilabial_heard / max(bilabial_total, 1),
        "stray": stray_heard / max(stray_total, 1),
        "warned": f"{sum(c < settings.doubtful_confidence for c in confidences)}/{len(confidences)}",
        "confidence p10/p50/p90": "/".join(
            f"{value:.2f}" for value in np.percentile(confidences, [10, 50, 90])
        ),
    }


def sentence_figures(sentences: list, settings: RecogniserSettings) -> dict:
    figures = {}
    for source in ("fillets-cs", "fillets-nl"):
        openings, closed, bilabials, vowels_closed, vowels, wrong, confidences = [], 0, 0, 0, 0, 0, []
        for recording, posteriors, duration, aligned in sentences:
            if not recording.source.startswith(source):
                continue
            found, confidence = heard(posteriors, duration, settings)
            confidences.append(confidence)
            if found is None:
                openings.append(0.0)
                continue
            length = max(aligned.duration, found.duration)
            openings.append(
                correlation(opening_trajectory(found, length), opening_trajectory(aligned, length))
            )
            scores = bilabial_scores(aligned, found, 0.0)
            wrong += wrong_closures(aligned, found)
            closed, bilabials = closed + scores[0], bilabials + scores[1]
            vowels_closed, vowels = vowels_closed + scores[2], vowels + scores[3]
        short = source.split("-")[1]
        figures[f"r {short}"] = float(np.median(openings))
        figures[f"bmp {short}"] = closed / max(bilabials, 1)
        figures[f"vowels closed {short}"] = vowels_closed / max(vowels, 1)
        figures[f"wrong closures {short}"] = wrong / max(bilabials, 1)
        figures[f"warned {short}"] = (
            f"{sum(c < settings.doubtful_confidence for c in confidences)}/{len(confidences)}"
        )
    return figures


def wrong_closures(aligned, found) -> int:
    """The heard closures (b, m, p visemes) that no aligned b, m or p overlaps (within 20 ms)."""
    truth = np.array([(p.start, p.end) for p in aligned.phones if p.viseme in BILABIAL_VISEMES]).reshape(
        -1, 2
    )
    wrong = 0
    for phone in found.phones:
        if phone.viseme in BILABIAL_VISEMES:
            wrong += not np.any((truth[:, 0] < phone.end + 0.02) & (truth[:, 1] > phone.start - 0.02))
    return wrong


def show(label: str, syllables: list, sentences: list, settings: RecogniserSettings) -> None:
    figures = syllable_figures(syllables, settings) | sentence_figures(sentences, settings)
    text = ", ".join(
        f"{name} {value:.3f}" if isinstance(value, float) else f"{name} {value}"
        for name, value in figures.items()
    )
    print(f"{label}: {text}", flush=True)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sentences", type=int, default=5, help="every Nth sentence of the tune part")
    parser.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE", help="the baseline's constants")
    parser.add_argument(
        "--try", dest="tries", nargs="*", default=[], metavar="NAME=V1,V2", help="one at a time"
    )
    parser.add_argument("--part", choices=("tune", "report"), default="tune", help=argparse.SUPPRESS)
    parser.add_argument("--cache", type=Path, default=TUNING_CACHE)
    arguments = parser.parse_args(argv)
    syllables, sentences = cached_takes(arguments.part, arguments.sentences, arguments.cache)
    for label, settings in settings_tried(DEFAULT_RECOGNISER, arguments.set, arguments.tries):
        show(label, syllables, sentences, settings)
    return 0


if __name__ == "__main__":
    sys.exit(main())
