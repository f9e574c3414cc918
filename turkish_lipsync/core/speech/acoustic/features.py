"""What the recogniser hears: log mel bands of 16 kHz audio, levelled on the take's own speech.

40 mel bands from 60 Hz (a nasal's murmur and a stop's voice bar sit low) to 7.6 kHz, 25 ms windows every
10 ms (speech/features.py computes them, block by block). Each band is taken relative to the take's
speech level in that band (the mean over its loudest frames, a long break in the take left out), which
removes the microphone's and the voice's colour and the recording's gain; the frame's loudness relative
to the speech joins them, so silence and quiet consonants stay apart from vowels. Everything is floored
far below the speech (eSpeak's digital silence and a quiet room then look alike) and scaled to units of
about one.

A take's own level stands for the voice's long-term spectrum only when the take holds speech enough for
several vowels. In a syllable or a single word the loudest frames are one vowel, and levelling on them
takes that vowel's colour away (people's syllables: an i heard as e in 26 of 35 before). A take with little
speech is therefore levelled half on its own spectrum and half on the long-term spectrum of people's speech
(LONG_TERM_SPECTRUM_FILE, lab/train/recogniser.py --spectrum makes it), and wholly on its own from
OWN_LEVEL_FRAMES frames of speech on.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np

from ...base.errors import DataError
from ..features import HOP, WINDOW, mel_energies
from ..voice_activity import long_runs

BANDS = 40
LOW_HERTZ = 60.0
TOP_HERTZ = 7600.0
LOUD_SHARE = 0.3  # the loudest 30 % of the frames stand for the take's speech level ...
# ... leaving out a long quiet stretch: this many frames (3 s) or more, each QUIET_UNDER_DB under the take's
# loudest frames (their 99th percentile), is a break in the recording, not a pause of its speech. Counted,
# it filled the loud share where the speech holds less than 30 % of the take (a voice's sentence, then
# 20 s of room, then the next: the first sentence recognised 0.985 -> 0.955 alike, 0.879 with 40 s).
LONG_QUIET_FRAMES = 300
QUIET_UNDER_DB = 30.0
FLOOR_DB = -60.0  # below the speech level; quieter is the same as this
SCALE_DB = 10.0  # decibels per feature unit
FEATURE_COUNT = BANDS + 1
SPEECH_WITHIN_DB = 20.0  # a frame this close to the speech level counts as speech for OWN_LEVEL_FRAMES
FEW_SPEECH_FRAMES = 50  # up to here (one or two syllables) the own spectrum counts half ...
OWN_LEVEL_FRAMES = 150  # ... from here (several words) wholly; in between, linearly
SHORT_OWN_WEIGHT = 0.5
LONG_TERM_SPECTRUM_FILE = Path(__file__).with_name("speech_spectrum.npy")
# A recording is heard from this many frames before its first speech to as many after its last
# (speech_stretch): the features are levelled on the take's loudest frames, and the speech detector's and
# the pauses' levels are the take's own, so silence or room beyond would change how the same speech is
# heard. People's lines with 3 s of digital silence each side, aligned to their text: word onsets moved
# over 50 ms in 148 of 201 Czech and 59 of 89 Dutch lines before, 57 and 5 after (at 150 frames, 68 and
# 17 with a floor that left digital silence out; that floor moved a clean synthetic voice's lines in a
# conversation by 5-7 ms, and a cloud voice is as clean: not taken), 8 and 1 since the aligner hears a
# take within its sound (sounding_frames). eSpeak NG's short lines in other voices: aligned 190-510 ms
# off, and recognised as other letters altogether ("merhaba nasılsın" as "bulavajlasılşıüfü"), before;
# within 50 ms and alike after. 75 frames is about the training clips' mean silence around their speech.
SPEECH_MARGIN_FRAMES = 75
# A stretch that leaves out less than this share of the take changes its levels too little to hear the
# take twice for (a long take with a second of room before it: 0.15 s more of its 4 minutes' alignment).
LEAST_LEFT_OUT = 0.1
# No sample of digital silence passes one step of 16-bit audio (dither included): nothing was recorded.
DIGITAL_SILENCE = 2 / 32768


def log_bands(samples: np.ndarray) -> np.ndarray:
    """Log mel energies (frames x BANDS, decibels) of 16 kHz float samples."""
    energies = mel_energies(samples, top_hertz=TOP_HERTZ, bands=BANDS, low_hertz=LOW_HERTZ)
    return 10.0 * np.log10(energies + 1e-10, dtype=np.float32)


def speech_levels(decibels: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Each frame's loudness, the take's spectral shape (band levels minus the speech level) and its speech
    level (decibels), all from the loudest LOUD_SHARE of the frames outside long quiet stretches."""
    loudness = 10.0 * np.log10(np.sum(10.0 ** (decibels / 10.0), axis=1) + 1e-10)
    counted = ~long_quiet(loudness)
    loud = counted & (loudness >= np.percentile(loudness[counted], 100 * (1 - LOUD_SHARE)))
    speech_level = float(loudness[loud].mean())
    return loudness, decibels[loud].mean(axis=0) - speech_level, speech_level


def long_quiet(loudness: np.ndarray) -> np.ndarray:
    """The frames of runs of at least LONG_QUIET_FRAMES frames each QUIET_UNDER_DB under the take's loudest
    (their 99th percentile: the loudest frames are never quiet, so some are always left)."""
    return long_runs(loudness < np.percentile(loudness, 99) - QUIET_UNDER_DB, LONG_QUIET_FRAMES)


