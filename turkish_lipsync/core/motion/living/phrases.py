"""Where the speech pauses, where its phrases begin and end, and which syllables carry a pitch accent.

With audio (synthesised or the user's recording) the pauses are the audio's own silences and the accents
are the syllables whose pitch stands out of their phrase; table timing has no audio, so the pauses come
from the timeline's gaps and the accents from Turkish word stress (most words stress their last syllable;
emphasised words always).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...base.model import Timeline
from .prosody import Prosody

MIN_PAUSE = 0.18  # seconds of silence that count as a pause (stop closures are shorter)
MIN_GAP = 0.15  # seconds between phones that count as a pause when there is no audio
ACCENT_RISE = 1.0  # semitones a syllable's pitch must rise above its phrase's median to be accented
ACCENT_FULL = 4.0  # semitones of rise that make an accent full strength
STRESS_STRENGTH = 0.45  # accent strength of a word's stressed syllable read from the text alone


@dataclass(frozen=True)
class Accent:
    time: float  # seconds: the syllable's pitch peak (its middle without audio)
    strength: float  # 0..1
    rise: float  # semitones above the phrase's median (0 without audio)


@dataclass(frozen=True, eq=False)
class SpeechStructure:
    """The speech's pauses, phrases and accents, and its prosody where there is audio."""

    duration: float
    pauses: tuple[tuple[float, float], ...]  # (start, end) seconds, leading and trailing silence included
    phrases: tuple[tuple[float, float], ...]  # (start, end) seconds of speech between pauses
    accents: tuple[Accent, ...]
    prosody: Prosody | None
    hesitations: tuple[tuple[float, float], ...] = ()  # (start, end) seconds of hesitations said aloud

    def in_pause(self, times: np.ndarray, margin: float = 0.0) -> np.ndarray:
        return self.pause_length_at(times, margin) > 0

    def pause_length_at(self, times: np.ndarray, margin: float = 0.0) -> np.ndarray:
        """Seconds of the pause each time falls in (0 while speaking); pauses widened by margin."""
        times = np.asarray(times, np.float64)
        if not self.pauses:
            return np.zeros(times.shape)
        starts = np.array([start for start, _ in self.pauses]) - margin
        ends = np.array([end for _, end in self.pauses]) + margin
        index = np.clip(np.searchsorted(starts, times, side="right") - 1, 0, len(starts) - 1)
        inside = (times >= starts[index]) & (times <= ends[index])
        return np.where(inside, ends[index] - starts[index] - 2 * margin, 0.0)


