"""The settings of lip sync from the audio alone (the decoder, the doubt kept off the lips, the phrases,
the closures given back, the warning): one object.

Each value says what it does; how each was chosen is in the manual (docs/developer/aligner-settings.md).
A call takes its own (`speech_from_audio(path, settings=RecogniserSettings(insertion_cost=2))`); the lab's
tuning scripts pass them the same way (`--set NAME=VALUE`).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class RecogniserSettings:
    """What the audio-only recogniser may be tuned by (see the module text)."""

    whisper_weight: float = 0.5
    """How much Whisper's hearing (acoustic/whisper.py), which has heard many people, counts against the
    shipped network's, which has heard eSpeak NG's voice in many rooms: their scaled likelihoods are
    averaged with this weight (0: the network alone, several times faster; 1: Whisper's alone)."""
    network_sure: float = 0.9
    """A take the network hears at least this surely (its likeliest class's posterior, averaged over the
    frames it hears as speech) is heard by the network alone: Whisper's encoder, ten times the network's
    time, adds little to a voice the network knows (eSpeak NG's, but in a reverberant room, where it is
    less sure and both are heard). People's takes fall far below (the tune part's Czech lines' median
    0.53). Above 1 (and network_doubtful too): Whisper always heard at its full weight."""
    network_doubtful: float = 0.7
    """Whisper's hearing counts fully (whisper_weight) for a take the network hears less surely than this;
    from here to network_sure its weight falls linearly to nothing (equal to network_sure: a step). The
    network hears eSpeak NG's voice in a reverberant room better than the pair does, though less surely
    than elsewhere; most people's takes lie below (the tune part's syllables' median 0.60). The
    low-confidence warning is judged with Whisper at its full weight wherever it is heard."""
    prior_weight: float = 0.8
    """The decoder divides the posteriors by the classes' priors to this power (scaled likelihoods)."""
    language_weight: float = 0.5
    """How much the Turkish letter transitions of the training texts count when leaving a class."""
    insertion_cost: float = 1.0
    """Natural-log units per new segment: keeps the mouth from chattering."""
    duration_scale: float = 0.7
    """Each class's shortest duration in the training speech, scaled by this (people speak faster than
    eSpeak's slowest)."""
    bilabial_sure: float = 0.15
    """A heard b, m or p is kept where the three together hold this share of its frames' posteriors (and
    no less than the vowels); else the likeliest letter that leaves the lips apart is taken."""
    phrase_pause: float = 0.12
    """Seconds of silence that end a phrase; shorter silences join the letters around them."""
    closure_share: float = 0.33
    """The share of the letter before a voiceless stop given back to the stop as its closure."""
    doubtful_confidence: float = 0.88
    """Below this confidence a take is reported as recognised with low confidence."""
    silent_peak_db: float = -70.0
    """A recording never louder than this (dB full scale) holds nothing."""


DEFAULT_RECOGNISER = RecogniserSettings()
