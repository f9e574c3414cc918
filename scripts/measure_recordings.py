"""How well a recording in another voice is aligned to its text: word and phone onset error per condition.

    python scripts/measure_recordings.py [--set held-out|tuning] [--voices NAME ...] [--conditions NAME ...]
                                         [--mismatch]
    python scripts/measure_recordings.py --long MINUTES   # one long take: time, peak memory, onset error

Stand-ins for other speakers are eSpeak NG's Turkish voice with other variants (timbre), pitches and
rates; each is spoken, then degraded (room noise at an SNR, noise or a breath and a click before the
first word, leading silence, MP3/AAC coding, a synthetic room's reverberation), written as a 44.1 kHz
WAV and aligned to the text like a user's recording. The truth is the variant's own phone events. The
sentences come from examples/corpus_tr.txt: the tuning set is lines 1-30, the held-out set lines 31-50.
Prints median, p90 and max onset error (ms) of words and of letters per condition, the sentences in
which a word was keyed more than 50 ms early or inside the next word's span, the sentences that drew a
warning, and with --mismatch how many takes were refused, or accepted with a warning, when aligned to
the next sentence instead. With --long, a take of that many minutes (the held-out sentences over and
over, voice f3-high, 30 dB SNR) is made by a child process, then aligned here: the time, the peak
resident memory of this process and the word onset error are printed.
Not a test: the figures go into the README.
"""

from __future__ import annotations

import argparse
import io
import resource
import subprocess
import sys
import tempfile
import time
import wave
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

REPOSITORY = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPOSITORY))

from turkish_lipsync.core.base.errors import AudioError, LipSyncError  # noqa: E402
from turkish_lipsync.core.speech import espeak, synthesize_timeline  # noqa: E402
from turkish_lipsync.core.speech.audio import resample  # noqa: E402
from turkish_lipsync.core.text.utterance import build_utterance  # noqa: E402

CORPUS = REPOSITORY / "examples" / "corpus_tr.txt"
TUNING_LINES = 30
RECORDED_RATE = 44100
LEAD_SECONDS = 1.0


@dataclass(frozen=True)
class Voice:
    """A stand-in speaker: an eSpeak NG variant with its own pitch and rate (JSML PROS percentages)."""

    variant: str
    pitch: int
    rate: int


VOICES = {
    "f3-high": Voice("tr+f3", 20, -10),
    "m5-low-fast": Voice("tr+m5", -30, 15),
    "klatt-slow": Voice("tr+klatt", 0, -25),
    "f5-fast": Voice("tr+f5", -10, 25),
    "croak": Voice("tr+croak", 10, 0),
    "m3-slow": Voice("tr+m3", -15, -20),
}
DEFAULT_VOICES = ("f3-high", "m5-low-fast", "klatt-slow", "f5-fast")


def speak(text: str, voice: Voice) -> tuple[np.ndarray, int, np.ndarray, np.ndarray]:
    """The voice's audio (float) and rate, and its word and letter onsets (the truth)."""
    library = espeak._library()  # the measuring stand-ins need another variant of the engine's one voice
    utterance = build_utterance(f'<PROS PITCH="{voice.pitch:+d}%" RATE="{voice.rate:+d}%">{text}</PROS>')
    with library.lock:
        library.handle.espeak_SetVoiceByName(voice.variant.encode())
    try:
        speech = synthesize_timeline(utterance)
        timeline, synthesis = speech.timeline, speech.synthesis
    finally:
        with library.lock:
            library.handle.espeak_SetVoiceByName(b"tr")
    samples = resample(synthesis.samples.astype(np.float32) / 32768, synthesis.sample_rate, RECORDED_RATE)
    words = np.array([word.start for word in timeline.words])
    letters = np.array([phone.start for phone in timeline.phones])
    return samples, RECORDED_RATE, words, letters


