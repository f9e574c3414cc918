"""How well lip sync from the audio alone follows the mouth, on voices and noise the recogniser never heard.

    python -m lab.measure.recogniser [--voices NAME ...] [--conditions NAME ...] [--sentences N]
    python -m lab.measure.recogniser --speed MINUTES [--people]  # one long take: x real time, memory
    python -m lab.measure.recogniser --bad               # silence, noise, music, other languages
    python -m lab.measure.recogniser --tune [--conditions NAME ...] [--set NAME=VALUE ...] [--try ...]

The takes: the held-out sentences of examples/corpus_tr.txt (lines 31-50, never in training) spoken by
eSpeak NG variants the network was not trained on (the weights' own list of held-out variants, checked
here), each at its own pitch and rate, degraded as in lab/measure/recordings.py (room noise, noise
and a breath before the first word, reverberation, MP3) and written as 44.1 kHz WAVs.

The measure: each phone's viseme mapped to an opening 0..1 (the reference head's lip aperture at the
midline under that viseme, over the a's), on a 10 ms grid, smoothed over 60 ms; the Pearson correlation
of that trajectory with the truth's (the variant's own phone events) per take, median per condition and
overall. Beside it, the loudness envelope of the take (its smoothed amplitude) as the baseline and the
recording aligned to its text (the text-aligned path) as the ceiling. Bilabials closed: the truth's b,
m, p that a recognised b, m or p overlaps (within 20 ms); closures on vowels: the truth's vowels whose
middle falls inside a recognised b, m or p. Not a test: the figures go into
docs/developer/measured/audio-alone.md.
"""

from __future__ import annotations

import argparse
import hashlib
import pickle
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from lab import REPOSITORY
from lab.kit import people
from lab.kit.corpus import held_out_sentences, tuning_sentences
from lab.kit.scores import bilabial_scores, correlation, loudness_envelope, opening_trajectory
from lab.kit.sweep import settings_tried
from lab.kit.takes import write_wav
from lab.kit.voices import (
    DIPHONE_VOICES,
    OTHER_LANGUAGES,
    RECORDED_RATE,
    TEST_VOICES,
    make_take,
    speak_language,
)
from lab.kit.voices import speak_variant as speak
from lab.measure.recordings import takes
from turkish_lipsync.core.base.errors import AudioError
from turkish_lipsync.core.speech import synthesize_timeline
from turkish_lipsync.core.speech.acoustic.network import load_network
from turkish_lipsync.core.speech.recognition import speech_from_audio
from turkish_lipsync.core.text.utterance import build_utterance

# Held out of training too, but never in the measure: the decoder's constants are tuned on these voices,
# reading the tuning sentences (lines 1-30).
TUNING_VOICES = {"iven2": ("iven2", 5, 15), "grandpa": ("grandpa", -10, -15)}
# The decoder's constants (recognition/decoder.py) and the other values --tune tries, one at a time.
TUNED = {
    "prior_weight": (0.5, 1.0),
    "language_weight": (0.0, 1.0),
    "insertion_cost": (0.0, 3.0),
    "duration_scale": (0.4, 1.0),
}
TUNING_CACHE = Path(tempfile.gettempdir()) / "recogniser_tuning"  # the tuning takes' posteriors
TEST_CONDITIONS = (
    "clean 60 dB",
    "30 dB, leading noise",
    "30 dB pink, leading noise",
    "30 dB brown, breath + click",
    "reverb RT60 0.4 s, 40 dB",
    "MP3 64k, 40 dB",
)


def measure_take(text, voice, condition, folder, rng, ceiling: bool = True) -> dict:
    path, truth, lead, samples = make_take(text, voice, condition, folder, rng)
    duration = samples.size / RECORDED_RATE
    truth_track = opening_trajectory(truth, duration, lead)
    _, speech = speech_from_audio(path)
    found = speech.timeline
    closed, bilabials, vowels_closed, vowels = bilabial_scores(truth, found, lead)
    result = {
        "recognised": correlation(truth_track, opening_trajectory(found, duration)),
        "loudness": correlation(truth_track, loudness_envelope(samples, RECORDED_RATE, truth_track.size)),
        "closed": closed,
        "bilabials": bilabials,
        "vowels_closed": vowels_closed,
        "vowels": vowels,
        "warned": bool(speech.warnings),
    }
    if ceiling:
        try:
            aligned = synthesize_timeline(build_utterance(text), recording=path).timeline
            result["aligned"] = correlation(truth_track, opening_trajectory(aligned, duration))
        except AudioError:  # the aligner took the take for another text: the ceiling has a gap there
            result["aligned"] = float("nan")
    return result


