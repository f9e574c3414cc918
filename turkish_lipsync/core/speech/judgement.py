"""How well a recording says the text: a confidence per phrase, the refusal of another text, warnings.

Judged by the acoustic model, not by distances to eSpeak's voice: the letters' forced alignment
(letter_warp.py) says, in each recorded frame, how much less likely the text's letter there is than the
best class the network hears in it (the mismatch, natural-log units: about 0.5 for a person reading the
text in the measured rooms, 2 and more for another text). A word's mismatch is the mean over its frames;
with how the word's length compares with the recording's pace and loud speech the alignment leaves to
a pause, they say which words the recording leaves out or adds. Only a take whose
frames fit as another text's do, and whose sounds fit the text's order little better than the reverse,
is refused.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..base.errors import AudioError
from ..base.model import Utterance
from .base import PhoneEvent
from .features import ANALYSIS_RATE, HOP, frame_seconds
from .timewarp import JUMP, TimeWarp
from .voice_activity import runs


@dataclass(frozen=True)
class PhraseMatch:
    """A phrase of the text (words between pauses) as found in the recording, with how sure the match is."""

    first_word: int
    word_count: int
    start: float  # seconds in the recording
    end: float
    confidence: float  # 0 (the recording says something else here) .. 1 (a close match)


@dataclass(frozen=True, eq=False)
class Fit:
    """How the recording meets the text: the DTW path, and the letters' forced alignment frame by frame."""

    path_x: np.ndarray
    path_y: np.ndarray
    mismatch: np.ndarray  # per recorded frame: the best class's scaled log likelihood less the text's
    heard_letters: np.ndarray  # per recorded frame: the network hears a letter there, not silence
    frame_words: np.ndarray  # per recorded frame: the word the forced alignment puts there (-1: a pause)
    synthetic_speech: np.ndarray
    recorded_speech: np.ndarray  # the recorded frames judged: speech that no pause holds
    recorded_under_speech: np.ndarray  # dB under the recording's loud frames, per frame
    lead: int
    order_ratio: float  # the path's cost over the cost with the text's sounds in reverse order