def speech_structure(timeline: Timeline, prosody: Prosody | None) -> SpeechStructure:
    duration = timeline.duration
    if prosody is not None and np.isfinite(prosody.f0).any():
        pauses = _audio_pauses(prosody, duration)
    else:
        prosody = None if prosody is None or not (~prosody.silent()).any() else prosody
        pauses = _audio_pauses(prosody, duration) if prosody is not None else _timeline_pauses(timeline)
    phrases = _phrases(pauses, duration)
    syllables, last_syllables = _syllable_spans(timeline)
    if prosody is not None and np.isfinite(prosody.f0).any():
        accents = _pitch_accents(syllables, phrases, prosody)
    else:
        accents = _stress_accents(syllables, last_syllables, timeline)
    hesitations = tuple((h.start, h.end) for h in timeline.hesitations)
    return SpeechStructure(duration, tuple(pauses), tuple(phrases), tuple(accents), prosody, hesitations)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last + 1) of every run of True."""
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True))


def _audio_pauses(prosody: Prosody, duration: float) -> list[tuple[float, float]]:
    silent = prosody.silent()
    pauses = []
    for first, last in _runs(silent):
        start, end = first / prosody.rate, min(last / prosody.rate, duration)
        at_edge = first == 0 or last >= silent.size
        if end - start >= MIN_PAUSE or (at_edge and end > start):
            pauses.append((start, end))
    if silent.size / prosody.rate < duration:  # the timeline's final pause outlasts the audio
        tail = silent.size / prosody.rate
        if pauses and abs(pauses[-1][1] - tail) < 1e-6:
            pauses[-1] = (pauses[-1][0], duration)
        else:
            pauses.append((tail, duration))
    return pauses


def _timeline_pauses(timeline: Timeline) -> list[tuple[float, float]]:
    phones = sorted(timeline.phones, key=lambda p: p.start)
    if not phones:
        return [(0.0, timeline.duration)]
    pauses = [(0.0, phones[0].start)] if phones[0].start > 0 else []
    reached = phones[0].end
    for phone in phones[1:]:
        if phone.start - reached >= MIN_GAP:
            pauses.append((reached, phone.start))
        reached = max(reached, phone.end)
    if timeline.duration > reached:
        pauses.append((reached, timeline.duration))
    return pauses


def _phrases(pauses: list[tuple[float, float]], duration: float) -> list[tuple[float, float]]:
    phrases, cursor = [], 0.0
    for start, end in pauses:
        if start - cursor > 0.05:
            phrases.append((cursor, start))
        cursor = max(cursor, end)
    if duration - cursor > 0.05:
        phrases.append((cursor, duration))
    return phrases


def _syllable_spans(timeline: Timeline) -> tuple[np.ndarray, np.ndarray]:
    """(syllables, 2) start and end seconds of each spoken syllable in order, and whether each is its word's
    last."""
    starts, ends, words = [], [], []
    last_key, end = None, -np.inf
    for phone in sorted(timeline.phones, key=lambda p: p.start):
        key = (phone.word_index, phone.syllable)
        if key == last_key and phone.start - end < 0.1:
            end = ends[-1] = max(end, phone.end)
        else:
            starts.append(phone.start)
            end = phone.end
            ends.append(end)
            words.append(phone.word_index)
            last_key = key
    words = np.array(words, int)
    last = np.ones(words.size, bool)  # the next syllable is another word's (none follows the last)
    last[:-1] = words[1:] != words[:-1]
    return np.array([starts, ends], np.float64).T.reshape(-1, 2), last


def _pitch_accents(spans: np.ndarray, phrases, prosody: Prosody) -> list[Accent]:
    semitones = prosody.semitones()
    rate = prosody.rate
    finite = np.isfinite(semitones)
    # Each syllable's highest voiced frame, all syllables at once (a syllable spans at most a few frames).
    first = np.ceil(spans[:, 0] * rate).astype(int)
    last = np.maximum(np.ceil(np.maximum(spans[:, 1], spans[:, 0] + 1 / rate) * rate).astype(int), first + 1)
    width = int((last - first).max(initial=1))
    index = np.minimum(first[:, None] + np.arange(width), semitones.size - 1)
    values = np.where((index < last[:, None]) & finite[index], semitones[index], -np.inf)
    best = values.argmax(axis=1)
    rows = np.arange(len(values))
    peak = values[rows, best]
    voiced = np.isfinite(peak)
    time = np.where(voiced, index[rows, best] / rate, spans.mean(axis=1))
    if not phrases or not voiced.any():
        return []
    baselines = _phrase_medians(semitones, phrases, rate)
    phrase_starts = np.array([start for start, _ in phrases])
    phrase_ends = np.array([end for _, end in phrases])
    phrase = np.clip(np.searchsorted(phrase_starts, time + 0.05, side="right") - 1, 0, len(phrases) - 1)
    inside = (phrase_starts[phrase] - 0.05 <= time) & (time <= phrase_ends[phrase] + 0.05)
    rise = peak - baselines[phrase]
    # a peak no lower than its voiced neighbours' (a syllable's accent is where its phrase's pitch tops)
    padded = np.concatenate([[-np.inf], np.where(voiced, peak, -np.inf), [-np.inf]])
    highest = np.maximum(padded[:-2], padded[2:]) <= peak
    chosen = voiced & inside & np.isfinite(rise) & (rise >= ACCENT_RISE) & highest
    strength = np.clip(rise / ACCENT_FULL, 0.0, 1.0)
    return [Accent(float(time[k]), float(strength[k]), float(rise[k])) for k in np.flatnonzero(chosen)]


def _phrase_medians(values: np.ndarray, phrases, rate: float) -> np.ndarray:
    """The median of each phrase's finite values (NaN for a phrase without one), all phrases at once."""
    bounds = [(int(start * rate), min(int(np.ceil(end * rate)) + 1, values.size)) for start, end in phrases]
    frames = np.concatenate([np.zeros(0, int), *(np.arange(first, last) for first, last in bounds)])
    phrase = np.repeat(np.arange(len(bounds)), [max(last - first, 0) for first, last in bounds])
    finite = np.isfinite(values[frames])
    frames, phrase = frames[finite], phrase[finite]
    medians = np.full(len(bounds), np.nan)
    if not frames.size:
        return medians
    ordered = values[frames][np.lexsort((values[frames], phrase))]  # by phrase, then by value
    counts = np.bincount(phrase, minlength=len(bounds))
    first = np.cumsum(counts) - counts
    found = counts > 0
    low = ordered[(first + (counts - 1) // 2)[found]]
    high = ordered[(first + counts // 2)[found]]
    medians[found] = (low + high) / 2
    return medians


def _stress_accents(spans: np.ndarray, lasts: np.ndarray, timeline: Timeline) -> list[Accent]:
    emphasised = timeline.emphases
    accents = []
    for (start, end), last in zip(spans.tolist(), lasts.tolist(), strict=True):
        middle = (start + end) / 2
        strong = any(s <= middle <= e for s, e in emphasised)
        if last or strong:
            accents.append(Accent(middle, 1.0 if strong else STRESS_STRENGTH, 0.0))
    return accents
