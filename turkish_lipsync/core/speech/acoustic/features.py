"""What the recogniser hears: log mel bands of 16 kHz audio, levelled on the take's own speech.

40 mel bands from 60 Hz (a nasal's murmur and a stop's voice bar sit low) to 7.6 kHz, 25 ms windows every
10 ms (speech/features.py computes them, block by block). Each band is taken relative to the take's
speech level in that band (the mean over its loudest frames), which removes the microphone's and the
voice's colour and the recording's gain; the frame's loudness relative to the speech joins them, so
silence and quiet consonants stay apart from vowels. Everything is floored far below the speech (eSpeak's
digital silence and a quiet room then look alike) and scaled to units of about one.
"""

from __future__ import annotations

import numpy as np

from ..features import mel_energies

BANDS = 40
LOW_HERTZ = 60.0
TOP_HERTZ = 7600.0
LOUD_SHARE = 0.3  # the loudest 30 % of the frames stand for the take's speech level
FLOOR_DB = -60.0  # below the speech level; quieter is the same as this
SCALE_DB = 10.0  # decibels per feature unit
FEATURE_COUNT = BANDS + 1


def log_bands(samples: np.ndarray) -> np.ndarray:
    """Log mel energies (frames x BANDS, decibels) of 16 kHz float samples."""
    energies = mel_energies(samples, top_hertz=TOP_HERTZ, bands=BANDS, low_hertz=LOW_HERTZ)
    return 10.0 * np.log10(energies + 1e-10, dtype=np.float32)


def levelled(decibels: np.ndarray) -> np.ndarray:
    """The recogniser's features (frames x FEATURE_COUNT, float32) from log_bands' decibels.

    The levels are the whole take's, so a long take is described alike from start to end.
    """
    loudness = 10.0 * np.log10(np.sum(10.0 ** (decibels / 10.0), axis=1) + 1e-10)
    loud = loudness >= np.percentile(loudness, 100 * (1 - LOUD_SHARE))
    band_level = decibels[loud].mean(axis=0)
    speech_level = loudness[loud].mean()
    features = np.empty((len(decibels), FEATURE_COUNT), np.float32)
    features[:, :BANDS] = np.maximum(decibels - band_level, FLOOR_DB) / SCALE_DB
    features[:, BANDS] = np.maximum(loudness - speech_level, FLOOR_DB) / SCALE_DB
    return features


def recogniser_features(samples: np.ndarray) -> np.ndarray:
    """The features of 16 kHz float samples in [-1, 1]."""
    return levelled(log_bands(samples))
