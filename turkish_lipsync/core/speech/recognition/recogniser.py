"""Recognise the Turkish letters of 16 kHz audio: two hearings, the decoder, and doubt.

The shipped network (acoustic/network.py) has heard eSpeak NG's Turkish voice in every room and few
people; Whisper's encoder under its classifier (acoustic/whisper.py) has heard many people and few
synthetic voices. Their scaled likelihoods (posteriors over priors) are averaged with the settings'
whisper_weight, which keeps the first's hearing of synthetic voices and brings the second's of people.
The network hears first; where it is sure of the take (settings.network_sure), as of eSpeak NG's voice
outside a reverberant room, Whisper's encoder, ten times its time, is not run; where it is nearly sure
(settings.network_doubtful), Whisper's weight is less.

The decoder's sequence is checked against the posteriors it came from, segment by segment, so that a
doubtful letter never shuts the mouth: a bilabial (b, m, p) the network is not sure of becomes the most
likely letter that leaves the lips apart (neither a bilabial nor f, v), and a stretch of the take that
sounds more like a vowel than anything else is never a closure. Letters between pauses form a phrase.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..acoustic.features import recogniser_features
from ..acoustic.labels import (
    BILABIAL_LETTERS,
    CLASS_INDEX,
    CLASSES,
    FRAME_SECONDS,
    SILENCE,
    VOWEL_CLASSES,
    frame_times,
)
from ..acoustic.network import load_network
from ..acoustic.whisper import load_whisper_hearing
from .decoder import Segment, decode
from .settings import DEFAULT_RECOGNISER, RecogniserSettings

BILABIALS = np.array([CLASS_INDEX[letter] for letter in sorted(BILABIAL_LETTERS)])
LIPS_APART = np.array(
    [index for index, name in enumerate(CLASSES) if name not in BILABIAL_LETTERS | {"f", "v", CLASSES[0]}]
)


@dataclass(frozen=True)
class HeardLetter:
    """A letter the recogniser heard: its span (seconds) and the share of its frames' posteriors it holds."""

    letter: str
    start: float
    end: float
    confidence: float


@dataclass(frozen=True, eq=False)
class Recognition:
    """What was heard: phrases of letters (between pauses), and how sure the recogniser is overall."""

    phrases: tuple[tuple[HeardLetter, ...], ...]
    # The decoded class's posterior in the middle of each heard letter, averaged (0..1): near 1 for Turkish
    # in any of the measured rooms, lower for another language's sounds (boundaries blur in any room, so
    # only the middles count).
    confidence: float


def recognise(
    samples: np.ndarray, settings: RecogniserSettings = DEFAULT_RECOGNISER, speech: np.ndarray | None = None
) -> Recognition:
    """The letters heard in 16 kHz float samples (Whisper's hearing only where the network needs it, and
    in a long take only around its speech: speech, the speech detector's frames, where given)."""
    network_heard = _network_hearing(samples)
    whisper_heard = None
    if whisper_needed(network_heard, settings):
        whisper_heard = load_whisper_hearing().log_posteriors(samples, speech)
    return recognise_posteriors(network_heard, whisper_heard, settings)


