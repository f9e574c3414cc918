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

import numpy as np

from ..base.errors import AudioError
from ..base.model import Utterance
from .aligner_settings import DEFAULT_ALIGNER, AlignerSettings
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
    hesitations: np.ndarray  # per recorded frame: the class of a hesitation's sound a pause holds (-1: none)
    synthetic_speech: np.ndarray
    recorded_speech: np.ndarray  # the recorded frames judged: speech that no pause holds
    recorded_under_speech: np.ndarray  # dB under the recording's loud frames, per frame
    lead: int
    order_ratio: float  # the path's cost over the cost with the text's sounds in reverse order
    hesitation_drawn_in: np.ndarray  # per word: frames of a hesitation said aloud drawn into it (LetterFit)


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
    utterance: Utterance,
    phone_events: tuple[PhoneEvent, ...],
    warp: TimeWarp,
    fit: Fit,
    settings: AlignerSettings = DEFAULT_ALIGNER,
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
    # A short word has few frames to judge it by: its mismatch leans toward the take's by word_prior_frames
    # (a person's "a", "ve", "bu" are said in a breath, and the network hears little of them).
    prior = settings.word_prior_frames * take_mismatch(fit, settings)
    mismatch = np.where(voiced, (sums + prior) / (frames + settings.word_prior_frames), np.nan)
    starts, ends = _word_times(count, phone_events)
    pace = np.full(count, np.nan)
    recorded = _recorded_times(starts[voiced], ends[voiced], warp)
    pace[voiced] = (recorded[1] - recorded[0]) / np.maximum(ends[voiced] - starts[voiced], 1e-3)
    return spans, mismatch, pace / np.nanmedian(pace)


