"""Matching the engine's phones to the letters of each word, and the per-letter times of the timing modes.

Within a word the engine's phones and the word's letters are aligned by a small edit distance: a letter
matching one of the symbols that may realise it costs nothing, substitutions and extra phones cost
something, and letters the engine usually merges into a neighbour (ğ, h, y, the second of a geminate)
are cheap to drop. A dropped letter then gets a short span cut from its neighbour's phone, so every
letter keeps a positive span and the letters stay in order.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cache

import numpy as np

from ..base.data import DATA_DIR, load_table
from ..base.errors import DataError
from ..base.model import Utterance
from ..text.syllables import VOWELS
from .base import PhoneEvent, SpeechEngine, Synthesis
from .timing import letter_durations

# Shortest span a letter may get (seconds): keeps spans positive where the engine gives two phones one onset.
MINIMUM_SPAN = 0.001
# eSpeak NG reports some phones with no duration (an l swallowed between vowel and s: nasılsın).
SILENT_PHONE = 0.005
# A word the engine did not voice at all gets at most this long per letter after the previous word.
UNVOICED_LETTER = 0.05


@dataclass(frozen=True)
class AlignmentCosts:
    substitute_same_kind: float
    substitute_other_kind: float
    extra_phone: float
    dropped_letter: float
    droppable: dict[str, float]  # letter -> cost of dropping it
    dropped_geminate_letter: float
    dropped_share: float


@cache
def alignment_costs() -> AlignmentCosts:
    path = DATA_DIR / "espeak_tr.toml"
    section = load_table("espeak_tr").get("alignment")
    if not isinstance(section, dict):
        raise DataError(f"{path}: needs an [alignment] table of costs")
    try:
        costs = AlignmentCosts(
            substitute_same_kind=float(section["substitute_same_kind"]),
            substitute_other_kind=float(section["substitute_other_kind"]),
            extra_phone=float(section["extra_phone"]),
            dropped_letter=float(section["dropped_letter"]),
            droppable={letter: float(cost) for letter, cost in dict(section["droppable"]).items()},
            dropped_geminate_letter=float(section["dropped_geminate_letter"]),
            dropped_share=float(section["dropped_share"]),
        )
    except KeyError as missing:
        raise DataError(f"{path}: [alignment] lacks {missing}") from None
    except (TypeError, ValueError) as error:
        raise DataError(f"{path}: [alignment] has a value of the wrong type ({error})") from None
    if not 0 < costs.dropped_share < 1:
        raise DataError(f"{path}: [alignment] dropped_share must lie between 0 and 1")
    return costs


def align_word(
    word: str, symbols: list[str], letter_symbols: dict[str, frozenset[str]], costs: AlignmentCosts
) -> list[list[int]]:
    """For each letter of the word, the indices of the phones (bare symbols) that realise it.

    A letter with no phone was dropped by the engine; a phone no letter matches joins the letter before
    it (the one after it at the start of the word).
    """
    letter_count, phone_count = len(word), len(symbols)
    symbol_is_vowel = [_is_vowel_symbol(symbol, letter_symbols) for symbol in symbols]
    drop_costs = [_drop_cost(word, index, costs) for index in range(letter_count)]
    # total[i][j]: cheapest alignment of the first i letters with the first j phones; move: how it ended
    # (0 letter with phone, 1 letter dropped, 2 extra phone).
    total = [[0.0] * (phone_count + 1) for _ in range(letter_count + 1)]
    move = [[0] * (phone_count + 1) for _ in range(letter_count + 1)]
    for j in range(1, phone_count + 1):
        total[0][j], move[0][j] = costs.extra_phone * j, 2
    for i in range(1, letter_count + 1):
        letter = word[i - 1]
        accepted = letter_symbols.get(letter, frozenset())
        letter_is_vowel = letter in VOWELS
        drop = drop_costs[i - 1]
        above, row = total[i - 1], total[i]
        row[0], move[i][0] = above[0] + drop, 1
        for j in range(1, phone_count + 1):
            if symbols[j - 1] in accepted:
                pair = 0.0
            elif letter_is_vowel == symbol_is_vowel[j - 1]:
                pair = costs.substitute_same_kind
            else:
                pair = costs.substitute_other_kind
            best, step = above[j - 1] + pair, 0
            if above[j] + drop <= best:  # on a tie the earlier letter keeps the phone (ğ follows its vowel)
                best, step = above[j] + drop, 1
            if row[j - 1] + costs.extra_phone < best:
                best, step = row[j - 1] + costs.extra_phone, 2
            row[j], move[i][j] = best, step
    realised: list[list[int]] = [[] for _ in range(letter_count)]
    extras_before_first: list[int] = []
    i, j = letter_count, phone_count
    while i > 0 or j > 0:
        step = move[i][j]
        if step == 0:
            realised[i - 1].append(j - 1)
            i, j = i - 1, j - 1
        elif step == 1:
            i -= 1
        else:
            # An extra phone joins the nearest letter before it that has a phone; decided after the walk.
            extras_before_first.append(j - 1)
            j -= 1
    _attach_extra_phones(realised, sorted(extras_before_first))
    return [sorted(phones) for phones in realised]


def _attach_extra_phones(realised: list[list[int]], extras: list[int]) -> None:
    for phone in extras:
        owner = None
        for index, phones in enumerate(realised):
            if phones and min(phones) < phone:
                owner = index
        if owner is None:
            owner = next((index for index, phones in enumerate(realised) if phones), 0)
        realised[owner].append(phone)


def _drop_cost(word: str, index: int, costs: AlignmentCosts) -> float:
    letter = word[index]
    if letter in costs.droppable:
        return costs.droppable[letter]
    if index and word[index - 1] == letter:
        return costs.dropped_geminate_letter
    return costs.dropped_letter


def _is_vowel_symbol(symbol: str, letter_symbols: dict[str, frozenset[str]]) -> bool:
    return any(symbol in letter_symbols.get(vowel, frozenset()) for vowel in VOWELS)


def phone_letter_spans(
    utterance: Utterance, synthesis: Synthesis, engine: type[SpeechEngine] | SpeechEngine
) -> tuple[np.ndarray, np.ndarray, Synthesis]:
    """Each letter's start and end (seconds) from the phone realising it; the events linked to letters."""
    letter_symbols = engine.letter_symbols()
    costs = alignment_costs()
    count = len(utterance.letters)
    starts = np.full(count, np.nan)
    ends = np.full(count, np.nan)
    by_word: list[list[int]] = [[] for _ in utterance.words]
    for number, event in enumerate(synthesis.phone_events):
        by_word[event.word_index].append(number)
    linked: list[PhoneEvent] = list(synthesis.phone_events)
    for word_index, word in enumerate(utterance.words):
        numbers = by_word[word_index]
        events = [synthesis.phone_events[number] for number in numbers]
        symbols = [engine.bare_symbol(event.symbol) or "" for event in events]
        realised = align_word(word.text, symbols, letter_symbols, costs)
        first = word.first_letter
        for position, phones in enumerate(realised):
            # A phone the engine reports with (almost) no duration is treated like a dropped letter.
            if phones and events[phones[-1]].end - events[phones[0]].start >= SILENT_PHONE:
                starts[first + position] = events[phones[0]].start
                ends[first + position] = events[phones[-1]].end
            for phone in phones:
                number = numbers[phone]
                linked[number] = replace(linked[number], letters=(*linked[number].letters, first + position))
        _place_dropped_letters(starts, ends, first, word.letter_count, costs.dropped_share)
    _place_unvoiced_words(utterance, synthesis, starts, ends)
    starts, ends = _ordered_positive(starts, ends)
    return starts, ends, replace(synthesis, phone_events=tuple(linked))


