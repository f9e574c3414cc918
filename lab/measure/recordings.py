"""How well a recording in another voice is aligned to its text: word and letter onset error per condition.

    python -m lab.measure.recordings [--set held-out|tuning] [--voices NAME ...] [--conditions NAME ...]
                                         [--mismatch] [--edits] [--aeneas] [--person] [--held-out-voices]
    python -m lab.measure.recordings --long MINUTES [--runs N] [--aeneas]   # one long take

Stand-ins for other speakers are eSpeak NG's Turkish voice with other variants (timbre), pitches and
rates; each is spoken, then turned into a take (lab/kit/takes.py): room noise at an SNR, noise or a
breath and a click before the first word, leading silence, MP3/AAC coding, a synthetic room, and what
a person does: tempo changing inside the sentence, hesitations where no comma is (silent, or said aloud:
the voice's own "ııı" or "eee"), another vocal tract, a talker in the background; each alone and all
together ("a person", its hesitations silent). The take is written as a
44.1 kHz WAV and aligned to the text like a user's recording. The truth is the variant's own phone
events, moved with the take. The sentences come from examples/corpus_tr.txt: the tuning set is lines
1-30, the held-out set lines 31-50; the voices tuned on are DEFAULT_VOICES, the others are held out.

Prints median, p90 and max onset error (ms) of words and of letters per condition, the sentences in
which a word was keyed more than 50 ms early or inside the next word's span, the takes refused (an
error, though they read the text) and warned, and with --mismatch how many takes were refused, or
accepted with a warning, when aligned to the next sentence instead (another text): the rest are missed
mismatches. With --edits, each take is also made leaving out one word and adding one (EXTRA_WORDS),
and the script counts those whose warnings name the word left out, or a neighbour of the word added.
With --long, a take of that many minutes (the held-out sentences over and over, voice
f3-high, 30 dB SNR) is made by a child process, then aligned here (--runs times, aeneas after each of
ours with --aeneas): the median time, the peak resident memory of this process and the word onset error
are printed.

With --aeneas, the same takes are also aligned by aeneas (TTS + MFCC DTW, eSpeak NG's Turkish voice,
its default settings, one word a fragment) and its word onset error and time are printed beside ours.
aeneas is never a dependency of the project: it is looked for in a venv of its own, AENEAS_PYTHON
(default /work/venvs/aeneas/bin/python), and run as a subprocess. To make that venv (Debian: apt-get
install espeak-ng libespeak-ng-dev ffmpeg), build aeneas-ng 1.7.4 without its Festival extension (its
setup.py builds it on every non-Windows system, with no switch, and Festival's libraries are not here):

    python3 -m venv /work/venvs/aeneas && /work/venvs/aeneas/bin/pip install numpy setuptools wheel
    /work/venvs/aeneas/bin/pip download --no-deps --no-binary aeneas-ng -d /tmp aeneas-ng
    tar xzf /tmp/aeneas_ng-1.7.4.0.tar.gz -C /tmp && cd /tmp/aeneas_ng-1.7.4.0
    sed -i 's/^    EXTENSIONS.append(EXTENSION_CFW)/    pass/' setup.py
    AENEAS_WITH_CEW=True AENEAS_USE_ESPEAKNG=True /work/venvs/aeneas/bin/pip install .
    /work/venvs/aeneas/bin/python -m aeneas.diagnostics   # cdtw, cmfcc and cew AVAILABLE

Not a test: the figures go into docs/developer/measured/timing-and-recordings.md.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from lab import REPOSITORY
from lab.kit import takes
from lab.kit.corpus import held_out_sentences, tuning_sentences
from lab.kit.takes import CONDITIONS, PERSON_CONDITIONS, RATE, write_wav
from lab.kit.voices import DEFAULT_VOICES, HELD_OUT_VOICES, TALKER, VOICES, hesitations, speak_take
from turkish_lipsync.core.base.errors import AudioError, LipSyncError
from turkish_lipsync.core.speech import synthesize_timeline
from turkish_lipsync.core.text.utterance import build_utterance

AENEAS_PYTHON = Path(os.environ.get("AENEAS_PYTHON", "/work/venvs/aeneas/bin/python"))


def sentences(which: str) -> list[str]:
    return tuning_sentences() if which == "tuning" else held_out_sentences()


# Run inside aeneas' own venv: aligns a WAV to one word a line, prints the onsets and the seconds it took.
AENEAS_RUNNER = """
import json, sys, time
from aeneas.executetask import ExecuteTask
from aeneas.task import Task
audio, text = sys.argv[1:3]
began = time.perf_counter()
task = Task(config_string="task_language=tur|is_text_type=plain|os_task_file_format=json")
task.audio_file_path_absolute, task.text_file_path_absolute = audio, text
ExecuteTask(task).execute()
onsets = [float(fragment.begin) for fragment in task.sync_map_leaves() if fragment.is_regular]
print(json.dumps({"onsets": onsets, "seconds": time.perf_counter() - began}))
"""


def aeneas_onsets(audio: Path, words: list[str]) -> tuple[np.ndarray, float]:
    """aeneas' word onsets for the take and the seconds its alignment took (its start-up not counted)."""
    text = audio.with_suffix(".words.txt")
    text.write_text("\n".join(words) + "\n", encoding="utf-8")
    done = subprocess.run(
        [str(AENEAS_PYTHON), "-c", AENEAS_RUNNER, str(audio), str(text)],
        capture_output=True,
        text=True,
        check=True,
        env={**os.environ, "PYTHONIOENCODING": "UTF-8"},
    )
    answer = json.loads(done.stdout.strip().splitlines()[-1])
    return np.array(answer["onsets"]), float(answer["seconds"])