def noise(count: int, colour: str, rng: np.random.Generator) -> np.ndarray:
    """Unit-power white, pink (1/f) or brown (1/f^2, a room's rumble) noise."""
    white = rng.normal(size=count)
    if colour != "white":
        spectrum = np.fft.rfft(white)
        frequency = np.maximum(np.fft.rfftfreq(count), 1 / count)
        spectrum /= frequency ** (0.5 if colour == "pink" else 1.0)
        white = np.fft.irfft(spectrum, count)
    return white / np.sqrt(np.mean(white**2))


def speech_power(samples: np.ndarray) -> float:
    """Mean power of the voiced part (the loud half of the 20 ms frames), the reference of an SNR."""
    frames = samples[: samples.size // 882 * 882].reshape(-1, 882)
    power = np.mean(frames**2, axis=1)
    return float(np.mean(power[power >= np.median(power)]))


def add_noise(samples: np.ndarray, snr: float, colour: str, rng: np.random.Generator) -> np.ndarray:
    return samples + noise(samples.size, colour, rng) * np.sqrt(speech_power(samples) / 10 ** (snr / 10))


def breath_and_click(samples: np.ndarray, lead: int, rng: np.random.Generator) -> np.ndarray:
    """A breath (band-limited noise swelling over 0.35 s) and a click (a 2 ms tick) in the lead-in."""
    out = samples.copy()
    level = np.sqrt(speech_power(samples))
    breath = int(0.35 * RECORDED_RATE)
    spectrum = np.fft.rfft(rng.normal(size=breath))
    frequency = np.fft.rfftfreq(breath, 1 / RECORDED_RATE)
    spectrum[(frequency < 500) | (frequency > 4000)] = 0
    shaped = np.fft.irfft(spectrum, breath) * np.hanning(breath)
    shaped *= 0.12 * level / np.sqrt(np.mean(shaped**2))
    start = lead - int(0.5 * RECORDED_RATE)
    out[start : start + breath] += shaped
    tick = int(0.002 * RECORDED_RATE)
    click = int(0.15 * RECORDED_RATE)
    out[click : click + tick] += 1.5 * level * np.hanning(tick) * np.sign(rng.normal(size=tick))
    return out


def reverberate(samples: np.ndarray, seconds: float, rng: np.random.Generator) -> np.ndarray:
    """Convolution with a synthetic room response: direct sound, then exponentially decaying noise (RT60)."""
    length = int(seconds * RECORDED_RATE)
    decay = np.exp(-6.9 * np.arange(length) / length)  # -60 dB at the end
    response = 0.4 * rng.normal(size=length) * decay * np.sqrt(3 / length * 100)
    response[0] = 1.0
    size = 1 << int(np.ceil(np.log2(samples.size + length)))
    wet = np.fft.irfft(np.fft.rfft(samples, size) * np.fft.rfft(response, size), size)[: samples.size]
    return wet * np.sqrt(speech_power(samples) / speech_power(wet))


def coded(samples: np.ndarray, codec: str) -> np.ndarray:
    """The samples after a round trip through MP3 or AAC at 64 kbit/s (PyAV, the dev dependency)."""
    import av

    buffer = io.BytesIO()
    container_format, codec_name = {"mp3": ("mp3", "libmp3lame"), "aac": ("adts", "aac")}[codec]
    with av.open(buffer, "w", format=container_format) as output:
        stream = output.add_stream(codec_name, rate=RECORDED_RATE, layout="mono")
        stream.bit_rate = 64000
        pcm = np.clip(samples, -1, 1).astype(np.float32)[None, :]
        frame = av.AudioFrame.from_ndarray(pcm, format="flt", layout="mono")
        frame.sample_rate = RECORDED_RATE
        for packet in stream.encode(frame):
            output.mux(packet)
        for packet in stream.encode(None):
            output.mux(packet)
    buffer.seek(0)
    decoded = []
    with av.open(buffer, "r") as source:
        for frame in source.decode(audio=0):
            decoded.append(frame.to_ndarray().astype(np.float32).mean(axis=0))
    out = np.concatenate(decoded)
    # The encoder's priming delay is the codec's: find it by correlation and take it out.
    window = min(out.size, samples.size, RECORDED_RATE * 4)
    correlation = np.fft.irfft(
        np.fft.rfft(out[:window], 2 * window) * np.conj(np.fft.rfft(samples[:window], 2 * window))
    )
    delay = int(np.argmax(correlation[: RECORDED_RATE // 10]))
    out = out[delay : delay + samples.size]
    return np.pad(out, (0, samples.size - out.size))


# name -> (lead-in seconds, degradation of the padded signal)
Condition = Callable[[np.ndarray, int, np.random.Generator], np.ndarray]
CONDITIONS: dict[str, tuple[float, Condition]] = {
    "clean 60 dB": (0.3, lambda s, lead, rng: add_noise(s, 60, "white", rng)),
    "40 dB": (0.3, lambda s, lead, rng: add_noise(s, 40, "white", rng)),
    "30 dB, leading noise": (LEAD_SECONDS, lambda s, lead, rng: add_noise(s, 30, "white", rng)),
    "30 dB pink, leading noise": (LEAD_SECONDS, lambda s, lead, rng: add_noise(s, 30, "pink", rng)),
    "30 dB brown, breath + click": (
        LEAD_SECONDS,
        lambda s, lead, rng: add_noise(breath_and_click(s, lead, rng), 30, "brown", rng),
    ),
    "leading silence 2 s": (2.0, lambda s, lead, rng: s),
    "MP3 64k, 40 dB": (0.3, lambda s, lead, rng: coded(add_noise(s, 40, "white", rng), "mp3")),
    "AAC 64k, 40 dB": (0.3, lambda s, lead, rng: coded(add_noise(s, 40, "white", rng), "aac")),
    "reverb RT60 0.4 s, 40 dB": (
        0.3,
        lambda s, lead, rng: add_noise(reverberate(s, 0.4, rng), 40, "white", rng),
    ),
}


def write_wav(path: Path, samples: np.ndarray, rate: int) -> Path:
    peak = max(1.0, float(np.max(np.abs(samples))))
    data = np.round(samples / peak * 32767).astype("<i2")
    with wave.open(str(path), "wb") as handle:
        handle.setnchannels(1)
        handle.setsampwidth(2)
        handle.setframerate(rate)
        handle.writeframes(data.tobytes())
    return path


def sentences(which: str) -> list[str]:
    lines = [line.strip() for line in CORPUS.read_text(encoding="utf-8").splitlines() if line.strip()]
    return lines[:TUNING_LINES] if which == "tuning" else lines[TUNING_LINES:]


def measure(texts: list[str], voices: list[str], conditions: list[str], folder: Path, mismatch: bool) -> None:
    print(f"{len(texts)} sentences x {len(voices)} voices ({', '.join(voices)}); onset error in ms")
    print(
        f"{'condition':<30}{'words':>24}{'letters':>24}  misplaced  warned"
        + ("  another text: refused / warned" if mismatch else "")
    )
    print(f"{'':<30}{'median    p90    max':>24}{'median    p90    max':>24}")
    spoken = {(text, name): speak(text, VOICES[name]) for text in texts for name in voices}
    for condition in conditions:
        lead, degrade = CONDITIONS[condition]
        word_errors, letter_errors, misplaced, failures = [], [], 0, 0
        warned, refused, doubted = 0, 0, 0
        rng = np.random.default_rng(11)
        for (text, _), (samples, rate, words, letters) in spoken.items():
            other = texts[(texts.index(text) + 1) % len(texts)]
            pad = int(lead * rate)
            padded = np.concatenate((np.zeros(pad), samples, np.zeros(int(0.4 * rate))))
            path = write_wav(folder / "take.wav", degrade(padded, pad, rng), rate)
            if mismatch:
                try:
                    doubted += bool(synthesize_timeline(build_utterance(other), recording=path).warnings)
                except AudioError:
                    refused += 1
            try:
                speech = synthesize_timeline(build_utterance(text), recording=path)
            except LipSyncError as error:
                failures += 1
                print(f"  failed: {text[:40]!r}: {error}")
                continue
            timeline = speech.timeline
            warned += bool(speech.warnings)
            found = np.array([word.start for word in timeline.words])
            word_errors.append(np.abs(found - words - lead))
            letter_errors.append(np.abs(np.array([p.start for p in timeline.phones]) - letters - lead))
            bounds = np.append(words + lead, np.inf)
            misplaced += int(np.any((found < bounds[:-1] - 0.05) | (found >= bounds[1:])))
        if not word_errors:
            print(f"{condition:<30} every alignment failed")
            continue
        row = f"{condition:<30}"
        for errors in (np.concatenate(word_errors), np.concatenate(letter_errors)):
            ms = 1000 * errors
            row += f"{np.median(ms):>10.0f}{np.percentile(ms, 90):>7.0f}{ms.max():>7.0f}"
        row += f"{misplaced:>11}{warned:>8}"
        row += f"{refused:>10} / {doubted} of {len(spoken)}" if mismatch else ""
        print(row + (f"  ({failures} refused)" if failures else ""), flush=True)


def write_long_take(path: Path, minutes: float) -> None:
    """The held-out sentences repeated for `minutes` in voice f3-high at 30 dB SNR; the truth beside it."""
    texts = sentences("held-out")
    one_pass = speak(" ".join(texts), VOICES["f3-high"])[0].size / RECORDED_RATE
    text = " ".join(texts * max(1, round(minutes * 60 / one_pass)))
    samples, rate, words, _ = speak(text, VOICES["f3-high"])
    lead = int(LEAD_SECONDS * rate)
    padded = np.concatenate((np.zeros(lead), samples, np.zeros(rate)))
    del samples
    write_wav(path, add_noise(padded, 30, "white", np.random.default_rng(3)), rate)
    np.save(path.with_suffix(".npy"), words + LEAD_SECONDS)
    path.with_suffix(".txt").write_text(text, encoding="utf-8")


def measure_long_take(minutes: float, folder: Path) -> None:
    path = folder / "long.wav"
    subprocess.run([sys.executable, __file__, "--write-long", str(path), str(minutes)], check=True)
    text = path.with_suffix(".txt").read_text(encoding="utf-8")
    truth = np.load(path.with_suffix(".npy"))
    began = time.perf_counter()
    speech = synthesize_timeline(build_utterance(text), recording=path)
    elapsed = time.perf_counter() - began
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # kB on Linux
    ms = 1000 * np.abs(np.array([word.start for word in speech.timeline.words]) - truth)
    print(
        f"take of {speech.synthesis.duration / 60:.1f} min, {len(text):,} characters, {truth.size:,} words: "
        f"aligned in {elapsed:.1f} s, peak resident memory {peak:.0f} MB; word onsets median "
        f"{np.median(ms):.0f} ms, p90 {np.percentile(ms, 90):.0f} ms, max {ms.max():.0f} ms; "
        f"{len(speech.warnings)} warnings"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--set", choices=("held-out", "tuning"), default="held-out")
    parser.add_argument("--voices", nargs="+", choices=sorted(VOICES), default=list(DEFAULT_VOICES))
    parser.add_argument("--conditions", nargs="+", choices=list(CONDITIONS), default=list(CONDITIONS))
    parser.add_argument("--sentences", type=int, default=0, help="use only the first N sentences")
    parser.add_argument("--mismatch", action="store_true", help="also align each take to the next sentence")
    parser.add_argument("--long", type=float, metavar="MINUTES", help="measure one take this long instead")
    parser.add_argument("--write-long", nargs=2, metavar=("PATH", "MINUTES"), help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.write_long:
        write_long_take(Path(args.write_long[0]), float(args.write_long[1]))
        return 0
    texts = sentences(args.set)[: args.sentences or None]
    with tempfile.TemporaryDirectory() as folder:
        if args.long:
            measure_long_take(args.long, Path(folder))
        else:
            measure(texts, args.voices, args.conditions, Path(folder), args.mismatch)
    return 0


if __name__ == "__main__":
    sys.exit(main())
