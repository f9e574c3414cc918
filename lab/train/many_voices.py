"""The acoustic model's round on many people: Festival's diphone voices, every phone labelled, and the rest.

    nice -n 10 ~/recogniser-venv/bin/python -m lab.train.many_voices [--voices NAME ...] [--per-voice 400]
        [--copies 2] [--epochs 10] [--start WEIGHTS] [--out WEIGHTS]
        [--teacher WEIGHTS [--teach-people]] [--channels N [--keep-start]] [--klettres]

Writes turkish_lipsync/core/speech/acoustic/people_network.npz (the recording aligner's second hearing)
unless --out says otherwise. Goes on from the weights of lab/train/recogniser.py's last round (--start;
by default the cache's `round_3_SEED.npz`, which lab/train/recogniser.py leaves there: run it first) at
its last round's learning rate and band warp, on:

1. eSpeak NG's clips as that round makes them (levelled as the extension levels them, a third cut to a word
   or two), first: the decoder's letter transitions and shortest durations come from their Turkish texts;
2. lab/kit/people.py's tune part (its Dutch lines and Russian and Tswana syllables), labelled by forced
   alignment with the starting weights, clean and degraded;
3. every voice of festival_voices.VOICES (or --voices): --per-voice random sentences of its language's
   words at random tempos (Festival's Duration_Stretch 0.8-1.35), labelled by Festival's own segments
   mapped to Turkish letter sounds (inventory/*.toml), each clean and degraded --copies - 1 times (another
   vocal tract, rooms, telephone bands, noise, music: lab.kit.degradations.degrade);
4. with --klettres, KLettres' syllables in eight more languages (lab/kit/people.py's train part, from
   lab/kit/klettres_syllables.py), labelled and degraded as the tune part's people are. Measured and not
   shipped: the report part's syllables and lines were heard no better (docs: people's voices).

With --teacher, eSpeak NG's clips learn what that network hears in them (its posteriors) instead of
their labels, so that its hearing of the project's own voice is kept (--teach-people: the tune part's
people's too). With --channels wider than the start's, the start's weights are grown into a wider
network that begins as the start (the new channels unheard); with --keep-start the start's channels
stay as they are and hear only each other, and the grown channels learn what the classes should hear
besides. The shipped people_network.npz is

    ~/recogniser-venv/bin/python -m lab.train.many_voices --clips 10000 --learning-rate 1e-3 --epochs 4 \
        --start turkish_lipsync/core/speech/acoustic/phone_network.npz \
        --teacher turkish_lipsync/core/speech/acoustic/phone_network.npz --channels 160 --keep-start

(about 28 minutes on two cores once the corpora are cached).

Every step seeded (--seed). Corpora are cached (--cache) and not made again.
"""

from __future__ import annotations

import argparse
import multiprocessing
import sys
import time
from pathlib import Path

import numpy as np

from lab.kit import festival_voices, people
from lab.train.recogniser import (
    CHANNELS,
    FINAL_BAND_WARP,
    FINAL_LEARNING_RATE,
    make_corpus,
    make_people_clip,
    make_people_corpus,
    train,
)
from turkish_lipsync.core.speech.acoustic.network import PEOPLE_WEIGHTS_FILE

CACHE = Path.home() / ".cache" / "turkish_lipsync_recogniser"
TEMPO = (0.8, 1.35)  # Festival's Duration_Stretch, drawn per sentence