def _word_times(count: int, phone_events: tuple[PhoneEvent, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Each word's synthetic start and end (seconds; inf and -inf for a word the engine did not voice)."""
    starts, ends = np.full(count, np.inf), np.full(count, -np.inf)
    for event in phone_events:
        starts[event.word_index] = min(starts[event.word_index], event.start)
        ends[event.word_index] = max(ends[event.word_index], event.end)
    return starts, ends


def _recorded_times(starts: np.ndarray, ends: np.ndarray, warp: TimeWarp) -> tuple[np.ndarray, np.ndarray]:
    """Synthetic spans' recorded starts and ends (an end taken before the warp's jump over a pause)."""
    return warp(starts), warp(ends - JUMP)


def take_mismatch(fit: Fit, settings: AlignerSettings = DEFAULT_ALIGNER) -> float:
    """The mismatch of the judged recorded frames (the speech no pause holds) in which the network hears a
    letter (where it hears silence in speech, it has no opinion on which letter): 0 is a perfect fit."""
    judged = fit.recorded_speech[: fit.mismatch.size] & fit.heard_letters
    return float(fit.mismatch[judged].mean()) if judged.any() else float(settings.unmatched)


def judge(
    utterance: Utterance,
    phone_events: tuple[PhoneEvent, ...],
    warp: TimeWarp,
    fit: Fit,
    name: str,
    clipped: str = "",
    settings: AlignerSettings = DEFAULT_ALIGNER,
) -> tuple[tuple[PhraseMatch, ...], tuple[str, ...]]:
    """A confidence per phrase; warnings naming the words where recording and text part. `clipped` names
    the take's clipping (audio.clipping), given as the likelier cause where the take fits loosely."""
    spans, mismatch, pace = word_scores(utterance, phone_events, warp, fit, settings)
    take = take_mismatch(fit, settings)
    phrases = _phrases(utterance, phone_events, warp, spans, fit, settings)
    texts = [word.text for word in utterance.words]
    voiced = np.flatnonzero(spans[:, 0] >= 0)
    worst = voiced[np.argsort(-mismatch[voiced], kind="stable")]
    # Both sides bound the evidence: a word shouted for a second is still one word's letters to go by.
    spoken = min(int(fit.recorded_speech[: fit.mismatch.size].sum()), int(fit.synthetic_speech.sum()))
    evidence = spoken >= settings.refusal_evidence_frames
    if evidence:
        _refuse_another_text(texts, mismatch, voiced, worst, take, fit.order_ratio, name, clipped, settings)
    causes = (
        f"{clipped}; or it may read another text"
        if clipped
        else "it may read another text, or be very noisy or reverberant"
    )
    warnings = [
        f"the recording fits this text only loosely ({causes}), worst at "
        f"{_word_list(texts, np.sort(worst[:3]))}; check that it reads this text: the face follows it as "
        "well as it can"
    ] * loosely_fitting(take, fit.order_ratio, evidence, _is_list(phrases, settings), settings)
    warnings += _word_warnings(texts, spans, mismatch, pace, take, warp, fit, settings)
    if len(warnings) > settings.most_warnings:
        more = len(warnings) - settings.most_warnings + 1
        warnings[settings.most_warnings - 1 :] = [
            f"and {more} more places where the recording and the text part"
        ]
    return phrases, tuple(warnings)


def _refuse_another_text(
    texts: list[str],
    mismatch: np.ndarray,
    voiced: np.ndarray,
    worst: np.ndarray,
    take: float,
    order_ratio: float,
    name: str,
    clipped: str,
    settings: AlignerSettings,
) -> None:
    """Refuse a take (one with evidence enough) whose frames fit as another text's do, its sounds fitting
    the text's order little better than the reverse or its fit plainly another text's, unless its best
    words are heard. mismatch: per word (NaN where the engine voiced none); worst: the voiced words, the
    worst fitting first."""
    order_fits_little = order_ratio > settings.other_text_order_ratio
    words_heard = np.percentile(mismatch[voiced], 25) < settings.words_heard if voiced.size else False
    other_text = (take > settings.other_text and order_fits_little) or take > settings.plainly_other_text
    if other_text and not words_heard:
        unheard = np.flatnonzero(mismatch > settings.other_text)
        unheard = unheard if unheard.size else np.sort(worst[: max(1, worst.size // 2)])
        raise AudioError(
            f"recording {name} does not read this text: {_word_list(texts, unheard)} "
            f"({unheard.size} of its {len(texts)} words) are not heard in it; check that the recording "
            "and the text belong together" + (f" ({clipped})" if clipped else "")
        )


def _word_warnings(
    texts: list[str],
    spans: np.ndarray,
    mismatch: np.ndarray,
    pace: np.ndarray,
    take: float,
    warp: TimeWarp,
    fit: Fit,
    settings: AlignerSettings,
) -> list[str]:
    """The places where recording and text part: words it seems not to say (their mismatch high and
    their time short, or far above the take's), speech it adds between two words (_stalls), and words
    drawn out far past the take's pace that fit their letters poorly."""
    unmatched = ((mismatch > settings.unmatched_word) & (pace < settings.shortened)) | (
        mismatch > take + settings.lost_word
    )
    crowded = (pace > settings.stretched) & (mismatch > settings.stretched_mismatch) & ~unmatched
    warnings = [
        f"the recording seems not to say {_word_list(texts, run)} (word {run[0] + 1} of the text); "
        "check the recording there: the face is timed on the rest"
        for run in _consecutive(np.flatnonzero(unmatched))
    ]
    stalls = _stalls(fit, settings)
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
    return warnings


def loosely_fitting(
    take: float,
    order_ratio: float,
    evidence: bool,
    is_list: bool,
    settings: AlignerSettings = DEFAULT_ALIGNER,
) -> bool:
    """Whether a take of this mismatch and order ratio fits its text only loosely (see loose)."""
    if not evidence:
        return take > settings.short_loose
    return take + settings.order_weight * (order_ratio - settings.own_text_order_ratio) > (
        settings.list_loose if is_list else settings.loose
    )


def _is_list(phrases: tuple[PhraseMatch, ...], settings: AlignerSettings) -> bool:
    """Whether the text is a list: list_items phrases or more of a word or two each (see list_loose)."""
    return len(phrases) >= settings.list_items and all(phrase.word_count <= 2 for phrase in phrases)


def _phrases(
    utterance: Utterance,
    phone_events: tuple[PhoneEvent, ...],
    warp: TimeWarp,
    spans: np.ndarray,
    fit: Fit,
    settings: AlignerSettings,
) -> tuple[PhraseMatch, ...]:
    """Words between pauses, the text's or the recording's (list_pause), each phrase with its place in
    the recording and its confidence."""
    starts, _ = _phrase_starts(utterance, phone_events, warp, settings)
    phrases = []
    for first, stop in zip(starts, [*starts[1:], len(utterance.words)], strict=True):
        voiced = [index for index in range(first, stop) if spans[index, 0] >= 0]
        if not voiced:
            continue
        begin, end = spans[voiced[0], 0], spans[voiced[-1], 1]
        frames = (fit.frame_words >= first) & (fit.frame_words < stop) & fit.heard_letters
        mismatch = float(fit.mismatch[frames].mean()) if frames.any() else settings.unmatched
        confidence = (settings.unmatched - mismatch) / (settings.unmatched - settings.matched)
        recorded = warp(frame_seconds(np.array([begin, end]), fit.lead))
        phrases.append(
            PhraseMatch(
                first, stop - first, float(recorded[0]), float(recorded[1]), float(np.clip(confidence, 0, 1))
            )
        )
    return tuple(phrases)


def pauses_read_as_list(
    utterance: Utterance,
    phone_events: tuple[PhoneEvent, ...],
    warp: TimeWarp,
    settings: AlignerSettings = DEFAULT_ALIGNER,
) -> set[int]:
    """The words the recording pauses before (list_pause) where the text runs on, when with the text's own
    pauses they make it a list as read (list_items phrases or more, none longer than two words): a list
    typed with spaces only, read item by item. Else none."""
    starts, marked = _phrase_starts(utterance, phone_events, warp, settings)
    lengths = np.diff([*starts, len(utterance.words)])
    if len(starts) < settings.list_items or lengths.max() > 2:
        return set()
    return set(starts) - marked


def _phrase_starts(
    utterance: Utterance, phone_events: tuple[PhoneEvent, ...], warp: TimeWarp, settings: AlignerSettings
) -> tuple[list[int], set[int]]:
    """The words phrases start at, in order (the first, those the text pauses before, those the recording
    pauses before for list_pause), and those of them that the text marks."""
    marked = {index for index, word in enumerate(utterance.words) if index == 0 or word.pause_before > 0}
    return sorted(marked | _recorded_pauses(utterance, phone_events, warp, settings)), marked


def _recorded_pauses(
    utterance: Utterance, phone_events: tuple[PhoneEvent, ...], warp: TimeWarp, settings: AlignerSettings
) -> set[int]:
    """The words the recording pauses before for list_pause or longer (after the word voiced before)."""
    starts, ends = _word_times(len(utterance.words), phone_events)
    voiced = np.flatnonzero(np.isfinite(starts))
    if voiced.size < 2:
        return set()
    recorded_starts, recorded_ends = _recorded_times(starts[voiced], ends[voiced], warp)
    gaps = recorded_starts[1:] - recorded_ends[:-1]
    return {int(index) for index in voiced[1:][gaps >= settings.list_pause]}


def _stalls(fit: Fit, settings: AlignerSettings) -> list[tuple[int, int, float]]:
    """Loud recorded speech that the letters' alignment leaves to a pause, between two words of the text.

    Each as (word before, word after, seconds into the recording). Before the first word or after the
    last, a breath or a noise is as likely as a word, so those are left alone; so is a hesitation's sound.
    """
    loud = fit.recorded_speech & (fit.recorded_under_speech <= settings.loud_under_speech_db)
    unplaced = loud & (fit.frame_words < 0) & (fit.hesitations < 0)
    placed = np.flatnonzero(fit.frame_words >= 0)
    found = []
    for start, stop in runs(unplaced):
        if stop - start < settings.extra_speech_frames or placed.size == 0:
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
