"""How well speech is told from silence, noise and music: Silero VAD (speech_detector.py) on people's voices.

    python -m lab.measure.detection                 # the report sets (nobody tuned on them)
    python -m lab.measure.detection --tune          # the tuning sets, and the constants tried on them
    python -m lab.measure.detection --product [--every N]  # the recogniser's and the aligner's decisions
    python -m lab.measure.detection --agreement     # Silero against the WebRTC mask on eSpeak NG takes
    python -m lab.measure.detection --speed         # 10 minutes of audio through the detector, one core

Speech (each recording as it is, with white hiss at 20 dB SNR, and 30 dB quieter; the words and syllables
also cut to their loudest 0.2 s with 0.25 s of silence each side, and that core with the hiss; the tuning
lines too, standing in for the tuning sets' few words):
- klettres syllables and Fish Fillets NG's Dutch lines: lab/kit/people.py's folder (out/people;
  `python -m lab.kit.people build` makes it), dev/ as ../shared/voices/dev_voices.py builds it; its
  manifest.tsv lists them. Tuned on klettres-ru and klettres-tn and on the Dutch levels
  whose name's position in the sorted list of levels is not a multiple of 3; reported on klettres-uk,
  -fr, -cs and the levels at positions 0, 3, 6, ...
- ktuberling's single words, every language (report only): the same folder's packages/ (ktuberling-data
  unpacked), usr/share/ktuberling/sounds/<lang>/* (.ogg, .wav, .opus; the Serbian scripts' folders hold
  the same recordings, heard once).
- Fish Fillets NG's Czech voice acting (report only): packages/usr/share/games/fillets-ng/sound/<level>/
  cs/*.ogg there (fillets-ng-data-cs unpacked).

Not speech (every one should be "no speech found"): digital silence; white, pink, brown and babble-like
noise and synthetic music (lab/train/recogniser.py's, other seeds for tuning than for the report) at
several levels; Fish Fillets NG's game music and sound effects (fillets-ng-data, under the voices'
packages/ folder).

The recordings are read where they lie and never copied (GPL and other licences). Prints figures, asserts
nothing; docs/developer/measured/detection.md holds the last run's.
"""

from __future__ import annotations

import argparse
import hashlib
import itertools
import sys
import tempfile
import time
from collections import defaultdict
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from lab.kit.degradations import coloured_noise, music, speech_power
from lab.kit.people import FOLDER
from turkish_lipsync.core.base.errors import AudioError
from turkish_lipsync.core.speech import speech_detector
from turkish_lipsync.core.speech.audio import read_audio, resample
from turkish_lipsync.core.speech.features import ANALYSIS_RATE, HOP
from turkish_lipsync.core.speech.speech_detector import DEFAULT_DETECTOR, DetectorSettings

VOICES = FOLDER / "dev"
KTUBERLING = FOLDER / "packages/usr/share/ktuberling/sounds"
FILLETS_CS = FOLDER / "packages/usr/share/games/fillets-ng/sound"
FILLETS_GAME = VOICES / "packages/usr/share/games/fillets-ng"
TUNING_KLETTRES = ("klettres-ru", "klettres-tn")
CORE = 0.2  # seconds of a word kept by the "0.2 s core" condition (its loudest stretch)
CORE_SILENCE = 0.25  # seconds of silence put around the core
HISS_SNR = 20.0  # dB
QUIET_DB = -30.0
# The constants --tune tries, one at a time around the chosen ones (speech_detector.py).
TRIED = {
    "speech_threshold": (0.2, 0.3, 0.4, 0.5),
    "silence_threshold": (0.1, 0.15, 0.2, 0.25),
    "shortest_silence": (0.05, 0.1, 0.2),
    "certain_speech": (0.25, 0.32, 0.38, 0.45),
    "shortest_word": (0.03, 0.06, 0.1),
    "word_energy_share": (0.3, 0.5, 0.7),
    "loud_level_db": (-20.0, -10.0, -5.0, -2.0),
}


@dataclass(frozen=True, eq=False)
class Clip:
    """One recording or made-up sound at 16 kHz, the set it belongs to, whether it holds speech and a
    Turkish spelling of what it says (where known)."""

    set_name: str
    name: str
    samples: np.ndarray
    speech: bool
    turkish: str = ""