def _place_dropped_letters(
    starts: np.ndarray, ends: np.ndarray, first: int, count: int, share: float
) -> None:
    """Give each run of dropped letters the tail of the phone before (or the head of the one after)."""
    stop = first + count
    index = first
    while index < stop:
        if not np.isnan(starts[index]):
            index += 1
            continue
        run_end = index
        while run_end < stop and np.isnan(starts[run_end]):
            run_end += 1
        run = run_end - index
        if index > first:  # the letter before keeps the head of its phone
            donor = index - 1
            cut = ends[donor] - share * (ends[donor] - starts[donor])
            edges = np.linspace(cut, ends[donor], run + 1)
            ends[donor] = cut
        elif run_end < stop:  # word-initial: take the head of the next letter's phone
            donor = run_end
            cut = starts[donor] + share * (ends[donor] - starts[donor])
            edges = np.linspace(starts[donor], cut, run + 1)
            starts[donor] = cut
        else:  # no phone in the whole word: _place_unvoiced_words handles it
            return
        starts[index:run_end] = edges[:-1]
        ends[index:run_end] = edges[1:]
        index = run_end


def _place_unvoiced_words(
    utterance: Utterance, synthesis: Synthesis, starts: np.ndarray, ends: np.ndarray
) -> None:
    """A word the engine gave no phone: short letters after the word before it (never seen with eSpeak NG)."""
    word_starts = {event.word_index: event.start for event in synthesis.word_events}
    previous_end = 0.0
    for word_index, word in enumerate(utterance.words):
        letters = slice(word.first_letter, word.first_letter + word.letter_count)
        if np.isnan(starts[letters]).all():
            begin = max(previous_end, word_starts.get(word_index, previous_end))
            later = [value for value in starts[letters.stop :] if not np.isnan(value)][:1]
            limit = later[0] if later else synthesis.duration
            step = max(min(UNVOICED_LETTER, (limit - begin) / word.letter_count), MINIMUM_SPAN)
            starts[letters] = begin + step * np.arange(word.letter_count)
            ends[letters] = starts[letters] + step
        previous_end = float(np.nanmax(ends[letters]))


def _ordered_positive(starts: np.ndarray, ends: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Starts non-decreasing and every span at least MINIMUM_SPAN long, changing as little as possible."""
    starts = starts.copy()
    ends = ends.copy()
    for index in range(starts.size):
        if index and starts[index] < starts[index - 1] + MINIMUM_SPAN:
            starts[index] = starts[index - 1] + MINIMUM_SPAN
        if ends[index] < starts[index] + MINIMUM_SPAN:
            ends[index] = starts[index] + MINIMUM_SPAN
    return starts, ends


def word_letter_spans(utterance: Utterance, synthesis: Synthesis) -> tuple[np.ndarray, np.ndarray]:
    """The thesis's timing: each word starts at its word-start event, its letters follow at Table 5.4 means.

    As in the thesis's render loop, a word waits for its event and for the previous word's letters to
    finish, so a word whose mean durations overrun delays the next one until the next pause absorbs it.
    """
    durations = letter_durations(utterance)
    event_starts = {event.word_index: event.start for event in synthesis.word_events}
    first_phone: dict[int, float] = {}
    for event in synthesis.phone_events:
        first_phone.setdefault(event.word_index, event.start)
    starts = np.empty(len(utterance.letters))
    previous_end = 0.0
    for word_index, word in enumerate(utterance.words):
        event = event_starts.get(word_index, first_phone.get(word_index, previous_end))
        time = max(event, previous_end)
        letters = slice(word.first_letter, word.first_letter + word.letter_count)
        starts[letters] = time + np.concatenate(([0.0], np.cumsum(durations[letters])[:-1]))
        previous_end = time + float(durations[letters].sum())
    return starts, starts + durations