def hearings(samples: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The network's and Whisper's hearing's log posteriors (frames x classes) of 16 kHz float samples,
    both whatever the settings (what a tuning run keeps)."""
    return _network_hearing(samples), load_whisper_hearing().log_posteriors(samples)


def _network_hearing(samples: np.ndarray) -> np.ndarray:
    return load_network().log_posteriors(recogniser_features(samples))


def whisper_needed(network_heard: np.ndarray, settings: RecogniserSettings) -> bool:
    """Whether Whisper's hearing counts for the take (whisper_share above 0)."""
    return whisper_share(network_heard, settings) > 0


def whisper_share(network_heard: np.ndarray, settings: RecogniserSettings) -> float:
    """Whisper's weight for the take: settings.whisper_weight where the network is doubtful of it (its
    likeliest class's mean posterior over the frames it hears as speech under network_doubtful; no such
    frames: doubtful), falling linearly to nothing at network_sure."""
    if settings.whisper_weight <= 0:
        return 0.0
    likeliest = network_heard.max(axis=1)
    speech = network_heard.argmax(axis=1) != CLASS_INDEX[SILENCE]
    if not speech.any():
        return settings.whisper_weight
    sureness = float(np.exp(likeliest[speech]).mean())
    if sureness >= settings.network_sure:
        return 0.0
    span = settings.network_sure - settings.network_doubtful
    if span <= 0 or sureness <= settings.network_doubtful:
        return settings.whisper_weight
    return settings.whisper_weight * (settings.network_sure - sureness) / span


def recognise_posteriors(
    network_heard: np.ndarray,
    whisper_heard: np.ndarray | None,
    settings: RecogniserSettings = DEFAULT_RECOGNISER,
) -> Recognition:
    """The letters heard in the two hearings' log posteriors (hearings): what a tuning run varies.
    Whisper's counts with whisper_share's weight; the take's confidence is that of the take heard with
    Whisper at its full weight wherever Whisper counts at all (the network, sure of a voice it knows, is
    about as sure of another language in that voice: Whisper's hearing is what tells them apart)."""
    network = load_network()
    share = whisper_share(network_heard, settings)
    log_posteriors, priors = _averaged(network_heard, whisper_heard if share > 0 else None, share)
    segments = decode(log_posteriors, priors, network.transitions, network.shortest, settings)
    recognition = _phrases(segments, log_posteriors, settings)
    if whisper_heard is None or not 0 < share < settings.whisper_weight:
        return recognition
    judged, judged_priors = _averaged(network_heard, whisper_heard, settings.whisper_weight)
    segments = decode(judged, judged_priors, network.transitions, network.shortest, settings)
    return Recognition(recognition.phrases, _phrases(segments, judged, settings).confidence)


def _averaged(
    network_heard: np.ndarray, whisper_heard: np.ndarray | None, weight: float
) -> tuple[np.ndarray, np.ndarray]:
    """The two hearings' log posteriors as one (the scaled likelihoods averaged, over Whisper's priors)
    and the priors the decoder divides them by. Where Whisper did not hear (NaN: away from speech), the
    network's alone."""
    network_priors = load_network().priors
    if whisper_heard is None:
        return network_heard, network_priors
    whisper_priors = load_whisper_hearing().priors
    count = min(len(network_heard), len(whisper_heard))
    log_priors = np.log(whisper_priors).astype(np.float32)
    network_scaled = network_heard[:count] - np.log(network_priors).astype(np.float32)
    whisper_scaled = whisper_heard[:count] - log_priors
    unheard = np.isnan(whisper_scaled[:, 0])
    whisper_scaled[unheard] = network_scaled[unheard]
    averaged = (1 - weight) * network_scaled + weight * whisper_scaled
    averaged += log_priors
    averaged -= averaged.max(axis=1, keepdims=True)
    averaged -= np.log(np.exp(averaged).sum(axis=1, keepdims=True))
    return averaged.astype(np.float32), whisper_priors


def _phrases(
    segments: tuple[Segment, ...], log_posteriors: np.ndarray, settings: RecogniserSettings
) -> Recognition:
    starts = frame_times(len(log_posteriors)) - FRAME_SECONDS / 2
    phrases: list[list[HeardLetter]] = [[]]
    middles = []
    for segment in segments:
        probabilities = np.exp(log_posteriors[segment.first : segment.stop]).mean(axis=0)
        label = _doubt_checked(segment.label, probabilities, settings)
        start = float(starts[segment.first])
        end = float(starts[segment.stop - 1] + FRAME_SECONDS)
        if label == 0:
            if end - start >= settings.phrase_pause and phrases[-1]:
                phrases.append([])
            continue
        middles.append(float(np.exp(log_posteriors[(segment.first + segment.stop) // 2, segment.label])))
        phrase = phrases[-1]
        if phrase and phrase[-1].end < start:  # a short silence inside a phrase: the letter before holds
            phrase[-1] = HeardLetter(phrase[-1].letter, phrase[-1].start, start, phrase[-1].confidence)
        phrase.append(HeardLetter(CLASSES[label], start, end, float(probabilities[label])))
    found = tuple(tuple(phrase) for phrase in phrases if phrase)
    return Recognition(found, float(np.mean(middles)) if middles else 0.0)


def _doubt_checked(label: int, probabilities: np.ndarray, settings: RecogniserSettings) -> int:
    """The decoded class, unless it would close the lips where the network doubts a closure."""
    if label not in BILABIALS:
        return label
    if probabilities[BILABIALS].sum() >= settings.bilabial_sure and probabilities[BILABIALS].sum() >= (
        probabilities[VOWEL_CLASSES].sum()
    ):
        return label
    return int(LIPS_APART[np.argmax(probabilities[LIPS_APART])])
