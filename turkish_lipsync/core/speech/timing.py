"""Phone timing without an engine (Table 5.4) and the Timeline built from per-letter times."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np

from ..base.data import DATA_DIR, load_table, require
from ..base.errors import DataError
from ..base.model import EmotionSpan, Hesitation, Phone, Timeline, Utterance, WordSpan
from ..text.syllables import VOWELS

SOFT_G = "ğ"


@dataclass(frozen=True)
class DurationTable:
    letters: dict[str, float]  # seconds
    lengthened_before_soft_g: dict[str, float]  # seconds
    soft_g_after_vowel: float
    geminate_factor: float
    silence: float
    lead_in: float


@cache
def duration_table() -> DurationTable:
    table = load_table("durations")
    letters = require(table, "letters", dict, "durations")
    lengthened = require(table, "lengthened_before_soft_g", dict, "durations")
    rules = require(table, "rules", dict, "durations")
    for section, values in (("letters", letters), ("lengthened_before_soft_g", lengthened), ("rules", rules)):
        for key, value in values.items():
            if not isinstance(value, int | float) or value <= 0:
                raise DataError(f"{DATA_DIR / 'durations.toml'}: [{section}] {key} must be a positive number")
    try:
        return DurationTable(
            letters={k: v / 1000 for k, v in letters.items()},
            lengthened_before_soft_g={k: v / 1000 for k, v in lengthened.items()},
            soft_g_after_vowel=rules["soft_g_after_vowel_ms"] / 1000,
            geminate_factor=float(rules["geminate_factor"]),
            silence=rules["silence_ms"] / 1000,
            lead_in=rules["lead_in_ms"] / 1000,
        )
    except KeyError as missing:
        raise DataError(f"{DATA_DIR / 'durations.toml'}: [rules] lacks {missing}") from None


def letter_durations(utterance: Utterance) -> np.ndarray:
    """Seconds per letter from the thesis's mean durations, with ğ-lengthening, geminates and rate."""
    table = duration_table()
    durations = np.empty(len(utterance.letters))
    for word in utterance.words:
        text = word.text
        for position, char in enumerate(text):
            following = text[position + 1] if position + 1 < len(text) else ""
            previous = text[position - 1] if position else ""
            if char in VOWELS and following == SOFT_G:
                seconds = table.lengthened_before_soft_g[char]
            elif char == SOFT_G and previous in VOWELS:
                seconds = table.soft_g_after_vowel
            else:
                seconds = table.letters[char]
                if char not in VOWELS and (following == char or previous == char):
                    seconds *= table.geminate_factor / 2
            durations[word.first_letter + position] = seconds / word.style.rate
    return durations


def table_timeline(utterance: Utterance) -> Timeline:
    """Every letter timed by Table 5.4 (no engine): the thesis's timing inside words, applied everywhere."""
    durations = letter_durations(utterance)
    starts = np.empty_like(durations)
    time = duration_table().lead_in
    for word in utterance.words:
        time += word.pause_before
        for index in range(word.first_letter, word.first_letter + word.letter_count):
            starts[index] = time
            time += durations[index]
    return build_timeline(utterance, starts, starts + durations, time + utterance.final_pause, "table")


def build_timeline(
    utterance: Utterance,
    starts: np.ndarray,
    ends: np.ndarray,
    duration: float,
    timing: str,
    engine_onsets: tuple[float, ...] = (),
    hesitations: tuple[Hesitation, ...] = (),
) -> Timeline:
    """Phones, words, emotion spans and emphases from each letter's start and end (seconds), with the
    hesitations said aloud between them."""
    starts = np.asarray(starts, dtype=np.float64)
    ends = np.asarray(ends, dtype=np.float64)
    if starts.shape != (len(utterance.letters),) or ends.shape != starts.shape:
        raise ValueError("starts and ends need one value per letter")
    phones = tuple(
        Phone(
            start=float(starts[i]),
            end=float(ends[i]),
            letter_index=i,
            letter=letter.char,
            syllable=utterance.syllables[letter.syllable_index].text,
            word_index=letter.word_index,
            viseme=letter.viseme,
        )
        for i, letter in enumerate(utterance.letters)
    )
    words = tuple(
        WordSpan(
            start=float(starts[word.first_letter]),
            end=float(ends[word.first_letter + word.letter_count - 1]),
            index=index,
            text=word.text,
        )
        for index, word in enumerate(utterance.words)
    )
    emotions: list[EmotionSpan] = []
    previous: tuple[str, float] | None = None
    for word, span in zip(utterance.words, words, strict=True):
        if word.style.emotion is None:
            previous = None
            continue
        current = (word.style.emotion, word.style.emotion_weight)
        if current == previous:  # consecutive words in the same emotion form one span
            emotions[-1] = EmotionSpan(emotions[-1].start, span.end, *current)
        else:
            emotions.append(EmotionSpan(span.start, span.end, *current))
        previous = current
    emphases = tuple(
        (span.start, span.end)
        for word, span in zip(utterance.words, words, strict=True)
        if word.style.emphasis
    )
    return Timeline(
        phones=phones,
        words=words,
        emotions=tuple(emotions),
        emphases=emphases,
        duration=float(max(duration, ends.max(initial=0.0))),
        timing=timing,
        engine_onsets=tuple(engine_onsets),
        hesitations=hesitations,
    )