def festival_corpus(name: str, per_voice: int, copies: int, seed: int, cache: Path) -> Path:
    """One voice's sentences, spoken, labelled and degraded: the features and labels of its clips."""
    path = cache / f"festival_{name}_{per_voice}_{copies}_{seed}.npz"
    if path.exists():
        return path
    voice = festival_voices.VOICES[name]
    rng = np.random.default_rng([seed, sorted(festival_voices.VOICES).index(name)])
    texts = festival_voices.sentences(voice, per_voice, rng)
    stretches = list(rng.uniform(*TEMPO, size=per_voice))
    began = time.time()
    stems = festival_voices.render(voice, texts, stretches, cache / "festival" / f"{name}_{seed}")
    table = festival_voices.inventory(voice.inventory)
    spoken = [festival_voices.labelled(stem, table) for stem in stems]
    jobs = [
        (samples, labels, None if copy == 0 else int(rng.integers(1 << 31)), False)
        for samples, labels in spoken
        for copy in range(copies)
    ]
    if not jobs:
        raise SystemExit(
            f"{name}: Festival spoke none of its {per_voice} sentences; is {voice.package} installed?"
        )
    with multiprocessing.Pool(2) as pool:
        results = pool.map(make_people_clip, jobs, chunksize=8)
    labels = np.concatenate([result[1] for result in results])
    np.savez(
        path,
        features=np.concatenate([result[0] for result in results]),
        labels=labels,
        lengths=np.array([len(result[1]) for result in results]),
    )
    ignored = float(np.mean(labels == festival_voices.IGNORE))
    print(
        f"{name}: {len(stems)} of {per_voice} sentences spoken, {len(jobs)} clips, "
        f"{labels.size / 360000:.2f} h ({ignored:.1%} of frames ignored), {time.time() - began:.0f} s",
        flush=True,
    )
    return path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--voices", nargs="*", choices=sorted(festival_voices.VOICES), default=None)
    parser.add_argument("--per-voice", type=int, default=400, help="sentences each voice speaks")
    parser.add_argument("--copies", type=int, default=2, help="each sentence: clean and degraded")
    parser.add_argument("--people-copies", type=int, default=3, help="each tune recording: clean, degraded")
    parser.add_argument("--clips", type=int, default=5000, help="eSpeak NG's clips (as train_recogniser)")
    parser.add_argument("--epochs", type=int, default=10)
    parser.add_argument("--learning-rate", type=float, default=FINAL_LEARNING_RATE)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--cache", type=Path, default=CACHE)
    parser.add_argument("--people", type=Path, default=people.FOLDER, help="lab/kit/people.py's folder")
    parser.add_argument("--start", type=Path, help="weights to go on from")
    parser.add_argument("--out", type=Path, default=PEOPLE_WEIGHTS_FILE)
    parser.add_argument(
        "--teacher",
        type=Path,
        help="eSpeak NG's clips learn these weights' posteriors instead of their labels (keeps its hearing)",
    )
    parser.add_argument(
        "--channels", type=int, default=CHANNELS, help="the network's width (wider: the start grown)"
    )
    parser.add_argument(
        "--teach-people", action="store_true", help="the teacher teaches the tune part's people too"
    )
    parser.add_argument("--keep-start", action="store_true", help="only the grown channels learn")
    parser.add_argument(
        "--klettres",
        action="store_true",
        help="KLettres' other languages' syllables too (people's train part)",
    )
    parser.add_argument("--corpus-only", action="store_true", help="make the corpora and stop")
    args = parser.parse_args(argv)
    args.cache.mkdir(parents=True, exist_ok=True)
    start = args.start or args.cache / f"round_3_{args.seed}.npz"
    if not start.exists():
        raise SystemExit(
            f"{start} is missing: run lab/train/recogniser.py first (it leaves its last round there)"
        )
    names = sorted(festival_voices.VOICES) if args.voices is None else args.voices
    festival_voices.install()
    voices = [festival_corpus(name, args.per_voice, args.copies, args.seed, args.cache) for name in names]
    espeak_clips = make_corpus(args.clips, args.seed, args.cache, whole_take_level=False)
    tune = make_people_corpus(
        args.people, start, args.people_copies, args.seed, args.cache, f"many_{start.stem}", False
    )
    syllables = []
    if args.klettres:
        name = f"klettres_{start.stem}"
        syllables.append(
            make_people_corpus(
                args.people, start, args.people_copies, args.seed, args.cache, name, False, "train"
            )
        )
    if args.corpus_only:
        return 0
    description = (
        "eSpeak NG's Turkish voice (variants, rates, pitches), degraded, a third of it cut to a word or two; "
        "people's speech (lab/kit/people.py's tune part, labelled by forced alignment, clean and degraded); "
        f"Festival's diphone voices {', '.join(names) or 'none'} ({args.per_voice} sentences each, labelled "
        f"by their own segments, clean and degraded)"
        + (
            "; KLettres' syllables in eight more languages (lab/kit/klettres_syllables.py, labelled by "
            "forced alignment, clean and degraded)"
            if args.klettres
            else ""
        )
        + f"; {args.epochs} epochs on from {start.name}"
        + (f", eSpeak NG's clips taught by {args.teacher.name}'s posteriors" if args.teacher else "")
        + (" (the tune part's people too)" if args.teach_people else "")
        + (f", grown to {args.channels} channels" if args.channels != CHANNELS else "")
        + (" (only the grown ones learning)" if args.keep_start else "")
    )
    train(
        [espeak_clips, tune, *voices, *syllables],
        args.epochs,
        args.seed,
        args.out,
        description,
        start,
        args.learning_rate,
        FINAL_BAND_WARP,
        args.teacher,
        args.channels,
        args.keep_start,
        2 if args.teach_people else 1,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
