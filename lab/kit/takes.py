"""Stand-ins for a user's recording, made from the project's own speech: voices, rooms, noise, a person.

Used by lab/measure/recordings.py. A Take is audio with its truth (word and letter onsets); each
condition turns one take into another and moves the truth with it:

- room noise at an SNR (white, pink or brown), a breath and a click before the first word, MP3/AAC coding;
- a synthetic room: direct sound, a few early reflections and an exponentially decaying tail of noise
  whose high frequencies die sooner, at a given RT60 and direct-to-reverberant ratio;
- what a person does: tempo that changes inside the sentence (pieces spoken 0.75x to 1.35x, Praat's
  overlap-add resynthesis along a duration tier), hesitations where the text has no comma (0.35-0.8 s
  of the room's silence between two words; or 0.5-1.2 s holding the speaker's own "ııı" or "eee",
  context["hesitations"]), another vocal tract (pitch and formants shifted by up to
  3 semitones, Praat's "Change gender"), a talker in the background (another voice reading another
  sentence, in its own room) some dB down.

Praat comes through the praat-parselmouth package (a dev dependency: measuring only).
"""

from __future__ import annotations

import io
import wave
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

RATE = 44100


@dataclass(frozen=True, eq=False)
class Take:
    """Audio of a reading (float, RATE) and its truth: onsets of its words and letters, in seconds."""

    samples: np.ndarray
    words: np.ndarray
    letters: np.ndarray
    commas: np.ndarray  # per word: True where the text has a pause before it

    def moved(self, samples: np.ndarray, source: np.ndarray, target: np.ndarray) -> Take:
        """The take with new samples whose time `source` (increasing knots) now lies at `target`."""
        return replace(
            self,
            samples=samples,
            words=np.interp(self.words, source, target),
            letters=np.interp(self.letters, source, target),
        )


Condition = Callable[[Take, np.random.Generator], Take]


