"""Continuous read speech of held-out speakers, every phone labelled: Festival's Italian and Russian voices.

    python -m lab.measure.read_speech [--sentences 20] [--voices NAME ...] [--espeak] [--seed 41]

Festival's Italian diphone voices (lp and pc: two speakers' recordings cut into diphones) and its
Russian voice (msu_ru_nsh: units of one speaker's recordings) read random sentences of their language's
words (wordfreq, seeded), and Festival writes each segment's time and each word's segments. The truth
is those segments as Turkish letter sounds (inventory/*.toml beside this file); the text given with a
take is each word's segments spelt in those letters (what a Turkish reader could write of what is
said). These voices are never trained or tuned on (lab/train/festival_voices.HELD_OUT). Each take is a
16-bit WAV at the voice's own rate and goes through the public entries a user's recording goes through.

Per voice:
- with the text: refused / warned / clean, and each bilabial run's (b, m, p) onset in the aligned timeline
  against its label (median / p90 / max ms), where the take's runs pair one to one;
- no text: stressed vowels heard in their class (the recognised letter at the vowel's middle: a / e /
  i ı / o ö / u ü), the labels' bilabials a recognised b, m or p overlaps (within 20 ms), the mouth's
  opening against the opening the labels give (Pearson r on a 10 ms grid, smoothed over 60 ms);
- with --espeak: eSpeak NG's voice of the language reading the same sentences, aligned to the same
  spellings: refused / warned (what a synthetic voice of that language draws).

Needs Festival and the voices (Debian festival, festvox-italp16k, festvox-itapc16k, festvox-ru).
Not a test: the figures go into docs/developer/measured/people.md.
"""

from __future__ import annotations

import argparse
import re
import sys
import tempfile
from collections import Counter
from dataclasses import dataclass, field, fields, replace
from pathlib import Path

import numpy as np

from lab.kit import festival_voices
from lab.kit.scores import bilabial_scores, correlation, opening_trajectory
from lab.kit.takes import write_wav
from lab.kit.voices import speak_language
from lab.measure.people import VOWEL_CLASSES, aligned, heard, shares
from turkish_lipsync.core.base.model import Timeline
from turkish_lipsync.core.speech.acoustic.labels import BILABIAL_LETTERS
from turkish_lipsync.core.speech.audio import read_audio
from turkish_lipsync.core.speech.recognition.recogniser import HeardLetter, Recognition
from turkish_lipsync.core.speech.recognition.settings import DEFAULT_RECOGNISER
from turkish_lipsync.core.speech.recognition.transcript import heard_timeline, heard_utterance

INVENTORY = Path(__file__).with_name("inventory")
RUN_GAP = 0.01  # seconds: bilabial phones this close form one run (the m m of "mamma")


@dataclass(frozen=True)
class HeldOutVoice:
    voice: festival_voices.Voice
    stressed: frozenset[str]  # the phones that are stressed vowels
    espeak: str  # eSpeak NG's voice of the language


VOICES = {
    "italian-lp": HeldOutVoice(
        festival_voices.Voice("festvox-italp16k", "voice_lp_diphone", "it", "iso-8859-1", "italian"),
        frozenset({"a1", "e1", "E1", "i1", "o1", "O1", "u1"}),
        "it",
    ),
    "italian-pc": HeldOutVoice(
        festival_voices.Voice("festvox-itapc16k", "voice_pc_diphone", "it", "iso-8859-1", "italian"),
        frozenset({"a1", "e1", "E1", "i1", "o1", "O1", "u1"}),
        "it",
    ),
    "russian-nsh": HeldOutVoice(
        festival_voices.Voice("festvox-ru", "voice_msu_ru_nsh_clunits", "ru", "utf-8", "russian"),
        frozenset({"aa", "ee", "ii", "oo", "uu", "yy"}),
        "ru",
    ),
}


@dataclass(frozen=True)
class Take:
    stem: Path
    text: str  # what the voice read
    spelling: str  # each word's segments in Turkish letters
    letters: tuple[HeardLetter, ...]  # the labels, in order (silence and ignored phones left out)
    stressed: tuple[tuple[float, str], ...]  # each stressed vowel's middle and letter
    duration: float


def takes(name: str, count: int, seed: int, folder: Path) -> list[Take]:
    held_out = VOICES[name]
    rng = np.random.default_rng([seed, sorted(VOICES).index(name)])
    texts = festival_voices.sentences(held_out.voice, count, rng)
    stems = festival_voices.render(held_out.voice, texts, [1.0] * count, folder / name)
    table = festival_voices.inventory(held_out.voice.inventory, INVENTORY)
    out = []
    for stem in stems:
        words = re.findall(r"\(([^()]*)\)", stem.with_suffix(".words").read_text(encoding="utf-8")[1:-1])
        spelt = ["".join("".join(table[p]) for p in re.findall(r'"([^"]+)"', word)) for word in words]
        letters, stressed = [], []
        for start, end, phone in festival_voices.segments(stem.with_suffix(".segs")):
            sounds = [letter for letter in table[phone] if letter != "_"]
            bounds = np.linspace(start, end, len(sounds) + 1)
            letters += [
                HeardLetter(s, float(a), float(b), 1.0)
                for s, a, b in zip(sounds, bounds, bounds[1:], strict=False)
            ]
            if phone in held_out.stressed:
                stressed.append(((start + end) / 2, sounds[0]))
        mono, rate = read_audio(stem.with_suffix(".wav"))
        spelling = " ".join(word for word in spelt if word)
        out.append(
            Take(stem, texts[int(stem.name)], spelling, tuple(letters), tuple(stressed), mono.size / rate)
        )
    return out


