"""How well a recording says the text: a confidence per phrase, the refusal of another text, warnings.

Judged by ranks, not distances: a live room, a noisy flat, a voice further from eSpeak's raise every
feature distance, but the synthetic sound matched to a recorded frame stays among the closest of all
the text's sounds to it when the recording says the text. Each recorded speech frame on the DTW path
gets the share of a sample of the text's synthetic speech frames that lie closer to it than its match
(match_ranks): near 0 for the same text in any voice or room, about a quarter for another text.
A word's rank is the mean over its frames; with how the word's length compares with the recording's
pace and recorded speech the synthetic speech does not advance through, they say which words the
recording leaves out or adds. Only a take most of whose words are unmatched, and whose frames rank as
another text's do, is refused.
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
    """The DTW path and how well each step of it matches, for judging how well the recording says the text."""

    path_x: np.ndarray
    path_y: np.ndarray
    ranks: np.ndarray  # per step: match_ranks (NaN where synthetic or recorded speech is silent)
    synthetic_speech: np.ndarray
    recorded_speech: np.ndarray
    recorded_under_speech: np.ndarray  # dB under the recording's loud frames, per frame
    lead: int
    order_ratio: float  # the path's cost over the cost with the text's sounds in reverse order


REFERENCE_FRAMES = 64  # synthetic speech frames each recorded frame's match is ranked among
# Measured with scripts/measure_recordings.py's takes on the tuning sentences and voices (every condition):
# the mean rank of a take of the same text mostly under 0.06 (p99 0.09), of another text 0.11-0.37; of a
# word the take says under 0.07 (p95; a person's take 0.28), of a word it leaves out 0.27-0.43 (p5-p50).
MATCHED_RANK = 0.05  # a phrase ranking this well has confidence 1
UNMATCHED_RANK = 0.30  # ... and this badly, 0
# A word is not in the recording when it ranks worse than UNMATCHED_WORD_RANK and the recording gives it
# less than SHORTENED of its pace, or ranks worse than LOST_WORD_RANK, or gets less than SQUEEZED.
UNMATCHED_WORD_RANK = 0.30
SHORTENED = 0.7
LOST_WORD_RANK = 0.55
SQUEEZED = 0.25
# A take ranking worse than this, whose sounds fit it in their order little better than reversed (the
# path's cost over that with the text's sounds in reverse order), reads another text; one ranking worse
# than LOOSE_RANK fits it only loosely. On the tuning takes (768 of the same text, 768 of another, every
# condition of measure_recordings.py): another text refused in 672, warned in the rest; the same text
# refused in none, warned as loose in none.
OTHER_TEXT_RANK = 0.15
OTHER_TEXT_ORDER_RATIO = 0.88
# A take ranking worse than this reads another text plainly, whatever its order: twice the worst take of
# the text on the tuning takes (0.096, a person's take; held-out voices: 0.085, a reverberant one).
PLAINLY_OTHER_TEXT_RANK = 0.2
LOOSE_RANK = 0.12
# A word stretched this much beyond the recording's pace, and ranking this badly, has company: words
# the text does not have were said next to it (a speaker's own lengthening of a word matches closely).
STRETCHED = 1.7
STRETCHED_RANK = 0.15
# A stretch of recorded speech this long (300 ms) that the synthetic speech does not advance through,
# at least half of it within LOUD_UNDER_SPEECH_DB of the speaker's loud frames (not a voice in the
# background, not a room's tail), is speech the text lacks.
EXTRA_SPEECH_FRAMES = 30
LOUD_UNDER_SPEECH_DB = 15.0
MOST_WARNINGS = 10  # a take with more places of doubt gets the first ones and a count of the rest


def match_ranks(
    x: np.ndarray,
    y: np.ndarray,
    path_x: np.ndarray,
    path_y: np.ndarray,
    synthetic_speech: np.ndarray,
    recorded_speech: np.ndarray,
) -> np.ndarray:
    """Per step of the path: the share of REFERENCE_FRAMES synthetic speech frames closer to y's frame.

    NaN where either frame is silence. The reference frames are a fixed sample over the whole text.
    """
    ranks = np.full(path_x.size, np.nan)
    both = np.flatnonzero(synthetic_speech[path_x] & recorded_speech[path_y])
    spoken = np.flatnonzero(synthetic_speech)
    if both.size == 0 or spoken.size == 0:
        return ranks
    reference = x[np.random.default_rng(0).choice(spoken, REFERENCE_FRAMES)].astype(np.float64)
    reference_norms = (reference**2).sum(axis=1)
    for begin in range(0, both.size, 1 << 14):
        steps = both[begin : begin + (1 << 14)]
        recorded = y[path_y[steps]].astype(np.float64)
        matched = ((x[path_x[steps]] - recorded) ** 2).sum(axis=1)
        # Squared distances to the references by |a|^2 + |b|^2 - 2ab: one matrix product.
        others = (recorded**2).sum(axis=1)[:, None] + reference_norms[None, :] - 2 * recorded @ reference.T
        ranks[steps] = (others < matched[:, None]).mean(axis=1)
    return ranks


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
    """Per word: its frames' first and last (word_frames), mean rank (NaN if unvoiced), and pace.

    The pace is the word's recorded length over its synthetic length, over the median word's: a
    pause put before a word (a hesitation) belongs to neither word.
    """
    spans = word_frames(utterance, phone_events, fit.lead)
    count = len(utterance.words)
    frames = len(fit.synthetic_speech)
    valid = ~np.isnan(fit.ranks)
    per_frame_count = np.bincount(fit.path_x[valid], minlength=frames)
    per_frame_sum = np.bincount(fit.path_x[valid], weights=fit.ranks[valid], minlength=frames)
    ranks = np.full(count, np.nan)
    starts, ends = np.full(count, np.inf), np.full(count, -np.inf)
    for event in phone_events:
        starts[event.word_index] = min(starts[event.word_index], event.start)
        ends[event.word_index] = max(ends[event.word_index], event.end)
    for index, (first, last) in enumerate(spans):
        if first >= 0:
            matched = per_frame_count[first : last + 1].sum()
            ranks[index] = per_frame_sum[first : last + 1].sum() / matched if matched else 1.0
    voiced = spans[:, 0] >= 0
    pace = np.full(count, np.nan)
    recorded = warp(starts[voiced]), warp(ends[voiced] - JUMP)
    pace[voiced] = (recorded[1] - recorded[0]) / np.maximum(ends[voiced] - starts[voiced], 1e-3)
    return spans, ranks, pace / np.nanmedian(pace)


def judge(
    utterance: Utterance, phone_events: tuple[PhoneEvent, ...], warp: TimeWarp, fit: Fit, path: Path
) -> tuple[tuple[PhraseMatch, ...], tuple[str, ...]]:
    """A confidence per phrase; warnings naming the words where recording and text part."""
    spans, ranks, pace = word_scores(utterance, phone_events, warp, fit)
    unmatched = (
        ((ranks > UNMATCHED_WORD_RANK) & (pace < SHORTENED)) | (ranks > LOST_WORD_RANK) | (pace < SQUEEZED)
    )
    crowded = (pace > STRETCHED) & (ranks > STRETCHED_RANK) & ~unmatched
    phrases = _phrases(utterance, warp, spans, fit)
    texts = [word.text for word in utterance.words]
    take_rank = float(np.nanmean(fit.ranks)) if (~np.isnan(fit.ranks)).any() else 1.0
    voiced = np.flatnonzero(spans[:, 0] >= 0)
    worst = voiced[np.argsort(-ranks[voiced], kind="stable")]
    order_fits_little = fit.order_ratio > OTHER_TEXT_ORDER_RATIO
    if (take_rank > OTHER_TEXT_RANK and order_fits_little) or take_rank > PLAINLY_OTHER_TEXT_RANK:
        unheard = np.flatnonzero(ranks > OTHER_TEXT_RANK)
        unheard = unheard if unheard.size else np.sort(worst[: max(1, worst.size // 2)])
        raise AudioError(
            f"recording {path} does not read this text: {_word_list(texts, unheard)} "
            f"({unheard.size} of its {len(texts)} words) are not heard in it; check that the recording "
            "and the text belong together"
        )
    warnings = [
        "the recording fits this text only loosely (it may read another text, or be very noisy or "
        f"reverberant), worst at {_word_list(texts, np.sort(worst[:3]))}; check that it reads this text: "
        "the face follows it as well as it can"
    ] * (take_rank > LOOSE_RANK)
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


def _phrases(utterance: Utterance, warp: TimeWarp, spans: np.ndarray, fit: Fit) -> tuple[PhraseMatch, ...]:
    """Words between pauses, each phrase with its place in the recording and its confidence."""
    starts = [index for index, word in enumerate(utterance.words) if index == 0 or word.pause_before > 0]
    valid = ~np.isnan(fit.ranks)
    phrases = []
    for first, stop in zip(starts, [*starts[1:], len(utterance.words)], strict=True):
        voiced = [index for index in range(first, stop) if spans[index, 0] >= 0]
        if not voiced:
            continue
        begin, end = spans[voiced[0], 0], spans[voiced[-1], 1]
        steps = valid & (fit.path_x >= begin) & (fit.path_x <= end)
        rank = float(fit.ranks[steps].mean()) if steps.any() else 1.0
        confidence = (UNMATCHED_RANK - rank) / (UNMATCHED_RANK - MATCHED_RANK)
        recorded = warp(frame_seconds(np.array([begin, end]), fit.lead))
        phrases.append(
            PhraseMatch(
                first, stop - first, float(recorded[0]), float(recorded[1]), float(np.clip(confidence, 0, 1))
            )
        )
    return tuple(phrases)


def _stalls(fit: Fit, spans: np.ndarray) -> list[tuple[int, int, float]]:
    """Loud recorded speech the synthetic speech does not advance through, between two words of the text.

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
    loud = fit.recorded_speech & (fit.recorded_under_speech <= LOUD_UNDER_SPEECH_DB)
    box = np.ones(window) / window
    speech_share = np.convolve(fit.recorded_speech, box, "valid")[:-1]
    loud_share = np.convolve(loud, box, "valid")[:-1]
    advance = progress[window:] - progress[:-window]
    stalled = (advance <= window // 8) & (speech_share >= 0.8) & (loud_share >= 0.5)
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