def _spread(errors: list[np.ndarray]) -> str:
    ms = 1000 * np.concatenate(errors)
    return f"{np.median(ms):>10.0f}{np.percentile(ms, 90):>7.0f}{ms.max():>7.0f}"


EXTRA_WORDS = ("büyük", "gerçekten", "sonra", "belki")  # said in a take though the text lacks them


def edited_takes(text: str, voice: str, condition: str, rng, context, folder: Path) -> tuple[int, int]:
    """Whether a take leaving out one word, and one adding a word, are each warned about by name.

    Returns (1 if the left-out word is named, 1 if a warning names a neighbour of the added word).
    """
    words = text.split()
    index = int(rng.integers(1, len(words) - 1))
    named = []
    for spoken, names in (
        (words[:index] + words[index + 1 :], {index}),
        (words[:index] + [EXTRA_WORDS[index % len(EXTRA_WORDS)]] + words[index:], {index - 1, index}),
    ):
        take = CONDITIONS[condition](speak_take(" ".join(spoken), VOICES[voice]), rng, context)
        path = write_wav(folder / "edited.wav", take.samples, RATE)
        utterance = build_utterance(text)
        texts = {repr(utterance.words[n].text) for n in names}
        try:
            warnings = synthesize_timeline(utterance, recording=path).warnings
        except AudioError:
            warnings = ()
        named.append(int(any(name in warning for warning in warnings for name in texts)))
    return named[0], named[1]


def measure(texts, voices, conditions, folder: Path, mismatch: bool, aeneas: bool, edits: bool) -> None:
    print(f"{len(texts)} sentences x {len(voices)} voices ({', '.join(voices)}); onset error in ms")
    print(
        f"{'condition':<32}{'words':>24}{'letters':>24}  misplaced refused warned"
        + ("  another text: refused / warned" if mismatch else "")
        + (f"{'aeneas words':>26}" if aeneas else "")
    )
    print(f"{'':<32}{'median    p90    max':>24}{'median    p90    max':>24}")
    spoken = {(text, name): speak_take(text, VOICES[name]) for text in texts for name in voices}
    other_set = sentences("tuning" if texts[0] in sentences("held-out") else "held-out")
    context = {"talker": speak_take(" ".join(other_set[:3]), TALKER).samples}
    sounds = {name: hesitations(VOICES[name]) for name in voices}
    for condition in conditions:
        word_errors, letter_errors, aeneas_errors = [], [], []
        misplaced = refused = warned = other_refused = other_warned = left_named = extra_named = 0
        ours_seconds = aeneas_seconds = 0.0
        rng = np.random.default_rng(11)
        for (text, voice), clean in spoken.items():
            context["hesitations"] = sounds[voice]
            if edits:
                left, extra = edited_takes(text, voice, condition, rng, context, folder)
                left_named, extra_named = left_named + left, extra_named + extra
            take = CONDITIONS[condition](clean, rng, context)
            path = write_wav(folder / "take.wav", take.samples, RATE)
            if mismatch:
                other = texts[(texts.index(text) + 1) % len(texts)]
                try:
                    other_warned += bool(synthesize_timeline(build_utterance(other), recording=path).warnings)
                except AudioError:
                    other_refused += 1
            began = time.perf_counter()
            try:
                speech = synthesize_timeline(build_utterance(text), recording=path)
            except LipSyncError as error:
                refused += 1
                print(f"  refused: {text[:40]!r}: {error}")
                continue
            ours_seconds += time.perf_counter() - began
            timeline = speech.timeline
            if speech.warnings:
                warned += 1
                print(f"  warned: {text[:40]!r}: {' / '.join(speech.warnings)}")
            found = np.array([word.start for word in timeline.words])
            word_errors.append(np.abs(found - take.words))
            letter_errors.append(np.abs(np.array([p.start for p in timeline.phones]) - take.letters))
            bounds = np.append(take.words, np.inf)
            misplaced += int(np.any((found < bounds[:-1] - 0.05) | (found >= bounds[1:])))
            if aeneas:
                onsets, seconds = aeneas_onsets(path, [word.text for word in timeline.words])
                aeneas_errors.append(np.abs(onsets - take.words))
                aeneas_seconds += seconds
        if not word_errors:
            print(f"{condition:<32} every take refused")
            continue
        row = f"{condition:<32}{_spread(word_errors)}{_spread(letter_errors)}"
        row += f"{misplaced:>11}{refused:>8}{warned:>7}"
        row += f"{other_refused:>10} / {other_warned} of {len(spoken)}" if mismatch else ""
        row += f"    {_spread(aeneas_errors)}" if aeneas else ""
        timing = f"  (ours {ours_seconds:.1f} s" + (f", aeneas {aeneas_seconds:.1f} s)" if aeneas else ")")
        print(row + timing, flush=True)
        if edits:
            print(
                f"{'':<32}a word left out named in {left_named}, one added in {extra_named} of {len(spoken)}"
            )