def check_held_out(voices: list[str]) -> None:
    held_out = set(load_network().metadata["held_out_variants"])
    trained = set(load_network().metadata["training_variants"])
    for name in voices:
        if name in DIPHONE_VOICES:
            continue
        variant = TEST_VOICES[name][0]
        if variant not in held_out or variant in trained:
            raise SystemExit(f"{variant} was used in training: it cannot measure held-out voices")


def measure(texts: list[str], voices: list[str], conditions: list[str], folder: Path) -> None:
    check_held_out(voices)
    print(f"{len(texts)} held-out sentences x {len(voices)} held-out voices ({', '.join(voices)})")
    print(
        f"{'condition':<30}{'recognised r':>13}{'loudness r':>11}{'aligned r':>10}{'bilabials closed':>18}"
        f"{'vowels closed':>14}{'warned':>8}"
    )
    everything = []
    for condition in conditions:
        rng = np.random.default_rng(5)
        results = [
            measure_take(text, (TEST_VOICES | DIPHONE_VOICES)[name], condition, folder, rng)
            for text in texts
            for name in voices
        ]
        everything += results
        print(_row(condition, results), flush=True)
    print(_row("all", everything))


def _row(name: str, results: list[dict]) -> str:
    def median(key):
        return np.nanmedian([result[key] for result in results])

    closed = sum(r["closed"] for r in results) / max(1, sum(r["bilabials"] for r in results))
    vowels = sum(r["vowels_closed"] for r in results) / max(1, sum(r["vowels"] for r in results))
    refused = sum(np.isnan(r["aligned"]) for r in results)
    return (
        f"{name:<30}{median('recognised'):>13.3f}{median('loudness'):>11.3f}{median('aligned'):>10.3f}"
        f"{closed:>17.1%}{vowels:>14.1%}{sum(r['warned'] for r in results):>8}"
        + (f"  (the aligner refused {refused} takes as another text)" if refused else "")
    )


def measure_speed(minutes: float, folder: Path, of_people: bool = False) -> None:
    """long_take's take: seconds, x real time and peak memory."""
    take, _ = long_take(minutes, of_people)
    path = write_wav(folder / "long.wav", take, RECORDED_RATE)
    del take
    # Recognised by a process of its own, so its peak memory is the recogniser's, not the take's making.
    subprocess.run(
        [sys.executable, "-m", __spec__.name, "--recognise", str(path)], check=True, cwd=REPOSITORY
    )


def long_take(minutes: float, of_people: bool = False) -> tuple[np.ndarray, list]:
    """One long take at RECORDED_RATE (30 dB of white noise over it) of held-out sentences (voice m3), or
    of people's voice-acted lines one after the other (the report part's; the recogniser hears these with
    Whisper too), 0.5 s apart; and each line's span in it (start, end in seconds, and the line: a
    people.Recording, or the sentence's text)."""
    if of_people:
        lines = people.sentence_lines("report")

        def said(n: int) -> tuple[np.ndarray, object]:
            return people.read(lines[n % len(lines)], RECORDED_RATE), lines[n % len(lines)]
    else:
        texts = held_out_sentences()

        def said(n: int) -> tuple[np.ndarray, object]:
            text = texts[n % len(texts)]
            return speak(text, *TEST_VOICES["m3"], sample_rate=RECORDED_RATE)[0], text

    rng = np.random.default_rng(3)
    pieces, spans = [], []
    total = 0.0
    while total < minutes * 60:
        samples, line = said(len(pieces))
        spans.append((total, total + samples.size / RECORDED_RATE, line))
        pieces.append(np.concatenate((samples, np.zeros(int(0.5 * RECORDED_RATE)))))
        total += pieces[-1].size / RECORDED_RATE
    reading = takes.Take(np.concatenate(pieces), np.zeros(0), np.zeros(0), np.zeros(0, bool))
    del pieces
    return takes.add_noise(reading, 30, "white", rng).samples, spans