# Measured with scripts/measure_people.py's tune part and scripts/measure_recordings.py's tuning takes:
# the mismatch of a take of the text (people: median 0.5, p95 0.8; eSpeak's other voices and rooms 0.1-0.4),
# of another text (people: 1.4-2.8, p5 1.5).
MATCHED = 0.5  # a phrase fitting this well has confidence 1
UNMATCHED = 2.0  # ... and this badly, 0
# A word is not in the recording when it fits worse than UNMATCHED_WORD and the recording gives it less
# than SHORTENED of its pace, or fits LOST_WORD worse than the take as a whole does (a take's own fit
# carries its voice, accent and room: the tune part's lists of foreign syllables that fit as a whole at
# 1.0-2.6 have their worst item at 2.3-6.1; eSpeak's voices fit at 0.1-0.4). (A short word a person says
# in a breath gets a fifth of eSpeak's pace and fits well: its shortness alone says nothing.)
UNMATCHED_WORD = 2.2
SHORTENED = 0.7
WORD_PRIOR_FRAMES = 10
LOST_WORD = 3.2
# A take fitting worse than OTHER_TEXT, whose sounds fit it in their order little better than reversed
# (the path's cost over that with the text's sounds in reverse order), reads another text and is refused;
# so does one fitting worse than PLAINLY_OTHER_TEXT whatever its order. The synthetic person's takes of
# another text (scripts/measure_recordings.py's tuning voices) that fit in some order (ratio 0.84-0.9) fit
# at 1.8-3.0, people's lists of eight read with their own text (the tune part) at most at 2.3: 2.5.
OTHER_TEXT = 1.6
OTHER_TEXT_ORDER_RATIO = 0.9
PLAINLY_OTHER_TEXT = 2.5
# ... unless a quarter of its words fit closer than WORDS_HEARD: a list of foreign syllables spelt roughly
# ("tsya", "şçı") fits as a whole, and in its order, as badly as another list's text, but its best
# words fit as another text's words do not (tune part, scripts/tune_judgement.py: the quarter-best word
# of a list read with its text at most 0.89, median 0.25; of another list's text at least 0.84, of
# another line's text p5 0.84-0.90). Such a take is judged by how loosely it fits (LOOSE, LIST_LOOSE).
WORDS_HEARD = 0.8
# A take fits its text only loosely, and is warned, when its mismatch plus ORDER_WEIGHT times its order
# ratio's excess over OWN_TEXT_ORDER_RATIO passes LOOSE: the order says as much as the fit. On the tune
# part's Czech lines (people), their own text's ratio is 0.68-0.96 (median 0.84), the next line's
# 0.90-1.08 (median 1.0). With the shipped network (scripts/tune_judgement.py) LOOSE warns as many of the
# right lines as the release before's network and bar did (21 of 166, 13 %, some by a word's own warning)
# and catches 96 % of the other lines' texts (92 % before); at 1.6, 17 warned and 95 %.
LOOSE = 1.45
OWN_TEXT_ORDER_RATIO = 0.7
ORDER_WEIGHT = 2.0
# A list (LIST_ITEMS phrases or more, none longer than two words: items read with pauses between them)
# is loose past LIST_LOOSE instead: each item is found on its own between pauses, and another list's text
# fits far worse than a list of foreign syllables spelt roughly does. Halfway between the tune part's
# lists' own texts' p90 of the score (1.58) and other lists' texts' p10 (2.52).
LIST_ITEMS = 4
LIST_LOOSE = 2.05
# A take or a text with less speech than this (1 s) is never refused, and warned as loose only past
# SHORT_LOOSE on its mismatch alone: a word or two said alone is too little to tell another text from a
# voice the network hears poorly (people's single words on the tune part: mismatch median 0.65, p90 2.3,
# against 1.9 for another word's text: at 2.4, 10 % of the right words were warned, at 2.6 6 %; a word
# shouted for over a second fits as badly), and a user who gives a single word with its text has almost
# always given the right one.
SHORT_LOOSE = 2.6
REFUSAL_EVIDENCE_FRAMES = 100
# A word stretched this much beyond the recording's pace, and fitting this badly, has company: words
# the text does not have were said next to it (a speaker's own lengthening of a word fits closely).
STRETCHED = 1.7
STRETCHED_MISMATCH = 1.3
# A stretch of loud recorded speech this long (300 ms; within LOUD_UNDER_SPEECH_DB of the speaker's loud
# frames: not a voice in the background, not a room's tail) that the letters' alignment leaves to a
# pause between two words is speech the text lacks.
EXTRA_SPEECH_FRAMES = 30
LOUD_UNDER_SPEECH_DB = 15.0
MOST_WARNINGS = 10  # a take with more places of doubt gets the first ones and a count of the rest


def word_frames(utterance: Utterance, phone_events: tuple[PhoneEvent, ...], lead: int) -> np.ndarray:
    """Each word's first and last synthetic frame (padded indices); -1 for a word the engine did not voice."""
    spans = np.full((len(utterance.words), 2), -1, np.int64)
    for event in phone_events:
        first = lead + int(event.start * ANALYSIS_RATE / HOP)
        last = lead + int(np.ceil(event.end * ANALYSIS_RATE / HOP))
        span = spans[event.word_index]
        span[0] = first if span[0] < 0 else min(span[0], first)
        span[1] = max(span[1], last)
    return spans