@cache
def long_term_spectrum() -> np.ndarray:
    """The long-term spectral shape of people's speech (BANDS decibels), as speech_levels measures it."""
    try:
        shape = np.load(LONG_TERM_SPECTRUM_FILE, allow_pickle=False)
    except (OSError, ValueError) as error:
        raise DataError(
            f"the recogniser's long-term spectrum {LONG_TERM_SPECTRUM_FILE} cannot be read ({error}); "
            "reinstall the extension"
        ) from None
    if shape.shape != (BANDS,):
        raise DataError(f"the recogniser's long-term spectrum {LONG_TERM_SPECTRUM_FILE} has the wrong shape")
    return shape.astype(np.float32)


def own_level_weight(loudness: np.ndarray, speech_level: float) -> float:
    """How much the take's own spectral shape counts in its levelling (SHORT_OWN_WEIGHT .. 1)."""
    speech = np.count_nonzero(loudness >= speech_level - SPEECH_WITHIN_DB)
    ramp = np.clip((speech - FEW_SPEECH_FRAMES) / (OWN_LEVEL_FRAMES - FEW_SPEECH_FRAMES), 0.0, 1.0)
    return float(SHORT_OWN_WEIGHT + (1.0 - SHORT_OWN_WEIGHT) * ramp)


def levelled(decibels: np.ndarray, whole_take_level: bool = False) -> np.ndarray:
    """The recogniser's features (frames x FEATURE_COUNT, float32) from log_bands' decibels.

    The levels are the whole take's, so a long take is described alike from start to end. With
    whole_take_level, a short take too is levelled on itself alone (as the shipped network's training
    data was).
    """
    loudness, shape, speech_level = speech_levels(decibels)
    weight = 1.0 if whole_take_level else own_level_weight(loudness, speech_level)
    if weight < 1.0:
        shape = weight * shape + (1.0 - weight) * long_term_spectrum()
    features = np.empty((len(decibels), FEATURE_COUNT), np.float32)
    features[:, :BANDS] = np.maximum(decibels - (speech_level + shape), FLOOR_DB) / SCALE_DB
    features[:, BANDS] = np.maximum(loudness - speech_level, FLOOR_DB) / SCALE_DB
    return features


def sounding_frames(samples: np.ndarray, frames: int) -> tuple[int, int]:
    """The first frame and the frame after the last of the take's sound: a run of digital silence at
    either end longer than SPEECH_MARGIN_FRAMES (an editor's export, a padded take) is not what was
    recorded, however long, so the same speech is aligned alike with or without it. The sound starts at
    the first frame whose window holds any of it. A shorter run is kept: it is the silence around speech
    the network learnt with (a conversation's turns are cut from a speaker's track with 0.3 s of it).
    The whole take where it is all digital silence.

    The aligner hears a take within its sound: its speech detector's floor is the take's quietest tenth,
    which digital silence pulled down (people's Czech lines with 3 s of it each side: a word moved over
    50 ms in 66 of 201 before). Every run left out, however short, kept more lines in place (4 of 201) but
    moved a conversation's turns (a character's jaw opening in the other's lines up to 6 % of its own
    instead of 4 %); the network hearing every take with silence around it instead moved people's lines
    as they come (the Dutch lines warned 4 -> 6 of 89). The recogniser hears a take with its silence (its
    speech stretch alone keeps a padded take's letters): within the sound, the report part's syllables'
    b, m, p were heard 5 of 20 times instead of 7."""
    sounding = np.flatnonzero(np.abs(samples) >= DIGITAL_SILENCE)
    if sounding.size == 0:
        return 0, frames
    first = max(0, -(-(int(sounding[0]) - WINDOW + 1) // HOP))  # the first frame whose window holds sound
    stop = min(int(sounding[-1]) // HOP + 1, frames)
    kept_before, kept_after = first <= SPEECH_MARGIN_FRAMES, frames - stop <= SPEECH_MARGIN_FRAMES
    return (0 if kept_before else first), (frames if kept_after else stop)


def frames_of(samples: np.ndarray, first: int, stop: int, frames: int) -> np.ndarray:
    """The samples of frames first .. stop - 1 of a take of `frames` frames (to its end where stop is the
    last), so that the part's frames are the take's."""
    return samples[first * HOP : stop * HOP if stop < frames else samples.size]


def speech_stretch(speech: np.ndarray) -> tuple[int, int]:
    """The first frame and the frame after the last of the stretch a take is heard on: SPEECH_MARGIN_FRAMES
    either side of its speech frames (all of it where it has none, or where that leaves out less than
    LEAST_LEFT_OUT of it)."""
    spoken = np.flatnonzero(speech)
    if spoken.size == 0:
        return 0, len(speech)
    first = max(0, int(spoken[0]) - SPEECH_MARGIN_FRAMES)
    stop = min(len(speech), int(spoken[-1]) + 1 + SPEECH_MARGIN_FRAMES)
    return (first, stop) if len(speech) - (stop - first) >= LEAST_LEFT_OUT * len(speech) else (0, len(speech))


def recogniser_features(samples: np.ndarray, whole_take_level: bool = False) -> np.ndarray:
    """The features of 16 kHz float samples in [-1, 1] (whole_take_level: see levelled)."""
    return levelled(log_bands(samples), whole_take_level)
