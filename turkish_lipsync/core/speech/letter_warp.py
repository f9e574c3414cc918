"""The time warp from where the acoustic model hears each letter of the text in the recording.

The DTW path (recording.py) finds the text in the recording as a whole, pauses and order included, but
its steps are drawn to the diagonal of eSpeak's pace. Each letter's own onset then comes from the
recording alone: forced alignment of the text's letters to what the network hears (acoustic/forced.py),
each recorded frame allowed only the letters the DTW path puts within reach of it. A knot of the warp
joins each letter's start (and end) in the synthetic speech to its start (and end) in the recording,
so every phone eSpeak spoke lands on the recording where its letter is heard.

The same path says how well the recording says the text, whatever the voice: in each recorded frame,
how much less likely the text's letter there is than the best class the network hears (the "goodness
of pronunciation" of Witt and Young 2000, in natural-log units of the scaled likelihoods): near 0 where a
person says the text, several units where they say something else (judgement.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.model import Hesitation, Utterance
from ..text.visemes import viseme_for_letter
from .acoustic.forced import (
    HELD_MARGIN,
    PARTING_FRAMES,
    PRIOR_WEIGHT,
    ForcedAlignment,
    LetterModel,
    TextUnits,
    force_align,
    letter_model,
    parting_gaps,
    text_units,
)
from .acoustic.labels import CLASS_INDEX, CLASSES, SILENCE, VOWEL_CLASSES, near_sounds
from .acoustic.network import PhoneNetwork
from .features import ANALYSIS_RATE, HOP, WINDOW
from .timewarp import JUMP, TimeWarp
from .voice_activity import runs

# A take of up to UNBANDED_CELLS frames x states (20 MB of back-pointers: a minute of speech) is aligned
# as a whole. In a longer one a recorded frame may hold the letters within a second of the synthetic
# frames the DTW path gives it, or, where no path fits that band, within three seconds: the DTW, drawn
# to eSpeak's pace, can be an item of a list read with long pauses away from it.
UNBANDED_CELLS = 20_000_000
REACHES = (100, 300)
SHORTEST_SCALE = 0.5  # a person's letters may be half as long as the shortest of eSpeak's
HESITATION_BREAK = 0.1  # seconds of quiet inside one hesitation said aloud (spoken_hesitations)


@dataclass(frozen=True, eq=False)
class LetterFit:
    """The warp through the letters, and per recorded frame the word there and how ill the text fits it."""

    warp: TimeWarp
    frame_words: np.ndarray  # index into Utterance.words, -1 where the path pauses
    mismatch: np.ndarray  # best class's scaled log likelihood less the text's letter's (>= 0)
    heard_letters: np.ndarray  # the network's best class is a letter, not silence, nor a hesitation's
    # the class of a hesitation's sound ("ııı") a pause holds, which no letter is drawn into (-1: none)
    hesitations: np.ndarray
    # per word: the most frames of a hesitation said aloud the path seems to draw into it
    # (_hesitation_drawn_in)
    hesitation_drawn_in: np.ndarray


def letter_warp(
    utterance: Utterance,
    synthetic_starts: np.ndarray,
    synthetic_ends: np.ndarray,
    log_posteriors: np.ndarray,
    silence_bias: np.ndarray,
    break_cost: np.ndarray,
    network: PhoneNetwork,
    path_x: np.ndarray,
    path_y: np.ndarray,
    lead: int,
    recording_duration: float,
    hesitation_classes: np.ndarray | None = None,
    hesitation_cost: float = 0.0,
    hesitation_frames: int = 1,
) -> LetterFit | None:
    """The letters' warp and fit; None where the text has no letter that is a sound, or no path fits.

    synthetic_starts, synthetic_ends: each utterance letter's span in the synthetic speech (seconds).
    log_posteriors: what the network hears in each recorded frame; silence_bias: what the speech
    detector adds to silence's score in each, break_cost: what a pause the text does not mark costs in
    each (acoustic/forced.py). path_x, path_y: the DTW path (synthetic frames padded by `lead`, recorded
    frames). hesitation_classes, hesitation_cost, hesitation_frames: what a pause may hold
    (acoustic/forced.py); a hesitation is not judged.
    """
    units = text_units(utterance)
    if units.classes.size == 0:
        return None
    shortest = np.maximum(1, np.round(network.shortest * SHORTEST_SCALE)).astype(np.int64)
    model = letter_model(units.classes, units.word_starts, shortest, units.marked)
    starts = synthetic_starts[units.letters]
    ends = synthetic_ends[units.letters]
    if len(log_posteriors) * len(model.classes) <= UNBANDED_CELLS:
        bands = [None]
    else:
        bands = [_band(model, starts, path_x, path_y, lead, len(log_posteriors), reach) for reach in REACHES]
    for band in bands:
        try:
            found = force_align(
                log_posteriors,
                network.priors,
                model,
                band,
                silence_bias,
                break_cost,
                hesitation_classes,
                hesitation_cost,
                hesitation_frames,
            )
            break
        except ValueError:
            continue
    else:
        return None
    recorded_starts = frame_edge_seconds(found.starts)
    recorded_ends = frame_edge_seconds(found.stops)
    _share_like_runs(units.classes, starts, ends, recorded_starts, recorded_ends)
    synthetic = np.ravel(np.column_stack((starts, ends - JUMP)))
    recorded = np.ravel(np.column_stack((recorded_starts, recorded_ends)))
    keep = np.concatenate(([True], np.diff(synthetic) > 0))
    synthetic, recorded = synthetic[keep], np.maximum.accumulate(recorded[keep])
    warp = TimeWarp(synthetic=synthetic, recorded=recorded, recording_duration=recording_duration)
    scaled = log_posteriors - PRIOR_WEIGHT * np.log(network.priors)[None, :]
    word_of_letter = np.array([utterance.letters[letter].word_index for letter in units.letters])
    frame_words = np.where(found.frame_letters >= 0, word_of_letter[found.frame_letters], -1)
    silence = CLASS_INDEX[SILENCE]
    # A hesitation's sound is no letter of the text's, nor one the text lacks: it is not judged.
    hesitations = found.frame_hesitations
    heard_letters = (scaled.argmax(axis=1) != silence) & (hesitations < 0)
    # The text's letter counts as heard where one of its near sounds is (shapekeys/near_sounds.toml).
    path_classes = np.where(found.frame_letters >= 0, units.classes[found.frame_letters], silence)
    text_score = np.where(near_sounds()[path_classes], scaled, -np.inf).max(axis=1)
    return LetterFit(
        warp,
        frame_words,
        scaled.max(axis=1) - text_score,
        heard_letters,
        hesitations,
        _hesitation_drawn_in(units, found, scaled, word_of_letter, len(utterance.words)),
    )


def _hesitation_drawn_in(
    units: TextUnits, found: ForcedAlignment, scaled: np.ndarray, word_of_letter: np.ndarray, words: int
) -> np.ndarray:
    """Per word, the most frames of a hesitation said aloud in a pause the text does not mark that the
    path seems to have drawn into it (0 for a word beside no such pause), from what the network hears
    (`scaled`, frames x classes): frames a vowel is heard as, or nearly as (forced.HELD_MARGIN), the best
    class inside one of the word's consonants ("eee" into the b of "balkonda", or into the p of
    "İmparatorluğu" after an İ a frame long; or into both consonants of a join, the m and the g of
    "Ağabeyim ııı geçen"), or a vowel inside the word held that long ("eee" into the e
    of "gelmeden": g a frame long, then the e through the hesitation). A word's first or last letter held
    long is its own (a drawn-out vowel, a room's tail) unless a pause parts the hold from the rest of the
    word inside it (forced.PARTING_FRAMES of silence: "eee", a breath, "eğlenceliydi"), where the vowel
    heard on the far side of that pause counts, or the path itself pauses at the join right beside it
    (forced.PARTING_FRAMES of the path's pause: "bugün eee işe" with the i and ş at the "eee"'s start and
    the e through it), where the whole letter counts."""
    joins = units.word_starts & ~units.marked
    joins[0] = False
    ends = np.append(units.word_starts[1:], True)
    after_join, before_join = joins, np.append(joins[1:], False)
    words_beside = np.unique(word_of_letter[np.flatnonzero(after_join | before_join)])
    placed = (found.starts >= 0) & np.isin(word_of_letter, words_beside)
    vowels = np.isin(units.classes, VOWEL_CLASSES)
    vowel_like = scaled[:, VOWEL_CLASSES].max(axis=1) >= scaled.max(axis=1) - HELD_MARGIN
    held = np.concatenate(([0], np.cumsum(vowel_like)))
    frames = np.zeros(len(units.classes), np.int64)
    consonants = np.flatnonzero(~vowels & placed)
    frames[consonants] = held[found.stops[consonants]] - held[found.starts[consonants]]
    inner = np.flatnonzero(vowels & ~units.word_starts & ~ends & placed)
    frames[inner] = found.stops[inner] - found.starts[inner]
    # A word's first vowel before its own start, its last after its own end: the whole letter where the
    # path itself pauses right beside it at the join ("bugün eee işe": i and ş at the "eee"'s start, the
    # e through it, then the pause); else the vowel heard on the far side of a silence inside it.
    gaps = parting_gaps(scaled.argmax(axis=1) == CLASS_INDEX[SILENCE])
    paused = np.concatenate(([0], np.cumsum(found.frame_letters < 0)))
    opening = np.flatnonzero(vowels & placed & units.word_starts & after_join)
    start, stop = found.starts[opening], found.stops[opening]
    beside = (start >= PARTING_FRAMES) & (
        paused[start] - paused[np.maximum(start - PARTING_FRAMES, 0)] == PARTING_FRAMES
    )
    last = np.searchsorted(gaps[:, 1], stop, side="left")  # gaps[:last] end inside or before the letter
    inside = last > np.searchsorted(gaps[:, 0], start, side="right")
    gap_start = gaps[np.maximum(last - 1, 0), 0] if len(gaps) else start
    frames[opening] = np.where(beside, held[stop] - held[start], 0)
    frames[opening] = np.maximum(frames[opening], np.where(inside, held[gap_start] - held[start], 0))
    closing = np.flatnonzero(vowels & placed & ends & before_join)
    start, stop = found.starts[closing], found.stops[closing]
    later = np.minimum(stop + PARTING_FRAMES, len(paused) - 1)
    beside = (stop + PARTING_FRAMES < len(paused)) & (paused[later] - paused[stop] == PARTING_FRAMES)
    first = np.searchsorted(gaps[:, 0], start, side="right")  # gaps[first:] start inside or after it
    inside = np.searchsorted(gaps[:, 1], stop, side="left") > first
    gap_stop = gaps[np.minimum(first, len(gaps) - 1), 1] if len(gaps) else stop
    frames[closing] = np.maximum(frames[closing], np.where(beside, held[stop] - held[start], 0))
    frames[closing] = np.maximum(frames[closing], np.where(inside, held[stop] - held[gap_stop], 0))
    drawn_in = np.zeros(words, np.int64)
    np.maximum.at(drawn_in, word_of_letter, frames)
    # A hold split between the consonants either side of a join ("Ağabeyim ııı geçen": the m and the g).
    after = np.flatnonzero(after_join)
    split = np.where(vowels[after - 1] | vowels[after], 0, frames[after - 1] + frames[after])
    np.maximum.at(drawn_in, word_of_letter[after - 1], split)
    np.maximum.at(drawn_in, word_of_letter[after], split)
    return drawn_in


def frame_edge_seconds(frames: np.ndarray) -> np.ndarray:
    """The recorded time (seconds) a span of frames starting at frame j starts at: between frames j-1
    and j."""
    return np.asarray(frames) * HOP / ANALYSIS_RATE + (WINDOW - HOP) / 2 / ANALYSIS_RATE


def spoken_hesitations(frame_hesitations: np.ndarray, frame_words: np.ndarray) -> tuple[Hesitation, ...]:
    """The hesitations said aloud in a fit's pauses (LetterFit.hesitations, .frame_words), one for each
    sound held, in recorded time, each shaped as its letter said alone; a few quiet frames in a pause
    (up to HESITATION_BREAK seconds) do not part one sound held on both sides of them."""
    sounds = frame_hesitations.copy()
    longest = round(HESITATION_BREAK * ANALYSIS_RATE / HOP)
    for start, stop in runs(sounds < 0):
        if (
            0 < start
            and stop < sounds.size
            and stop - start <= longest
            and sounds[start - 1] == sounds[stop]
            and np.all(frame_words[start:stop] < 0)
        ):
            sounds[start:stop] = sounds[stop]
    edges = np.flatnonzero(np.diff(sounds)) + 1
    starts = np.concatenate(([0], edges))
    stops = np.concatenate((edges, [sounds.size]))
    held = sounds[starts] >= 0
    return tuple(
        Hesitation(float(start), float(end), CLASSES[sound], viseme_for_letter(CLASSES[sound], None))
        for start, end, sound in zip(
            frame_edge_seconds(starts[held]),
            frame_edge_seconds(stops[held]),
            sounds[starts[held]],
            strict=True,
        )
    )


def _share_like_runs(
    classes: np.ndarray,
    synthetic_starts: np.ndarray,
    synthetic_ends: np.ndarray,
    recorded_starts: np.ndarray,
    recorded_ends: np.ndarray,
) -> None:
    """Letters of one class in a row and with no pause between them ("çok kar", "yapalım mı") are one
    sound to the network, which cannot say where one ends: their recorded span is shared out in the
    proportions of their synthetic spans (in place)."""
    index = 0
    while index < classes.size:
        last = index
        while (
            last + 1 < classes.size
            and classes[last + 1] == classes[index]
            and recorded_starts[last + 1] <= recorded_ends[last]
        ):
            last += 1
        if last > index:
            lengths = np.maximum(synthetic_ends[index : last + 1] - synthetic_starts[index : last + 1], 1e-3)
            bounds = recorded_starts[index] + (recorded_ends[last] - recorded_starts[index]) * np.concatenate(
                ([0.0], np.cumsum(lengths) / lengths.sum())
            )
            recorded_starts[index : last + 1] = bounds[:-1]
            recorded_ends[index : last + 1] = bounds[1:]
        index = last + 1


def _band(
    model: LetterModel,
    unit_starts: np.ndarray,
    path_x: np.ndarray,
    path_y: np.ndarray,
    lead: int,
    frames: int,
    reach: int,
) -> tuple[np.ndarray, np.ndarray]:
    """Per recorded frame, the states of the letters within `reach` frames of its synthetic frames."""
    lowest = np.full(frames, np.iinfo(np.int64).max)
    highest = np.full(frames, -1)
    np.minimum.at(lowest, path_y, path_x)
    np.maximum.at(highest, path_y, path_x)
    # Synthetic frame (padded) -> the letter being said there (-1 before the first).
    onsets = np.round(unit_starts * ANALYSIS_RATE / HOP).astype(np.int64) + lead
    first_unit = np.searchsorted(onsets, lowest - reach, side="right") - 1
    last_unit = np.searchsorted(onsets, highest + reach, side="right") - 1
    states = len(model.classes)
    firsts = np.append(model.first_states, states)
    # From the pause before the first letter reached to the pause after the last one.
    low = np.where(first_unit >= 0, firsts[np.maximum(first_unit, 0)] - 1, 0)
    high = np.where(last_unit >= 0, firsts[np.minimum(last_unit + 1, len(firsts) - 1)] + 1, 2)
    low = np.clip(np.minimum.accumulate(low[::-1])[::-1], 0, states - 1)
    high = np.clip(np.maximum.accumulate(high), 1, states)
    low[0], high[-1] = 0, states
    return low, high