def word_scores(
    utterance: Utterance, phone_events: tuple[PhoneEvent, ...], warp: TimeWarp, fit: Fit
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per word: its synthetic frames' first and last (word_frames), its mismatch, and its pace.

    The mismatch is the mean over the recorded frames the forced alignment gives the word (NaN for a word
    the engine did not voice). The pace is the word's recorded length over its synthetic length, over
    the median word's: a pause put before a word (a hesitation) belongs to neither word.
    """
    spans = word_frames(utterance, phone_events, fit.lead)
    count = len(utterance.words)
    placed = (fit.frame_words >= 0) & fit.heard_letters
    frames = np.bincount(fit.frame_words[placed], minlength=count)[:count]
    sums = np.bincount(fit.frame_words[placed], weights=fit.mismatch[placed], minlength=count)[:count]
    voiced = spans[:, 0] >= 0
    # A short word has few frames to judge it by: its mismatch leans toward the take's by WORD_PRIOR_FRAMES
    # (a person's "a", "ve", "bu" are said in a breath, and the network hears little of them).
    prior = WORD_PRIOR_FRAMES * take_mismatch(fit)
    mismatch = np.where(voiced, (sums + prior) / (frames + WORD_PRIOR_FRAMES), np.nan)
    starts, ends = np.full(count, np.inf), np.full(count, -np.inf)
    for event in phone_events:
        starts[event.word_index] = min(starts[event.word_index], event.start)
        ends[event.word_index] = max(ends[event.word_index], event.end)
    pace = np.full(count, np.nan)
    recorded = warp(starts[voiced]), warp(ends[voiced] - JUMP)
    pace[voiced] = (recorded[1] - recorded[0]) / np.maximum(ends[voiced] - starts[voiced], 1e-3)
    return spans, mismatch, pace / np.nanmedian(pace)


def take_mismatch(fit: Fit) -> float:
    """The mismatch of the judged recorded frames (the speech no pause holds) in which the network hears a
    letter (where it hears silence in speech, it has no opinion on which letter): 0 is a perfect fit."""
    judged = fit.recorded_speech[: fit.mismatch.size] & fit.heard_letters
    return float(fit.mismatch[judged].mean()) if judged.any() else float(UNMATCHED)


def judge(
    utterance: Utterance,
    phone_events: tuple[PhoneEvent, ...],
    warp: TimeWarp,
    fit: Fit,
    path: Path,
    clipped: str = "",
) -> tuple[tuple[PhraseMatch, ...], tuple[str, ...]]:
    """A confidence per phrase; warnings naming the words where recording and text part. `clipped` names
    the take's clipping (audio.clipping), given as the likelier cause where the take fits loosely."""
    spans, mismatch, pace = word_scores(utterance, phone_events, warp, fit)
    take = take_mismatch(fit)
    unmatched = ((mismatch > UNMATCHED_WORD) & (pace < SHORTENED)) | (mismatch > take + LOST_WORD)
    crowded = (pace > STRETCHED) & (mismatch > STRETCHED_MISMATCH) & ~unmatched
    phrases = _phrases(utterance, warp, spans, fit)
    texts = [word.text for word in utterance.words]
    voiced = np.flatnonzero(spans[:, 0] >= 0)
    worst = voiced[np.argsort(-mismatch[voiced], kind="stable")]
    order_fits_little = fit.order_ratio > OTHER_TEXT_ORDER_RATIO
    # Both sides bound the evidence: a word shouted for a second is still one word's letters to go by.
    spoken = min(int(fit.recorded_speech[: fit.mismatch.size].sum()), int(fit.synthetic_speech.sum()))
    evidence = spoken >= REFUSAL_EVIDENCE_FRAMES
    words_heard = np.percentile(mismatch[voiced], 25) < WORDS_HEARD if voiced.size else False
    other_text = (take > OTHER_TEXT and order_fits_little) or take > PLAINLY_OTHER_TEXT
    if evidence and other_text and not words_heard:
        unheard = np.flatnonzero(mismatch > OTHER_TEXT)
        unheard = unheard if unheard.size else np.sort(worst[: max(1, worst.size // 2)])
        raise AudioError(
            f"recording {path} does not read this text: {_word_list(texts, unheard)} "
            f"({unheard.size} of its {len(texts)} words) are not heard in it; check that the recording "
            "and the text belong together" + (f" ({clipped})" if clipped else "")
        )
    causes = (
        f"{clipped}; or it may read another text"
        if clipped
        else "it may read another text, or be very noisy or reverberant"
    )
    warnings = [
        f"the recording fits this text only loosely ({causes}), worst at "
        f"{_word_list(texts, np.sort(worst[:3]))}; check that it reads this text: the face follows it as "
        "well as it can"
    ] * loosely_fitting(take, fit.order_ratio, evidence, _is_list(phrases))
    warnings += [
        f"the recording seems not to say {_word_list(texts, run)} (word {run[0] + 1} of the text); "
        "check the recording there: the face is timed on the rest"
        for run in _consecutive(np.flatnonzero(unmatched))
    ]
    stalls = _stalls(fit)
    for before, after, seconds in stalls:
        warnings.append(
            f"the recording says something the text does not between {texts[before]!r} and "
            f"{texts[after]!r} (at {seconds:.1f} s); the face keeps to the text's words there"
        )
    named = {index for before, after, _ in stalls for index in (before, after)}
    warnings.extend(
        f"the recording says something the text does not around {texts[index]!r} (word {index + 1} of the "
        f"text, at {float(warp(frame_seconds(spans[index, 0], fit.lead))):.1f} s); the face keeps to the "
        "text's words there"
        for index in np.flatnonzero(crowded)
        if index not in named
    )
    if len(warnings) > MOST_WARNINGS:
        more = len(warnings) - MOST_WARNINGS + 1
        warnings[MOST_WARNINGS - 1 :] = [f"and {more} more places where the recording and the text part"]
    return phrases, tuple(warnings)


def loosely_fitting(take: float, order_ratio: float, evidence: bool, is_list: bool) -> bool:
    """Whether a take of this mismatch and order ratio fits its text only loosely (see LOOSE)."""
    if not evidence:
        return take > SHORT_LOOSE
    return take + ORDER_WEIGHT * (order_ratio - OWN_TEXT_ORDER_RATIO) > (LIST_LOOSE if is_list else LOOSE)


def _is_list(phrases: tuple[PhraseMatch, ...]) -> bool:
    """Whether the text is a list: LIST_ITEMS phrases or more of a word or two each (see LIST_LOOSE)."""
    return len(phrases) >= LIST_ITEMS and all(phrase.word_count <= 2 for phrase in phrases)


def _phrases(utterance: Utterance, warp: TimeWarp, spans: np.ndarray, fit: Fit) -> tuple[PhraseMatch, ...]:
    """Words between pauses, each phrase with its place in the recording and its confidence."""
    starts = [index for index, word in enumerate(utterance.words) if index == 0 or word.pause_before > 0]
    phrases = []
    for first, stop in zip(starts, [*starts[1:], len(utterance.words)], strict=True):
        voiced = [index for index in range(first, stop) if spans[index, 0] >= 0]
        if not voiced:
            continue
        begin, end = spans[voiced[0], 0], spans[voiced[-1], 1]
        frames = (fit.frame_words >= first) & (fit.frame_words < stop) & fit.heard_letters
        mismatch = float(fit.mismatch[frames].mean()) if frames.any() else UNMATCHED
        confidence = (UNMATCHED - mismatch) / (UNMATCHED - MATCHED)
        recorded = warp(frame_seconds(np.array([begin, end]), fit.lead))
        phrases.append(
            PhraseMatch(
                first, stop - first, float(recorded[0]), float(recorded[1]), float(np.clip(confidence, 0, 1))
            )
        )
    return tuple(phrases)


def _stalls(fit: Fit) -> list[tuple[int, int, float]]:
    """Loud recorded speech that the letters' alignment leaves to a pause, between two words of the text.

    Each as (word before, word after, seconds into the recording). Before the first word or after the
    last, a breath or a noise is as likely as a word, so those are left alone.
    """
    loud = fit.recorded_speech & (fit.recorded_under_speech <= LOUD_UNDER_SPEECH_DB)
    unplaced = loud & (fit.frame_words < 0)
    placed = np.flatnonzero(fit.frame_words >= 0)
    found = []
    for start, stop in runs(unplaced):
        if stop - start < EXTRA_SPEECH_FRAMES or placed.size == 0:
            continue
        before = placed[placed < start]
        after = placed[placed >= stop]
        if before.size and after.size:
            middle = (start + stop) // 2
            found.append(
                (
                    int(fit.frame_words[before[-1]]),
                    int(fit.frame_words[after[0]]),
                    float(frame_seconds(middle)),
                )
            )
    return found


def _consecutive(indices: np.ndarray) -> list[np.ndarray]:
    if indices.size == 0:
        return []
    return np.split(indices, np.flatnonzero(np.diff(indices) > 1) + 1)


def _word_list(texts: list[str], indices: np.ndarray, shown: int = 6) -> str:
    names = [repr(texts[index]) for index in indices[:shown]]
    more = f" and {indices.size - shown} more" if indices.size > shown else ""
    return ", ".join(names) + more