def read_16k(path: Path) -> np.ndarray | None:
    """The recording at 16 kHz, or None for one that holds no audio (fillets-nl has a few empty files)."""
    try:
        samples, rate = read_audio(path)
    except AudioError:
        return None
    return resample(samples, rate, ANALYSIS_RATE)


def voices_manifest(folder: Path) -> list[dict[str, str]]:
    lines = (folder / "manifest.tsv").read_text(encoding="utf-8").splitlines()
    header = lines[0].split("\t")
    return [dict(zip(header, line.split("\t"), strict=False)) for line in lines[1:] if line.strip()]


def speech_clips(
    tune: bool, voices: Path, ktuberling: Path, fillets_cs: Path, lines: bool = True
) -> Iterator[Clip]:
    """The people's recordings of the tuning part or of the report part (without the lines: the words and
    syllables only)."""
    manifest = voices_manifest(voices)
    levels = sorted(
        {row["source"].split("/", 1)[1] for row in manifest if row["source"].startswith("fillets")}
    )
    reported_levels = set(levels[::3])
    for row in manifest:
        source = row["source"]
        if source.startswith("klettres"):
            if (source in TUNING_KLETTRES) != tune:
                continue
            set_name = f"klettres syllables ({source.removeprefix('klettres-')})"
        else:
            if (source.split("/", 1)[1] not in reported_levels) != tune or not lines:
                continue
            set_name = "fillets-nl lines"
        yield Clip(set_name, row["id"], read_16k(voices / row["wav"]), True, row["turkish"])
    if tune:
        return
    heard = set()  # the Serbian scripts' folders hold the same recordings
    for language in sorted(path.name for path in ktuberling.iterdir() if path.is_dir()):
        for path in sorted((ktuberling / language).iterdir()):
            digest = hashlib.sha1(path.read_bytes()).hexdigest()
            if path.suffix in (".ogg", ".wav", ".opus") and digest not in heard:
                heard.add(digest)
                yield Clip("ktuberling words", f"{language}/{path.stem}", read_16k(path), True)
    for path in sorted(fillets_cs.glob("*/cs/*.ogg")) if lines else ():
        yield Clip("fillets-cs lines", f"{path.parent.parent.name}/{path.stem}", read_16k(path), True)


def non_speech_clips(tune: bool, game: Path) -> Iterator[Clip]:
    """Silence, made-up noise and music (other seeds for tuning), and, for the report, real game sounds."""
    rng = np.random.default_rng(100 if tune else 0)
    seconds = 5 * ANALYSIS_RATE
    yield Clip("silence", "digital", np.zeros(seconds, np.float32), False)
    for colour in ("white", "pink", "brown", "babble"):
        for level in (0.003, 0.03, 0.3):
            noise = level * coloured_noise(seconds, colour, rng)
            yield Clip(f"{colour} noise", f"rms {level}", noise.astype(np.float32), False)
    for number in range(10):
        yield Clip(
            "synthetic music",
            f"seed {number}",
            (0.2 * music(8 * ANALYSIS_RATE, rng)).astype(np.float32),
            False,
        )
    if tune:
        return
    for path in sorted((game / "music").glob("*.ogg")):
        yield Clip("game music", path.stem, read_16k(path), False)
    for path in sorted((game / "sound" / "share").glob("sp-*.ogg")):
        yield Clip("game sound effects", path.stem, read_16k(path), False)


