"""Stand-in speakers: eSpeak NG's variants of its Turkish voice (and MBROLA's Turkish diphone voices, measured
with only), each at its own pitch and rate, and the degraded takes the measures and tests align or recognise.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from lab.kit import diphone_voices
from lab.kit.takes import CONDITIONS, RATE, Take, write_wav
from turkish_lipsync.core.scene import RoleChoice
from turkish_lipsync.core.speech import espeak, get_engine, synthesize_timeline
from turkish_lipsync.core.speech.align import phone_letter_spans
from turkish_lipsync.core.speech.audio import resample
from turkish_lipsync.core.speech.features import ANALYSIS_RATE
from turkish_lipsync.core.speech.timing import build_timeline
from turkish_lipsync.core.text.utterance import build_utterance


def speak_variant(
    text: str, variant: str, pitch: int, rate: int, sample_rate: int = ANALYSIS_RATE, stops_at_bursts=False
):
    """Float samples of the text in the variant (16 kHz unless asked), and its timeline (the truth): as the
    product's, each voiceless stop from its closure, or with stops_at_bursts from its burst (the labels
    the network learns: burst_timeline)."""
    library = espeak._library()
    utterance = build_utterance(f'<PROS PITCH="{pitch:+d}%" RATE="{rate:+d}%">{text}</PROS>')
    with library.lock:
        library.handle.espeak_SetVoiceByName(f"tr+{variant}".encode())
    try:
        if stops_at_bursts:
            synthesis = get_engine("espeak").synthesize(utterance)
            timeline = burst_timeline(utterance, synthesis)
        else:
            speech = synthesize_timeline(utterance)
            synthesis, timeline = speech.synthesis, speech.timeline
    finally:
        with library.lock:
            library.handle.espeak_SetVoiceByName(b"tr")
    samples = resample(synthesis.samples.astype(np.float32) / 32768, synthesis.sample_rate, sample_rate)
    return samples, timeline


def burst_timeline(utterance, synthesis):
    """The timeline with each voiceless stop from its burst, where eSpeak NG reports it: the network learns
    the stops there, for the aligner matches the synthetic letters at their bursts and gives each stop its
    closure after the warp (timewarp.warp_synthesis), and the recogniser gives a stop back a share of the
    letter before (recognition/transcript.py). (The product's timelines start a stop at its closure.)"""
    starts, ends, linked = phone_letter_spans(utterance, synthesis, get_engine("espeak"))
    onsets = tuple(event.start for event in linked.phone_events)
    return build_timeline(utterance, starts, ends, linked.duration, "phone", onsets)


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
    "m7-low": Voice("tr+m7", -20, 5),
    "f2-high-slow": Voice("tr+f2", 15, -15),
    # MBROLA's Turkish diphone voices (lab/kit/diphone_voices.py): recordings of two Turkish speakers cut and
    # joined, at eSpeak NG's durations and pitch: another kind of synthesiser, and real people's sounds.
    "mbrola-tr1": Voice("mb-tr1", 0, 0),
    "mbrola-tr2": Voice("mb-tr2", 0, 0),
}


DEFAULT_VOICES = ("f3-high", "m5-low-fast", "klatt-slow", "f5-fast")


HELD_OUT_VOICES = ("croak", "m3-slow", "m7-low", "f2-high-slow")


TALKER = Voice("tr+m2", -5, 5)  # the voice in the background, reading a sentence of the other set


def speak_take(text: str, voice: Voice) -> Take:
    """The voice's reading of the text at RATE, with its word and letter onsets (the truth)."""
    if voice.variant.startswith("mb-"):
        samples, timeline = diphone_voices.speak(text, voice.variant.removeprefix("mb-"), RATE)
        return Take(
            samples,
            words=np.array([word.start for word in timeline.words]),
            letters=np.array([phone.start for phone in timeline.phones]),
            commas=np.array([word.pause_before > 0 for word in build_utterance(text).words]),
        )
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
    samples = resample(synthesis.samples.astype(np.float32) / 32768, synthesis.sample_rate, RATE)
    return Take(
        samples.astype(np.float64),
        words=np.array([word.start for word in timeline.words]),
        letters=np.array([phone.start for phone in timeline.phones]),
        commas=np.array([word.pause_before > 0 for word in utterance.words]),
    )


