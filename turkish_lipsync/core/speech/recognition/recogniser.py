"""Recognise the Turkish letters of 16 kHz audio: features, the network, the decoder, and doubt.

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
    VOWEL_LETTERS,
    frame_times,
)
from ..acoustic.network import load_network
from .decoder import Segment, decode
from .settings import DEFAULT_RECOGNISER, RecogniserSettings

BILABIALS = np.array([CLASS_INDEX[letter] for letter in sorted(BILABIAL_LETTERS)])
VOWELS = np.array([CLASS_INDEX[letter] for letter in sorted(VOWEL_LETTERS)])
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


def recognise(samples: np.ndarray, settings: RecogniserSettings = DEFAULT_RECOGNISER) -> Recognition:
    """The letters heard in 16 kHz float samples."""
    return recognise_posteriors(load_network().log_posteriors(recogniser_features(samples)), settings)


def recognise_posteriors(
    log_posteriors: np.ndarray, settings: RecogniserSettings = DEFAULT_RECOGNISER
) -> Recognition:
    """The letters heard in the network's log posteriors (frames x classes): what a tuning run varies."""
    network = load_network()
    segments = decode(log_posteriors, network.priors, network.transitions, network.shortest, settings)
    return _phrases(segments, log_posteriors, settings)


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
        probabilities[VOWELS].sum()
    ):
        return label
    return int(LIPS_APART[np.argmax(probabilities[LIPS_APART])])
