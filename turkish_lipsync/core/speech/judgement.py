"""How well a recording says the text: a confidence per phrase, the refusal of another text, warnings.

Judged from the DTW path between the synthetic rendition and the recording: the feature distance along
it per word and per phrase, how the words' lengths compare with the recording's pace, recorded speech the
synthetic speech does not advance through, and the path's cost against that of the text's sounds in
reverse order (near 1 when the recording says something else, whatever the voice).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..base.errors import AudioError
from ..base.model import Utterance
from .base import PhoneEvent
from .features import ANALYSIS_RATE, HOP, frame_seconds
from .timewarp import TimeWarp
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
    """The DTW path and the feature distance along it, for judging how well the recording says the text."""

    path_x: np.ndarray
    path_y: np.ndarray
    distances: np.ndarray
    synthetic_speech: np.ndarray
    recorded_speech: np.ndarray
    lead: int
    order_ratio: float  # the path's cost over the cost with the text's sounds in reverse order


# Mean feature distance (normalised cepstra and slopes) along the path. Measured with scripts/
# measure_recordings.py on the tuning sentences: the same text in other voices, noise and codecs 1.1-2.9 per
# sentence, in a reverberant room 3.1-3.9, another text 4.1-4.8; the path's cost over that of the text's
# sounds reversed 0.5-0.81 for the same text, 0.85-1.0 for another. A voice further from eSpeak's raises
# every word's distance, so words are judged against the recording's own median word too.
MATCHED_DISTANCE = 1.5  # a phrase this close has confidence 1
UNMATCHED_DISTANCE = 4.0  # ... and this far, 0
# The whole recording this far off, and its order no better than this: it reads another text.
OTHER_TEXT_DISTANCE = 3.95
OTHER_TEXT_ORDER_RATIO = 0.83
# Either beyond these (above all the same text's clean or noisy takes, below the reverberant ones): a warning.
DOUBTFUL_DISTANCE = 3.4
DOUBTFUL_ORDER_RATIO = 0.78
UNMATCHED_WORD_DISTANCE = 4.4  # one word this far off, and
UNMATCHED_WORD_RATIO = 1.7  # this many times the median word's distance, is not in the recording
SQUEEZED = 0.25  # a word given less than this share of the recording's pace is missing
# A word stretched this much beyond the recording's pace, and matched loosely, has company: words the text
# does not have were said next to it (a speaker's own lengthening of a word matches closely).
STRETCHED = 1.7
STRETCHED_DISTANCE = 3.6
STRETCHED_WORD_RATIO = 1.4
EXTRA_SPEECH_FRAMES = 35  # a stretch of recorded speech this long (350 ms) matched to no synthetic speech
MOST_WARNINGS = 10  # a take with more places of doubt gets the first ones and a count of the rest
OTHER_TEXT_SHARE = 0.5  # more than this share of the words unmatched: the recording reads another text


def _word_frames(utterance: Utterance, phone_events: tuple[PhoneEvent, ...], lead: int) -> np.ndarray:
    """Each word's first and last synthetic frame (padded indices); -1 for a word the engine did not voice."""
    spans = np.full((len(utterance.words), 2), -1, np.int64)
    for event in phone_events:
        first = lead + int(event.start * ANALYSIS_RATE / HOP)
        last = lead + int(np.ceil(event.end * ANALYSIS_RATE / HOP))
        span = spans[event.word_index]
        span[0] = first if span[0] < 0 else min(span[0], first)
        span[1] = max(span[1], last)
    return spans