def hesitations(voice: Voice) -> tuple[np.ndarray, ...]:
    """The voice's "ııı" and "eee" (0.6-0.7 s each): the sounds of a hesitation said aloud."""
    return tuple(speak_take(sound, voice).samples for sound in ("ıııııı", "eeeeee"))


RECORDED_RATE = RATE


# Held-out voices: (variant, pitch %, rate %); the variants must be among the weights' held-out ones.
TEST_VOICES = {
    "m3": ("m3", -15, -20),
    "f4": ("f4", 20, 10),
    "klatt3": ("klatt3", 0, -15),
    "Andrea": ("Andrea", 10, 25),
    "benjamin": ("benjamin", -25, 5),
    "steph2": ("steph2", 30, -10),
}


# MBROLA's Turkish diphone voices (recordings of two Turkish speakers cut and joined; never in training):
# measured only when named with --voices.
DIPHONE_VOICES = {"mbrola-tr1": ("mb-tr1", 0, 0), "mbrola-tr2": ("mb-tr2", 0, 0)}  # lab/kit/diphone_voices.py


def make_take(text: str, voice: tuple[str, int, int], condition: str, folder: Path, rng) -> tuple:
    """A degraded take of the text in the voice: its path, the truth's timeline and the lead (seconds)."""
    if voice[0].startswith("mb-"):
        samples, truth = diphone_voices.speak(text, voice[0].removeprefix("mb-"), RECORDED_RATE)
    else:
        samples, truth = speak_variant(text, *voice, sample_rate=RECORDED_RATE)
    # The reading's start stands in for its words: a condition pads the take, and moves them by its lead.
    reading = Take(samples, words=np.zeros(1), letters=np.zeros(0), commas=np.zeros(1, bool))
    degraded = CONDITIONS[condition](reading, rng, {})
    path = write_wav(folder / "take.wav", degraded.samples, RECORDED_RATE)
    return path, truth, float(degraded.words[0]), degraded.samples


OTHER_LANGUAGES = {
    "en": (
        "The quick brown fox jumps over the lazy dog.",
        "Please call me back when you get home tonight.",
        "We were walking along the river when it started to rain.",
    ),
    "de": ("Der schnelle braune Fuchs springt über den faulen Hund.", "Wir gehen morgen früh in die Stadt."),
    "fr": ("Le petit chat dort sur le canapé du salon.", "Nous partons en vacances au mois de juillet."),
    "es": ("El perro corre por el parque todas las mañanas.", "Mañana vamos a visitar a mis abuelos."),
    "az": ("Bu gün hava çox gözəldir, parka gedək.", "Mən səhər tezdən durub çay içirəm."),
    "ja": ("kyou wa tenki ga ii desu ne.", "watashi wa mainichi gakkou ni ikimasu."),
}


def speak_language(text: str, language: str) -> tuple[np.ndarray, int]:
    """eSpeak NG's voice of another language reading a sentence of it (float samples, rate)."""
    from turkish_lipsync.core.base.model import Style
    from turkish_lipsync.core.speech import espeak

    library = espeak._library()
    with library.lock:
        library.handle.espeak_SetVoiceByName(language.encode())
        try:
            spoken = library.speak(text, Style())
        finally:
            library.handle.espeak_SetVoiceByName(b"tr")
    return np.concatenate(spoken.chunks).astype(np.float32) / 32768, library.sample_rate


def cast_reading(cast, reading: dict[str, float]) -> dict[str, RoleChoice]:
    """Each role of a conversation's cast in its own voice, read faster or lower by the factors of `reading`
    ("rate", "pitch"; none: as cast): a take of the scene unlike what its alignment synthesises."""
    return {
        role.name: RoleChoice(
            variant=role.voice.variant,
            pitch=role.voice.pitch * reading.get("pitch", 1.0),
            rate=role.voice.rate * reading.get("rate", 1.0),
        )
        for role in cast.roles
    }