def speech_power(samples: np.ndarray) -> float:
    """Mean power of the voiced part (the loud half of the 20 ms frames), the reference of an SNR."""
    frames = samples[: samples.size // 882 * 882].reshape(-1, 882)
    power = np.mean(frames**2, axis=1)
    return float(np.mean(power[power >= np.median(power)]))


def noise(count: int, colour: str, rng: np.random.Generator) -> np.ndarray:
    """Unit-power white, pink (1/f) or brown (1/f^2, a room's rumble) noise."""
    white = rng.normal(size=count)
    if colour != "white":
        spectrum = np.fft.rfft(white)
        frequency = np.maximum(np.fft.rfftfreq(count), 1 / count)
        spectrum /= frequency ** (0.5 if colour == "pink" else 1.0)
        white = np.fft.irfft(spectrum, count)
    return white / np.sqrt(np.mean(white**2))


def add_noise(take: Take, snr: float, colour: str, rng: np.random.Generator) -> Take:
    level = np.sqrt(speech_power(take.samples) / 10 ** (snr / 10))
    return replace(take, samples=take.samples + noise(take.samples.size, colour, rng) * level)


def padded(take: Take, lead: float, tail: float = 0.4) -> Take:
    """Silence of `lead` seconds before the reading and `tail` after it."""
    pad = int(lead * RATE)
    samples = np.concatenate((np.zeros(pad), take.samples, np.zeros(int(tail * RATE))))
    return replace(take, samples=samples, words=take.words + pad / RATE, letters=take.letters + pad / RATE)


def breath_and_click(take: Take, lead: float, rng: np.random.Generator) -> Take:
    """A breath (band-limited noise swelling over 0.35 s) and a click (a 2 ms tick) in the lead-in."""
    out = take.samples.copy()
    level = np.sqrt(speech_power(out))
    breath = int(0.35 * RATE)
    spectrum = np.fft.rfft(rng.normal(size=breath))
    frequency = np.fft.rfftfreq(breath, 1 / RATE)
    spectrum[(frequency < 500) | (frequency > 4000)] = 0
    shaped = np.fft.irfft(spectrum, breath) * np.hanning(breath)
    shaped *= 0.12 * level / np.sqrt(np.mean(shaped**2))
    start = int((lead - 0.5) * RATE)
    out[start : start + breath] += shaped
    tick, click = int(0.002 * RATE), int(0.15 * RATE)
    out[click : click + tick] += 1.5 * level * np.hanning(tick) * np.sign(rng.normal(size=tick))
    return replace(take, samples=out)


def instrumental(seconds: float, rate: int = RATE, seed: int = 5) -> np.ndarray:
    """Music with no voice, as a video's intro or outro has it (peak 0.3): a kick and a snare on the beat
    (every 0.5 s), a hi-hat between, two chords held a second each."""
    rng = np.random.default_rng(seed)
    music = np.zeros(int(seconds * rate))
    for beat, start in enumerate(range(0, music.size, rate // 2)):
        hit = np.arange(min(music.size - start, int(0.15 * rate))) / rate
        drum = np.sin(2 * np.pi * 60 * hit) if beat % 2 == 0 else 0.4 * rng.normal(size=hit.size)
        music[start : start + hit.size] += 0.5 * np.exp(-hit / 0.03) * drum
        hat = start + rate // 4
        if hat < music.size:
            tick = np.arange(min(music.size - hat, int(0.05 * rate))) / rate
            music[hat : hat + tick.size] += 0.05 * np.exp(-tick / 0.01) * rng.normal(size=tick.size)
    for second, start in enumerate(range(0, music.size, rate)):
        held = np.arange(min(music.size - start, rate)) / rate
        for pitch in ((110, 220, 277, 330), (98, 196, 247, 294))[second % 2]:
            music[start : start + held.size] += 0.04 * np.sin(2 * np.pi * pitch * held) * np.exp(-held / 1.5)
    return 0.3 * music / np.abs(music).max()


def room_response(rt60: float, direct_to_reverberant_db: float, rng: np.random.Generator) -> np.ndarray:
    """A synthetic room's impulse response: direct sound, early reflections, a decaying diffuse tail.

    The tail is noise whose envelope falls 60 dB in rt60 seconds; its upper half-band decays twice as
    fast (walls and air absorb the highs). Reflections and tail together carry the direct sound's energy
    divided by the direct-to-reverberant ratio.
    """
    length = int(1.2 * rt60 * RATE)
    time = np.arange(length) / RATE
    tail = rng.normal(size=length) * np.exp(-6.9 * time / rt60)
    highs = rng.normal(size=length) * np.exp(-6.9 * time / (rt60 / 2))
    highs -= np.convolve(highs, np.ones(5) / 5, "same")  # keep the upper band only
    tail = np.convolve(tail, np.ones(5) / 5, "same") + highs
    onset = int(0.004 * RATE)
    tail[:onset] = 0
    tail[onset : 2 * onset] *= np.linspace(0, 1, onset)
    for delay in rng.uniform(0.003, 0.025, 6):  # early reflections off the walls, floor and desk
        tail[int(delay * RATE)] += rng.choice((-1, 1)) * rng.uniform(0.3, 0.7)
    tail *= np.sqrt(10 ** (-direct_to_reverberant_db / 10) / np.sum(tail**2))
    tail[0] = 1.0
    return tail


def plain_room_response(rt60: float, rng: np.random.Generator) -> np.ndarray:
    """The first measurements' room: direct sound, then white noise decaying over rt60 (DRR about -5 dB)."""
    length = int(rt60 * RATE)
    response = 0.4 * rng.normal(size=length) * np.exp(-6.9 * np.arange(length) / length)
    response *= np.sqrt(3 / length * 100)
    response[0] = 1.0
    return response


def reverberate(take: Take, response: np.ndarray) -> Take:
    """The take heard through a room's impulse response (at the same speech power)."""
    size = 1 << int(np.ceil(np.log2(take.samples.size + response.size)))
    wet = np.fft.irfft(np.fft.rfft(take.samples, size) * np.fft.rfft(response, size), size)
    wet = wet[: take.samples.size]
    return replace(take, samples=wet * np.sqrt(speech_power(take.samples) / speech_power(wet)))


def coded(take: Take, codec: str) -> Take:
    """The take after a round trip through MP3 or AAC at 64 kbit/s (PyAV, the dev dependency)."""
    import av

    samples = take.samples
    buffer = io.BytesIO()
    container_format, codec_name = {"mp3": ("mp3", "libmp3lame"), "aac": ("adts", "aac")}[codec]
    with av.open(buffer, "w", format=container_format) as output:
        stream = output.add_stream(codec_name, rate=RATE, layout="mono")
        stream.bit_rate = 64000
        frame = av.AudioFrame.from_ndarray(
            np.clip(samples, -1, 1).astype(np.float32)[None, :], format="flt", layout="mono"
        )
        frame.sample_rate = RATE
        for packet in [*stream.encode(frame), *stream.encode(None)]:
            output.mux(packet)
    buffer.seek(0)
    with av.open(buffer, "r") as source:
        out = np.concatenate(
            [frame.to_ndarray().astype(np.float32).mean(axis=0) for frame in source.decode(audio=0)]
        )
    # The encoder's priming delay is the codec's: find it by correlation and take it out.
    window = min(out.size, samples.size, RATE * 4)
    correlation = np.fft.irfft(
        np.fft.rfft(out[:window], 2 * window) * np.conj(np.fft.rfft(samples[:window], 2 * window))
    )
    delay = int(np.argmax(correlation[: RATE // 10]))
    out = out[delay : delay + samples.size]
    return replace(take, samples=np.pad(out, (0, samples.size - out.size)))


def _praat_sound(samples: np.ndarray):
    import parselmouth

    return parselmouth.Sound(samples.astype(np.float64), RATE)


def shift_vocal_tract(take: Take, rng: np.random.Generator, most_semitones: float = 3.0) -> Take:
    """Pitch and formants both shifted by the same random amount, up to most_semitones either way."""
    from parselmouth.praat import call

    semitones = rng.uniform(1.0, most_semitones) * rng.choice((-1, 1))
    factor = 2 ** (semitones / 12)
    sound = _praat_sound(take.samples)
    median = call(call(sound, "To Pitch", 0.0, 75, 600), "Get quantile", 0, 0, 0.5, "Hertz")
    shifted = call(sound, "Change gender", 75, 600, factor, median * factor, 1.0, 1.0)
    out = shifted.values[0]
    return replace(take, samples=np.pad(out, (0, max(0, take.samples.size - out.size)))[: take.samples.size])


def change_tempo(take: Take, rng: np.random.Generator, slowest: float = 0.75, fastest: float = 1.35) -> Take:
    """Pieces of 0.4-1.2 s, each spoken at its own tempo between slowest and fastest (pitch kept).

    A duration tier (Praat's manipulation) steps between the pieces' factors over 20 ms; the truth is
    moved by the integral of the same tier.
    """
    from parselmouth.praat import call

    duration = take.samples.size / RATE
    bounds = [0.0]
    while bounds[-1] < duration:
        bounds.append(bounds[-1] + rng.uniform(0.4, 1.2))
    bounds[-1] = duration
    tempos = rng.uniform(slowest, fastest, len(bounds) - 1)
    times, factors = [], []
    for begin, end, tempo in zip(bounds[:-1], bounds[1:], tempos, strict=True):
        times += [begin + 0.01, end - 0.01]
        factors += [1 / tempo, 1 / tempo]
    sound = _praat_sound(take.samples)
    manipulation = call(sound, "To Manipulation", 0.01, 75, 600)
    tier = call("Create DurationTier", "tempo", 0, duration)
    for time, factor in zip(times, factors, strict=True):
        call(tier, "Add point", time, factor)
    call([manipulation, tier], "Replace duration tier")
    out = call(manipulation, "Get resynthesis (overlap-add)").values[0]
    grid = np.linspace(0, duration, int(duration * 1000) + 1)
    stretch = np.interp(grid, times, factors)
    mapped = np.concatenate(([0.0], np.cumsum(0.5 * (stretch[1:] + stretch[:-1]) * np.diff(grid))))
    return take.moved(out, grid, mapped)


def hesitate(
    take: Take,
    rng: np.random.Generator,
    shortest: float = 0.35,
    longest: float = 0.8,
    sound: np.ndarray | None = None,
    before: tuple[int, ...] = (),
) -> Take:
    """One or two hesitations before words the text gives no pause (fades of 10 ms around them), or
    before the words `before` (indexes): silent, or holding `sound` (a hesitation's "ııı", RATE) with at
    least 50 ms of silence either side."""
    if before:
        chosen = np.array(sorted(before), np.int64)
    else:
        candidates = np.flatnonzero(~take.commas[1:]) + 1
        if candidates.size == 0:
            return take
        chosen = np.sort(rng.choice(candidates, size=min(candidates.size, rng.integers(1, 3)), replace=False))
    samples = take.samples
    fade = int(0.01 * RATE)
    pieces, source, target, begin, shift = [], [0.0], [0.0], 0, 0
    for word in chosen:
        cut = int(take.words[word] * RATE)
        piece = samples[begin:cut].copy()
        piece[-fade:] *= np.linspace(1, 0, fade)
        if begin:
            piece[:fade] *= np.linspace(0, 1, fade)
        pause = int(rng.uniform(shortest, longest) * RATE)
        pieces += [piece, np.zeros(pause) if sound is None else _holding(sound, pause)]
        source += [cut / RATE - 1e-6, cut / RATE]  # the word that starts at the cut starts after the pause
        target += [(cut + shift) / RATE - 1e-6, (cut + shift + pause) / RATE]
        begin, shift = cut, shift + pause
    last = samples[begin:].copy()
    last[:fade] *= np.linspace(0, 1, fade)
    pieces.append(last)
    end = samples.size / RATE
    return take.moved(
        np.concatenate(pieces), np.array([*source, end]), np.array([*target, end + shift / RATE])
    )


def _holding(sound: np.ndarray, length: int) -> np.ndarray:
    """`length` samples of silence with as much of `sound` as fits 50 ms inside it, faded over 30 ms."""
    margin, fade = int(0.05 * RATE), int(0.03 * RATE)
    heard = sound[: max(0, length - 2 * margin)].copy()
    if heard.size > 2 * fade:
        heard[:fade] *= np.linspace(0, 1, fade)
        heard[-fade:] *= np.linspace(1, 0, fade)
    pause = np.zeros(length)
    pause[margin : margin + heard.size] = heard
    return pause


def background_talker(take: Take, talker: np.ndarray, below_db: float, rng: np.random.Generator) -> Take:
    """Another voice (`talker`, RATE) reading in its own room throughout the take, below_db under it."""
    repeats = int(np.ceil(take.samples.size / talker.size)) + 1
    voice = np.tile(talker, repeats)
    start = int(rng.integers(0, talker.size))
    voice = voice[start : start + take.samples.size]
    heard = reverberate(replace(take, samples=voice), room_response(0.5, -3.0, rng)).samples
    level = np.sqrt(speech_power(take.samples) / speech_power(heard) / 10 ** (below_db / 10))
    return replace(take, samples=take.samples + heard * level)


def _talker(take: Take, rng: np.random.Generator, context: dict) -> Take:
    return background_talker(take, context["talker"], 18.0, rng)


def _person(take: Take, rng: np.random.Generator, context: dict) -> Take:
    """Everything a person's take has at once: another tract, changing tempo, hesitations, a live room."""
    take = hesitate(change_tempo(shift_vocal_tract(take, rng), rng), rng)
    take = reverberate(padded(take, 0.5), room_response(0.3, 0.0, rng))
    return add_noise(_talker(take, rng, context), 25, "pink", rng)


def _aloud(take: Take, rng: np.random.Generator, context: dict) -> Take:
    sounds = context["hesitations"]
    return hesitate(take, rng, 0.5, 1.2, sounds[int(rng.integers(len(sounds)))])


def _clean(lead: float, snr: float = 60):
    return lambda take, rng, context: add_noise(padded(take, lead), snr, "white", rng)


CONDITIONS = {
    "clean 60 dB": _clean(0.3),
    "40 dB": _clean(0.3, 40),
    "30 dB, leading noise": _clean(1.0, 30),
    "30 dB pink, leading noise": lambda t, rng, c: add_noise(padded(t, 1.0), 30, "pink", rng),
    "30 dB brown, breath + click": lambda t, rng, c: add_noise(
        breath_and_click(padded(t, 1.0), 1.0, rng), 30, "brown", rng
    ),
    "leading silence 2 s": lambda t, rng, c: padded(t, 2.0),
    "MP3 64k, 40 dB": lambda t, rng, c: coded(_clean(0.3, 40)(t, rng, c), "mp3"),
    "AAC 64k, 40 dB": lambda t, rng, c: coded(_clean(0.3, 40)(t, rng, c), "aac"),
    "reverb RT60 0.4 s, 40 dB": lambda t, rng, c: add_noise(
        reverberate(padded(t, 0.3), plain_room_response(0.4, rng)), 40, "white", rng
    ),
    "tempo 0.75-1.35x": lambda t, rng, c: _clean(0.3)(change_tempo(t, rng), rng, c),
    "hesitations 0.35-0.8 s": lambda t, rng, c: _clean(0.3)(hesitate(t, rng), rng, c),
    "hesitations aloud (ııı, eee)": lambda t, rng, c: _clean(0.3)(_aloud(t, rng, c), rng, c),
    "vocal tract +-3 semitones": lambda t, rng, c: _clean(0.3)(shift_vocal_tract(t, rng), rng, c),
    "live room RT60 0.3 s, DRR 0 dB": lambda t, rng, c: add_noise(
        reverberate(padded(t, 0.3), room_response(0.3, 0.0, rng)), 60, "white", rng
    ),
    "background talker -18 dB": lambda t, rng, c: _clean(0.3)(_talker(t, rng, c), rng, c),
    "25 dB SNR pink": lambda t, rng, c: add_noise(padded(t, 0.5), 25, "pink", rng),
    "a person (all of these)": _person,
}


PERSON_CONDITIONS = list(CONDITIONS)[9:]


def write_wav(path: Path, samples: np.ndarray, rate: int) -> Path:
    peak = max(1.0, float(np.max(np.abs(samples))))
    data = np.round(samples / peak * 32767).astype("<i2")
    with wave.open(str(path), "wb") as handle:
        handle.setnchannels(1)
        handle.setsampwidth(2)
        handle.setframerate(rate)
        handle.writeframes(data.tobytes())
    return path