def hissed(samples: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    level = np.sqrt(speech_power(samples) / 10 ** (HISS_SNR / 10))
    return (samples + level * coloured_noise(samples.size, "white", rng)).astype(np.float32)


def core(samples: np.ndarray) -> np.ndarray:
    """The loudest CORE seconds of a recording with CORE_SILENCE seconds of silence each side."""
    width = int(CORE * ANALYSIS_RATE)
    if samples.size > width:
        energy = np.convolve(samples.astype(np.float64) ** 2, np.ones(width), "valid")
        start = int(np.argmax(energy))
        samples = samples[start : start + width]
    silence = np.zeros(int(CORE_SILENCE * ANALYSIS_RATE), np.float32)
    return np.concatenate((silence, samples, silence))


CORE_CONDITIONS = (f"{CORE:g} s core", f"{CORE:g} s core + hiss")
CONDITIONS: dict[str, Callable[[np.ndarray, np.random.Generator], np.ndarray]] = {
    "as recorded": lambda samples, rng: samples,
    f"hiss {HISS_SNR:g} dB SNR": hissed,
    f"{CORE:g} s core": lambda samples, rng: core(samples),
    f"{CORE:g} s core + hiss": lambda samples, rng: hissed(core(samples), rng),
    f"{-QUIET_DB:g} dB quieter": lambda samples, rng: samples * np.float32(10 ** (QUIET_DB / 20)),
}


@dataclass(frozen=True, eq=False)
class Heard:
    """What the detector made of one clip (its samples dropped) under one condition."""

    set_name: str
    name: str
    condition: str
    probabilities: np.ndarray
    energies: np.ndarray

    def found(self, settings: DetectorSettings = DEFAULT_DETECTOR) -> bool:
        return bool(speech_detector.speech_chunks(self.probabilities, self.energies, settings).any())


def hear(
    clips: Iterator[Clip],
    speech_conditions: bool,
    tune_lines: bool = False,
    settings: DetectorSettings = DEFAULT_DETECTOR,
) -> list[Heard]:
    """Silero's chunk probabilities (the take levelled) and the chunks' energies under every condition (the
    0.2 s cores of sentences only when tuning: they stand in for the tuning sets' few words)."""
    rng = np.random.default_rng(5)
    heard = []
    for clip in clips:
        if clip.samples is None:
            continue
        for condition, make in CONDITIONS.items() if speech_conditions else (("as recorded", None),):
            if condition in CORE_CONDITIONS and clip.set_name.endswith("lines") and not tune_lines:
                continue  # a 0.2 s piece of a sentence is not a word: reported on the words and syllables
            samples = make(clip.samples, rng) if make else clip.samples
            probabilities, energies = speech_detector.levelled_probabilities(samples, settings)
            heard.append(Heard(clip.set_name, clip.name, condition, probabilities, energies))
    return heard


def report_speech(heard: list[Heard]) -> None:
    table: dict[tuple[str, str], list[bool]] = defaultdict(list)
    for item in heard:
        table[(item.set_name, item.condition)].append(item.found())
    print(f"{'speech: share found (missed/clips)':<34}" + "".join(f"{c:>20}" for c in CONDITIONS))
    for set_name in dict.fromkeys(name for name, _ in table):
        cells = []
        for condition in CONDITIONS:
            hits = table[(set_name, condition)]
            cells.append(f"{np.mean(hits):.1%} ({len(hits) - sum(hits)}/{len(hits)})" if hits else "-")
        print(f"{set_name:<34}" + "".join(f"{cell:>20}" for cell in cells))


def report_non_speech(heard: list[Heard]) -> None:
    table: dict[str, list[Heard]] = defaultdict(list)
    for item in heard:
        table[item.set_name].append(item)
    print(f"{'not speech':<34}{'taken for speech':>18}{'highest probability':>21}{'minutes':>9}")
    for set_name, items in table.items():
        false = [item.name for item in items if item.found()]
        highest = max(float(item.probabilities.max()) for item in items)
        minutes = sum(item.energies.size for item in items) * speech_detector.CHUNK / ANALYSIS_RATE / 60
        print(f"{set_name:<34}{f'{len(false)} of {len(items)}':>18}{highest:>21.3f}{minutes:>9.1f}", end="")
        print(f"  ({', '.join(false)})" if false else "")


def tune(speech: list[Heard], non_speech: list[Heard], remake) -> None:
    """Each constant varied alone (the level by hearing the clips again): misses per speech condition and
    false speech, on the tuning sets."""
    print("one constant at a time, the others as chosen: speech missed per condition; not speech taken")
    print(f"{'':<36}" + "".join(f"{condition[:14]:>16}" for condition in CONDITIONS))
    for name, values in TRIED.items():
        chosen = getattr(DEFAULT_DETECTOR, name)
        for value in values:
            settings = replace(DEFAULT_DETECTOR, **{name: value})
            tried_speech, tried_non_speech = (
                (speech, non_speech) if value == chosen or name != "loud_level_db" else remake(settings)
            )
            misses = defaultdict(int)
            for item in tried_speech:
                misses[item.condition] += not item.found(settings)
            false = sum(item.found(settings) for item in tried_non_speech)
            label = f"{name} {value}" + (" (chosen)" if value == chosen else "")
            cells = "".join(f"{misses[condition]:>16}" for condition in CONDITIONS)
            print(f"  {label:<34}{cells}   not speech taken: {false} of {len(tried_non_speech)}")
    print(f"  ({len(speech) // len(CONDITIONS)} speech clips per condition)")


def product_decisions(clips: Iterator[Clip], folder: Path, every: int) -> None:
    """The recogniser's "no speech found" and "no letters heard", and the aligner's "silent", on the single
    words and syllables (as recorded, their 0.2 s cores, the cores with hiss) and on what is not speech."""
    from lab.kit.takes import write_wav
    from turkish_lipsync.core.speech import synthesize_timeline
    from turkish_lipsync.core.speech.recognition import speech_from_audio
    from turkish_lipsync.core.text.utterance import build_utterance

    rng = np.random.default_rng(6)
    table: dict[tuple[str, str], list[int]] = defaultdict(lambda: [0, 0, 0, 0])
    for number, clip in enumerate(clips):
        if clip.samples is None or number % every:
            continue
        variants = {"as recorded": clip.samples}
        if clip.speech:
            variants[f"{CORE:g} s core"] = core(clip.samples)
            variants[f"{CORE:g} s core + hiss"] = hissed(core(clip.samples), rng)
        for condition, samples in variants.items():
            path = write_wav(folder / "clip.wav", samples, ANALYSIS_RATE)
            row = table[(clip.set_name, condition)]
            row[0] += 1
            try:
                speech_from_audio(path)
            except AudioError as error:
                row[1] += "no speech found" in str(error)
                row[2] += "no letters heard" in str(error)
            if clip.turkish:
                try:
                    synthesize_timeline(build_utterance(clip.turkish), recording=path)
                except AudioError as error:
                    row[3] += "silent" in str(error)
    header = f"{'clips':>6}{'no speech found':>17}{'no letters heard':>18}{'aligner: silent':>17}"
    print(f"{'product decisions':<52}{header}")
    for (set_name, condition), (count, nothing, no_letters, silent) in table.items():
        print(f"{set_name + ', ' + condition:<52}{count:>6}{nothing:>17}{no_letters:>18}{silent:>17}")


def agreement() -> None:
    """Silero's frame mask against the WebRTC-based one (voice_activity.speech_frames) on eSpeak NG takes:
    frames on which they agree, frames only one calls speech, and the share of the words' onsets (the
    truth, moved with the take) whose frame 30 ms later each calls speech."""
    from lab.kit.corpus import held_out_sentences
    from lab.kit.takes import CONDITIONS as TAKE_CONDITIONS
    from lab.kit.takes import RATE
    from lab.kit.voices import HELD_OUT_VOICES, TALKER, hesitations
    from lab.kit.voices import VOICES as TAKE_VOICES
    from lab.kit.voices import speak_take as speak
    from turkish_lipsync.core.speech.features import frame_count
    from turkish_lipsync.core.speech.voice_activity import speech_frames

    texts = held_out_sentences()[:10]
    context = {"talker": speak(" ".join(held_out_sentences()[10:13]), TALKER).samples}
    voices = HELD_OUT_VOICES[:2]
    spoken = [(speak(text, TAKE_VOICES[voice]), voice) for text in texts for voice in voices]
    sounds = {voice: hesitations(TAKE_VOICES[voice]) for voice in voices}
    print(f"{f'eSpeak NG takes ({len(spoken)} a condition)':<34}{'agree':>7}{'Silero only':>13}"
          f"{'WebRTC only':>13}{'onsets: Silero':>16}{'WebRTC':>8}{'no speech: Silero':>19}")  # fmt: skip
    for condition, make in TAKE_CONDITIONS.items():
        rng = np.random.default_rng(11)
        frames_counted = np.zeros(3)
        onsets = np.zeros(3)
        silent = 0
        for take, voice in spoken:
            context["hesitations"] = sounds[voice]
            made = make(take, rng, context)
            samples = resample(made.samples.astype(np.float32), RATE, ANALYSIS_RATE)
            frames = frame_count(samples.size)
            detection = speech_detector.detect_speech(samples, frames)
            silero, webrtc = detection.speech, speech_frames(samples, frames)
            frames_counted += [np.sum(silero == webrtc), np.sum(silero & ~webrtc), np.sum(webrtc & ~silero)]
            onset_frames = np.minimum(
                np.round((made.words + 0.03) * ANALYSIS_RATE / HOP).astype(int), frames - 1
            )
            onsets += [silero[onset_frames].sum(), webrtc[onset_frames].sum(), onset_frames.size]
            silent += not detection.found
        shares = frames_counted / frames_counted.sum()
        print(f"{condition:<34}{shares[0]:>7.1%}{shares[1]:>13.1%}{shares[2]:>13.1%}"
              f"{onsets[0] / onsets[2]:>16.1%}{onsets[1] / onsets[2]:>8.1%}{silent:>19}")  # fmt: skip


def speed() -> None:
    """10 minutes of 16 kHz audio (a Dutch line over and over, with noise) through the detector."""
    rng = np.random.default_rng(7)
    line = read_16k(next(VOICES.glob("wav/fillets-nl_*.wav")))
    count = 600 * ANALYSIS_RATE
    samples = np.tile(line, count // line.size + 1)[:count]
    samples = (samples + 0.01 * rng.normal(size=count)).astype(np.float32)
    speech_detector.load_detector()
    walls, processor = [], []
    for _ in range(5):
        began, began_processor = time.perf_counter(), time.process_time()
        speech_detector.detect_speech(samples)
        walls.append(time.perf_counter() - began)
        processor.append(time.process_time() - began_processor)
    # The processor time is what one core spends on it; the wall time grows with whatever else runs.
    print(f"10 minutes of 16 kHz audio: Silero's probabilities and the speech mask in "
          f"{np.median(processor):.2f} s of processor time, {np.median(walls):.2f} s of wall time "
          "(medians of 5; run it with OPENBLAS_NUM_THREADS=1 taskset -c 0 for one core)")  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tune", action="store_true", help="the tuning sets and the constants tried on them")
    parser.add_argument(
        "--product", action="store_true", help="also the recogniser's and aligner's decisions"
    )
    parser.add_argument("--agreement", action="store_true", help="Silero against WebRTC on eSpeak NG takes")
    parser.add_argument("--speed", action="store_true", help="10 minutes of audio through the detector")
    parser.add_argument("--every", type=int, default=1, help="--product: every Nth clip only (time)")
    parser.add_argument("--voices", type=Path, default=VOICES, help="dev_voices.py's folder")
    parser.add_argument("--ktuberling", type=Path, default=KTUBERLING, help="ktuberling's sounds/ folder")
    parser.add_argument(
        "--fillets-cs", type=Path, default=FILLETS_CS, help="fillets-ng-data-cs's sound/ folder"
    )
    parser.add_argument("--game", type=Path, default=FILLETS_GAME, help="fillets-ng-data's games/fillets-ng/")
    args = parser.parse_args(argv)
    if args.speed:
        speed()
        return 0
    if args.agreement:
        agreement()
        return 0
    constants = ", ".join(f"{name} {getattr(speech_detector, name)}" for name in TRIED)
    print(f"{'tuning' if args.tune else 'report'} sets; {constants}")

    def remake(settings: DetectorSettings = DEFAULT_DETECTOR) -> tuple[list[Heard], list[Heard]]:
        clips = speech_clips(args.tune, args.voices, args.ktuberling, args.fillets_cs)
        return (
            hear(clips, True, args.tune, settings),
            hear(non_speech_clips(args.tune, args.game), False, settings=settings),
        )

    if args.product:
        clips = itertools.chain(
            speech_clips(args.tune, args.voices, args.ktuberling, args.fillets_cs, lines=False),
            non_speech_clips(args.tune, args.game),
        )
        with tempfile.TemporaryDirectory() as folder:
            product_decisions(clips, Path(folder), args.every)
        return 0
    speech, non_speech = remake()
    report_speech(speech)
    report_non_speech(non_speech)
    if args.tune:
        tune(speech, non_speech, remake)
    return 0


if __name__ == "__main__":
    sys.exit(main())