def judge(
    utterance: Utterance, phone_events: tuple[PhoneEvent, ...], warp: TimeWarp, fit: Fit, path: Path
) -> tuple[tuple[PhraseMatch, ...], tuple[str, ...]]:
    """A confidence per phrase; warnings naming the words where recording and text part."""
    frames = len(fit.synthetic_speech)
    spoken = fit.synthetic_speech[fit.path_x]
    per_frame_count = np.bincount(fit.path_x[spoken], minlength=frames)
    per_frame_sum = np.bincount(fit.path_x[spoken], weights=fit.distances[spoken], minlength=frames)
    spans = _word_frames(utterance, phone_events, fit.lead)
    word_distance = np.full(len(utterance.words), np.nan)
    pace = np.full(len(utterance.words), np.nan)  # recorded length / synthetic length
    for index, (first, last) in enumerate(spans):
        if first < 0:
            continue
        count = per_frame_count[first : last + 1].sum()
        word_distance[index] = per_frame_sum[first : last + 1].sum() / count if count else UNMATCHED_DISTANCE
        synthetic = frame_seconds(np.array([first, last]), fit.lead)
        recorded = warp(synthetic)
        pace[index] = (recorded[1] - recorded[0]) / max(synthetic[1] - synthetic[0], 1e-3)
    pace /= np.nanmedian(pace)
    typical = np.nanmedian(word_distance)
    unmatched = (word_distance > max(UNMATCHED_WORD_DISTANCE, UNMATCHED_WORD_RATIO * typical)) | (
        pace < SQUEEZED
    )
    loose = word_distance > max(STRETCHED_DISTANCE, STRETCHED_WORD_RATIO * typical)
    crowded = (pace > STRETCHED) & loose & ~unmatched
    phrases = _phrases(utterance, warp, spans, fit, word_distance, per_frame_count, per_frame_sum)
    texts = [word.text for word in utterance.words]
    distance = float(fit.distances[spoken].mean())
    if fit.order_ratio > OTHER_TEXT_ORDER_RATIO and (
        distance > OTHER_TEXT_DISTANCE or unmatched.mean() > OTHER_TEXT_SHARE
    ):
        unheard = np.flatnonzero(unmatched | (word_distance > OTHER_TEXT_DISTANCE))
        raise AudioError(
            f"recording {path} does not read this text: {_word_list(texts, unheard)} "
            f"({unheard.size} of its {len(texts)} words) are not heard in it; check that the recording "
            "and the text belong together"
        )
    warnings = [
        "the recording fits this text only loosely (it may read another text, or be very noisy or "
        "reverberant); check that it reads this text: the face follows it as well as it can"
    ] * (fit.order_ratio > DOUBTFUL_ORDER_RATIO or distance > DOUBTFUL_DISTANCE)
    warnings += [
        f"the recording seems not to say {_word_list(texts, run)} (word {run[0] + 1} of the text); "
        "check the recording there: the face is timed on the rest"
        for run in _consecutive(np.flatnonzero(unmatched))
    ]
    stalls = _stalls(fit, spans)
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


def _phrases(
    utterance: Utterance,
    warp: TimeWarp,
    spans: np.ndarray,
    fit: Fit,
    word_distance: np.ndarray,
    per_frame_count: np.ndarray,
    per_frame_sum: np.ndarray,
) -> tuple[PhraseMatch, ...]:
    """Words between pauses, each phrase with its place in the recording and its confidence."""
    starts = [index for index, word in enumerate(utterance.words) if index == 0 or word.pause_before > 0]
    phrases = []
    for first, stop in zip(starts, [*starts[1:], len(utterance.words)], strict=True):
        voiced = [index for index in range(first, stop) if spans[index, 0] >= 0]
        if not voiced:
            continue
        begin, end = spans[voiced[0], 0], spans[voiced[-1], 1]
        count = per_frame_count[begin : end + 1].sum()
        distance = per_frame_sum[begin : end + 1].sum() / count if count else UNMATCHED_DISTANCE
        confidence = (UNMATCHED_DISTANCE - distance) / (UNMATCHED_DISTANCE - MATCHED_DISTANCE)
        recorded = warp(frame_seconds(np.array([begin, end]), fit.lead))
        phrases.append(
            PhraseMatch(
                first, stop - first, float(recorded[0]), float(recorded[1]), float(np.clip(confidence, 0, 1))
            )
        )
    return tuple(phrases)


def _stalls(fit: Fit, spans: np.ndarray) -> list[tuple[int, int, float]]:
    """Recorded speech the synthetic speech does not advance through, between two words of the text.

    Each as (word before, word after, seconds into the recording). Before the first word or after the
    last, a breath or a noise is as likely as a word, so those are left alone.
    """
    recorded_frames = len(fit.recorded_speech)
    window = EXTRA_SPEECH_FRAMES
    if recorded_frames <= window:
        return []
    matched = np.zeros(recorded_frames, np.int64)
    matched[fit.path_y] = fit.path_x  # the path is monotone: the last synthetic frame matched to each
    progress = np.cumsum(fit.synthetic_speech)[matched]  # synthetic speech frames passed
    speech_share = np.convolve(fit.recorded_speech, np.ones(window), "valid")[:-1] / window
    advance = progress[window:] - progress[:-window]
    stalled = (advance <= window // 8) & (speech_share >= 0.8)
    firsts = spans[:, 0]
    found = []
    for start, _ in runs(stalled):
        at = matched[start + window // 2]
        before = np.flatnonzero((firsts >= 0) & (firsts <= at))
        after = np.flatnonzero(firsts > at)
        if before.size and after.size:
            found.append((int(before[-1]), int(after[0]), float(frame_seconds(start + window // 2))))
    return found


def _consecutive(indices: np.ndarray) -> list[np.ndarray]:
    if indices.size == 0:
        return []
    return np.split(indices, np.flatnonzero(np.diff(indices) > 1) + 1)


def _word_list(texts: list[str], indices: np.ndarray, shown: int = 6) -> str:
    names = [repr(texts[index]) for index in indices[:shown]]
    more = f" and {indices.size - shown} more" if indices.size > shown else ""
    return ", ".join(names) + more