def write_long_take(path: Path, minutes: float) -> None:
    """The held-out sentences repeated for `minutes` in voice f3-high at 30 dB SNR; the truth beside it."""
    texts = sentences("held-out")
    one_pass = speak_take(" ".join(texts), VOICES["f3-high"]).samples.size / RATE
    text = " ".join(texts * max(1, round(minutes * 60 / one_pass)))
    take = takes.padded(speak_take(text, VOICES["f3-high"]), 1.0, 1.0)
    write_wav(path, takes.add_noise(take, 30, "white", np.random.default_rng(3)).samples, RATE)
    np.save(path.with_suffix(".npy"), take.words)
    path.with_suffix(".txt").write_text(text, encoding="utf-8")


def measure_long_take(minutes: float, folder: Path, aeneas: bool, runs: int) -> None:
    """Align the long take `runs` times (and aeneas after each when asked): the median times, the errors."""
    path = folder / "long.wav"
    subprocess.run(
        [sys.executable, "-m", __spec__.name, "--write-long", str(path), str(minutes)],
        check=True,
        cwd=REPOSITORY,
    )
    text = path.with_suffix(".txt").read_text(encoding="utf-8")
    truth = np.load(path.with_suffix(".npy"))
    ours, theirs = [], []
    for _ in range(runs):
        began = time.perf_counter()
        speech = synthesize_timeline(build_utterance(text), recording=path)
        ours.append(time.perf_counter() - began)
        if aeneas:
            onsets, seconds = aeneas_onsets(path, [word.text for word in speech.timeline.words])
            theirs.append(seconds)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # kB on Linux
    ms = 1000 * np.abs(np.array([word.start for word in speech.timeline.words]) - truth)
    print(
        f"take of {speech.synthesis.duration / 60:.1f} min, {len(text):,} characters, {truth.size:,} words: "
        f"aligned in {np.median(ours):.2f} s (median of {runs}: {', '.join(f'{t:.2f}' for t in ours)}), peak "
        f"resident memory {peak:.0f} MB; word onsets median {np.median(ms):.0f} ms, p90 "
        f"{np.percentile(ms, 90):.0f} ms, max {ms.max():.0f} ms; {len(speech.warnings)} warnings"
    )
    if aeneas:
        ms = 1000 * np.abs(onsets - truth)
        print(
            f"aeneas: aligned in {np.median(theirs):.2f} s (median of {runs}: "
            f"{', '.join(f'{t:.2f}' for t in theirs)}); word onsets median {np.median(ms):.0f} ms, "
            f"p90 {np.percentile(ms, 90):.0f} ms, max {ms.max():.0f} ms"
        )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--set", choices=("held-out", "tuning"), default="held-out")
    parser.add_argument("--voices", nargs="+", choices=sorted(VOICES), default=list(DEFAULT_VOICES))
    parser.add_argument("--held-out-voices", action="store_true", help="the voices not tuned on")
    parser.add_argument("--conditions", nargs="+", choices=list(CONDITIONS), default=list(CONDITIONS))
    parser.add_argument(
        "--person", action="store_true", help="only a person's conditions, alone and together"
    )
    parser.add_argument("--sentences", type=int, default=0, help="use only the first N sentences")
    parser.add_argument("--mismatch", action="store_true", help="also align each take to the next sentence")
    parser.add_argument("--edits", action="store_true", help="also takes leaving out or adding a word")
    parser.add_argument("--aeneas", action="store_true", help=f"also align with aeneas ({AENEAS_PYTHON})")
    parser.add_argument("--long", type=float, metavar="MINUTES", help="measure one take this long instead")
    parser.add_argument("--runs", type=int, default=1, help="with --long: align it this many times")
    parser.add_argument("--write-long", nargs=2, metavar=("PATH", "MINUTES"), help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.write_long:
        write_long_take(Path(args.write_long[0]), float(args.write_long[1]))
        return 0
    if args.aeneas and not AENEAS_PYTHON.exists():
        parser.error(f"aeneas is not installed at {AENEAS_PYTHON}; see this script's docstring")
    texts = sentences(args.set)[: args.sentences or None]
    voices = list(HELD_OUT_VOICES) if args.held_out_voices else args.voices
    conditions = PERSON_CONDITIONS if args.person else args.conditions
    with tempfile.TemporaryDirectory() as folder:
        if args.long:
            measure_long_take(args.long, Path(folder), args.aeneas, args.runs)
        else:
            measure(texts, voices, conditions, Path(folder), args.mismatch, args.aeneas, args.edits)
    return 0


if __name__ == "__main__":
    sys.exit(main())