def truth_timeline(take: Take) -> Timeline:
    """The labels as the timeline a recogniser hearing them exactly would give (their stops hold their
    closures already)."""
    phrases, phrase = [], []
    for letter in take.letters:
        if phrase and letter.start - phrase[-1].end >= DEFAULT_RECOGNISER.phrase_pause:
            phrases.append(tuple(phrase))
            phrase = []
        phrase.append(letter)
    phrases.append(tuple(phrase))
    recognition = Recognition(tuple(phrases), 1.0)
    return heard_timeline(
        heard_utterance(recognition),
        recognition,
        take.duration,
        replace(DEFAULT_RECOGNISER, closure_share=0.0),
    )


def bilabial_runs(spans: list[tuple[float, float]]) -> list[float]:
    """Onsets of runs of bilabial spans (sorted), a run's spans no more than RUN_GAP apart."""
    onsets, last_end = [], -1.0
    for start, end in spans:
        if start - last_end > RUN_GAP:
            onsets.append(start)
        last_end = end
    return onsets


def letter_class_at(timeline: Timeline, time: float) -> str | None:
    for phone in timeline.phones:
        if phone.start <= time < phone.end:
            return VOWEL_CLASSES.get(phone.letter)
    return None


@dataclass
class Tally:
    """What a voice's takes gave (and, summed, all voices')."""

    with_text: Counter = field(default_factory=Counter)
    alone: Counter = field(default_factory=Counter)
    synthetic: Counter = field(default_factory=Counter)
    errors: list = field(default_factory=list)  # seconds: bilabial runs' onsets against their labels
    unpaired: int = 0
    openings: list = field(default_factory=list)
    closed: int = 0
    bilabials: int = 0
    stressed_right: int = 0
    stressed: int = 0

    def __add__(self, other: Tally) -> Tally:
        return Tally(*(getattr(self, f.name) + getattr(other, f.name) for f in fields(Tally)))


def measure_voice(name: str, chosen: list[Take], espeak: bool, scratch: Path) -> Tally:
    tally = Tally()
    for take in chosen:
        truth = truth_timeline(take)
        timeline, result = aligned(take.spelling, take.stem.with_suffix(".wav"))
        tally.with_text[result] += 1
        if timeline is not None:
            truth_runs = bilabial_runs(
                [(p.start, p.end) for p in truth.phones if p.letter in BILABIAL_LETTERS]
            )
            runs = bilabial_runs([(p.start, p.end) for p in timeline.phones if p.letter in BILABIAL_LETTERS])
            if len(truth_runs) == len(runs):
                tally.errors += [abs(a - b) for a, b in zip(truth_runs, runs, strict=True)]
            else:
                tally.unpaired += 1
        found, result = heard(take.stem.with_suffix(".wav"))
        tally.alone[result] += 1
        if found is not None:
            hits, total, _, _ = bilabial_scores(truth, found, 0.0)
            tally.closed, tally.bilabials = tally.closed + hits, tally.bilabials + total
            for middle, letter in take.stressed:
                tally.stressed += 1
                tally.stressed_right += letter_class_at(found, middle) == VOWEL_CLASSES[letter]
            duration = max(truth.duration, found.duration)
            tally.openings.append(
                correlation(opening_trajectory(found, duration), opening_trajectory(truth, duration))
            )
        if espeak:
            samples, rate = speak_language(take.text, VOICES[name].espeak)
            path = write_wav(scratch / "espeak.wav", samples, rate)
            tally.synthetic[aligned(take.spelling, path)[1]] += 1
    return tally


def report(name: str, tally: Tally, espeak: str | None) -> None:
    count = sum(tally.with_text.values())
    milliseconds = 1000 * np.array(tally.errors or [0.0])
    print(f"{name} ({count} sentences)")
    print(f"  with the text: {shares(tally.with_text, count)}")
    print(
        f"  bilabial runs keyed (ms): median {np.median(milliseconds):.0f}, p90 "
        f"{np.percentile(milliseconds, 90):.0f}, max {milliseconds.max():.0f} ({len(tally.errors)} runs; "
        f"{tally.unpaired} takes whose runs do not pair)"
    )
    print(f"  no text: {shares(tally.alone, count)}")
    print(
        f"  no text: stressed vowels in class {tally.stressed_right} of {tally.stressed} "
        f"({100 * tally.stressed_right / max(tally.stressed, 1):.0f} %); bilabials heard {tally.closed} of "
        f"{tally.bilabials} ({100 * tally.closed / max(tally.bilabials, 1):.0f} %); mouth r median "
        f"{np.median(tally.openings or [np.nan]):.2f}"
    )
    if espeak:
        print(f"  eSpeak NG's voice ({espeak}), the same spellings: {shares(tally.synthetic, count)}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--voices", nargs="+", choices=sorted(VOICES), default=sorted(VOICES))
    parser.add_argument("--sentences", type=int, default=20, help="sentences each voice reads")
    parser.add_argument("--seed", type=int, default=41)
    parser.add_argument("--espeak", action="store_true", help="eSpeak NG's voice of the language too")
    parser.add_argument("--folder", type=Path, default=Path(tempfile.gettempdir()) / "read_speech")
    args = parser.parse_args(argv)
    total = Tally()
    with tempfile.TemporaryDirectory() as scratch:
        for name in args.voices:
            tally = measure_voice(
                name, takes(name, args.sentences, args.seed, args.folder), args.espeak, Path(scratch)
            )
            report(name, tally, VOICES[name].espeak if args.espeak else None)
            total = total + tally
    report("all", total, "it, ru" if args.espeak else None)
    return 0


if __name__ == "__main__":
    sys.exit(main())