def peak_memory_mb() -> float:
    """This process's peak resident memory (VmHWM: unlike ru_maxrss, not inherited from the parent)."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) / 1024
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def recognise_and_report(path: Path) -> None:
    """Recognise one take (the whole path a user's take goes: lip_sync with the tracks) and report."""
    from turkish_lipsync.core.pipeline import LipSyncOptions, lip_sync

    began = time.perf_counter()
    result = lip_sync("", LipSyncOptions(recording=path))
    elapsed = time.perf_counter() - began
    peak = peak_memory_mb()
    total = result.synthesis.duration
    print(
        f"{total / 60:.1f} min take: lip sync from the audio alone (reading, recognition, timeline, weight "
        f"tracks) in {elapsed:.1f} s ({total / elapsed:.0f} x real time, {elapsed / total * 600:.1f} s per "
        f"10 minutes), {len(result.timeline.phones):,} letters, peak resident memory {peak:.0f} MB"
    )


def measure_bad_input(folder: Path) -> None:
    """Silence, noise, music and other languages: what the user is told."""
    from lab.kit.degradations import coloured_noise, music

    rng = np.random.default_rng(9)
    rate = 16_000
    cases = {
        "silence": np.zeros(5 * rate),
        "white noise": 0.1 * coloured_noise(5 * rate, "white", rng),
        "pink noise": 0.1 * coloured_noise(5 * rate, "pink", rng),
        "babble-like noise": 0.1 * coloured_noise(5 * rate, "babble", rng),
        "music": 0.2 * music(8 * rate, rng),
    }
    for name, samples in cases.items():
        path = write_wav(folder / "bad.wav", samples, rate)
        try:
            _, speech = speech_from_audio(path)
            print(f"{name:<20} accepted: {len(speech.timeline.phones)} letters, warnings {speech.warnings}")
        except AudioError as error:
            print(f"{name:<20} refused: {error}")
    for language in ("en", "de", "fr", "es", "az", "ja"):
        confidences = []
        for text in OTHER_LANGUAGES[language]:
            samples, rate = speak_language(text, language)
            path = write_wav(folder / "other.wav", np.concatenate((np.zeros(rate // 2), samples)), rate)
            try:
                _, speech = speech_from_audio(path)
                confidences.append(bool(speech.warnings))
            except AudioError:
                confidences.append(None)
        print(
            f"language {language}: {sum(c is True for c in confidences)} of {len(confidences)} warned, "
            f"{sum(c is None for c in confidences)} refused"
        )
    warned = 0
    texts = held_out_sentences()
    for text in texts:
        path, *_ = make_take(text, TEST_VOICES["m3"], "30 dB, leading noise", folder, rng)
        warned += bool(speech_from_audio(path)[1].warnings)
    print(f"Turkish (held-out voice m3, 30 dB): {warned} of {len(texts)} warned")


def weights_digest() -> str:
    """What cached posteriors were heard with: both hearings' weights."""
    from turkish_lipsync.core.speech.acoustic.network import WEIGHTS_FILE
    from turkish_lipsync.core.speech.acoustic.whisper import WEIGHTS_FILE as WHISPER_WEIGHTS_FILE

    return hashlib.sha1(WEIGHTS_FILE.read_bytes() + WHISPER_WEIGHTS_FILE.read_bytes()).hexdigest()[:12]


def tuning_takes(folder: Path, conditions: tuple[str, ...] = TEST_CONDITIONS) -> list[tuple]:
    """The tuning voices reading the tuning sentences, each in a condition drawn from `conditions`: per
    take its posteriors, truth, lead and length (kept in TUNING_CACHE per weights file and conditions)."""
    from turkish_lipsync.core.speech.audio import read_audio, resample
    from turkish_lipsync.core.speech.recognition import recogniser

    drawn = (
        ""
        if conditions == TEST_CONDITIONS
        else "_" + hashlib.sha1("|".join(conditions).encode()).hexdigest()[:8]
    )
    cached = TUNING_CACHE / f"synthetic_{weights_digest()}{drawn}.pickle"
    if cached.exists():
        return pickle.loads(cached.read_bytes())
    rng = np.random.default_rng(21)
    takes = []
    for text in tuning_sentences():
        for voice in TUNING_VOICES.values():
            condition = conditions[int(rng.integers(len(conditions)))]
            path, truth, lead, samples = make_take(text, voice, condition, folder, rng)
            native, rate = read_audio(path)
            duration = samples.size / RECORDED_RATE
            takes.append((recogniser.hearings(resample(native, rate, 16_000)), truth, lead, duration))
    TUNING_CACHE.mkdir(parents=True, exist_ok=True)
    cached.write_bytes(pickle.dumps(takes))
    return takes


def tune(folder: Path, baseline: list[str], tries: list[str], conditions: tuple[str, ...]) -> None:
    """The recogniser's constants on the tuning voices and sentences (each take in one of `conditions`):
    r and bilabials closed per setting."""
    from turkish_lipsync.core.speech.recognition import recogniser
    from turkish_lipsync.core.speech.recognition.settings import DEFAULT_RECOGNISER
    from turkish_lipsync.core.speech.recognition.transcript import heard_timeline, heard_utterance

    takes = tuning_takes(folder, conditions)
    for label, settings in settings_tried(DEFAULT_RECOGNISER, baseline, tries, TUNED):
        rs, closed, total, vowels_closed, vowels, confidences = [], 0, 0, 0, 0, []
        for posteriors, truth, lead, duration in takes:
            recognition = recogniser.recognise_posteriors(*posteriors, settings)
            confidences.append(recognition.confidence)
            timeline = heard_timeline(heard_utterance(recognition), recognition, duration, settings)
            rs.append(
                correlation(opening_trajectory(truth, duration, lead), opening_trajectory(timeline, duration))
            )
            scores = bilabial_scores(truth, timeline, lead)
            closed, total = closed + scores[0], total + scores[1]
            vowels_closed, vowels = vowels_closed + scores[2], vowels + scores[3]
        print(
            f"{label}: r median {np.median(rs):.3f}, "
            f"bilabials closed {closed / total:.1%}, "
            f"vowels closed {vowels_closed / vowels:.1%}, "
            f"warned {sum(c < settings.doubtful_confidence for c in confidences)} of {len(confidences)} "
            f"(confidence p10 / p50 {np.percentile(confidences, 10):.2f} / {np.median(confidences):.2f})",
            flush=True,
        )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--voices", nargs="+", choices=sorted(TEST_VOICES | DIPHONE_VOICES), default=list(TEST_VOICES)
    )
    parser.add_argument("--conditions", nargs="+", choices=TEST_CONDITIONS, default=list(TEST_CONDITIONS))
    parser.add_argument("--sentences", type=int, default=0, help="use only the first N sentences")
    parser.add_argument("--speed", type=float, metavar="MINUTES", help="time one take this long instead")
    parser.add_argument("--people", action="store_true", help="--speed: of people's lines, not eSpeak NG's")
    parser.add_argument("--bad", action="store_true", help="silence, noise, music and other languages")
    parser.add_argument("--tune", action="store_true", help="the recogniser's constants on the tuning voices")
    parser.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE", help="--tune: the baseline")
    parser.add_argument("--try", dest="tries", nargs="*", default=[], metavar="NAME=V1,V2", help="--tune")
    parser.add_argument("--recognise", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.recognise:
        recognise_and_report(args.recognise)
        return 0
    with tempfile.TemporaryDirectory() as folder:
        if args.speed:
            measure_speed(args.speed, Path(folder), args.people)
        elif args.bad:
            measure_bad_input(Path(folder))
        elif args.tune:
            tune(Path(folder), args.set, args.tries, tuple(args.conditions))
        else:
            texts = held_out_sentences()[: args.sentences or None]
            measure(texts, args.voices, args.conditions, Path(folder))
    return 0


if __name__ == "__main__":
    sys.exit(main())
