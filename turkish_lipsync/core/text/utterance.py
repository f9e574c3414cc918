"""JSML source to an Utterance: words, syllables and letters with their visemes."""

from __future__ import annotations

import dataclasses
import unicodedata
from collections.abc import Iterable
from dataclasses import replace

from ..base.errors import TextError
from ..base.model import Letter, Pause, SpokenWord, Syllable, TextRun, Utterance, Word
from .jsml import parse_jsml, pause_seconds
from .normalize import normalize
from .syllables import VOWELS, syllabify, syllable_vowel
from .tables import fold_letter
from .visemes import viseme_for_letter

# Reading a text takes time in proportion to its length (about 20 s for this many characters on one core):
# longer texts are refused at once instead.
MAX_SOURCE_CHARACTERS = 1_000_000

# The punctuation a pause stands for, as the speech engine reads it.
PAUSE_ENDINGS = {
    "comma": ",",
    "clause": ",",
    "sentence": ".",
    "paragraph": ".",
    "question": "?",
    "exclamation": "!",
}


def build_utterance(source: str) -> Utterance:
    """Parse, normalise, syllabify and map every letter to its viseme (thesis 5.2.2-5.2.3)."""
    if len(source) > MAX_SOURCE_CHARACTERS:
        raise TextError(
            f"the text has {len(source):,} characters, more than the {MAX_SOURCE_CHARACTERS:,} (about 20 "
            "hours of speech) one text may hold: split it into several texts"
        )
    items = parse_jsml(source)
    unspoken = unspoken_characters(items)
    try:
        normalized = normalize(items)
    except TextError as error:
        if unspoken:
            raise TextError(
                f"{error} (left out, as Turkish speech cannot say them: {_quoted(unspoken)})"
            ) from None
        raise
    return assemble_utterance(source, normalized, unspoken)


def assemble_utterance(
    source: str, items: Iterable[SpokenWord | Pause], unspoken: tuple[str, ...] = ()
) -> Utterance:
    """The utterance of words as spoken and the pauses between them: syllables, letters and visemes.

    build_utterance's last step; a text recognised from audio (speech/recognition) starts here, since it
    is already spoken Turkish letters and must not be read again as written text (an acronym's letters).
    """
    words: list[Word] = []
    syllables: list[Syllable] = []
    letters: list[Letter] = []
    pending_pause, line_start = 0.0, False
    for item in items:
        if isinstance(item, Pause):
            pending_pause += item.seconds
            line_start = line_start or item.kind == "line"
            if words and item.kind in PAUSE_ENDINGS and not words[-1].ending:
                words[-1] = replace(words[-1], ending=PAUSE_ENDINGS[item.kind])
            continue
        _append_word(item, pending_pause, line_start and bool(words), words, syllables, letters)
        pending_pause, line_start = 0.0, False
    if not words:
        raise TextError("nothing to speak: the text has no Turkish words after normalisation")
    return Utterance(
        source=source,
        words=tuple(words),
        syllables=tuple(syllables),
        letters=tuple(letters),
        final_pause=pending_pause,
        unspoken=unspoken,
    )


def unspoken_characters(items) -> tuple[str, ...]:
    """Stretches of the text that are spoken as nothing: letters of other scripts (Cyrillic, Arabic, Han,
    ...) and pictographs (emoji, symbols), each stretch as written."""
    found: list[str] = []
    for item in items:
        if not isinstance(item, TextRun):
            continue
        current = ""
        for char in item.text + " ":
            category = unicodedata.category(char)
            silent = (category.startswith("L") and not fold_letter(char)) or category == "So"
            # a zero-width joiner, a variation selector, a mark or a skin tone belongs to what it follows
            joiner = current and (char in "\u200d\ufe0f" or category in ("Mn", "Me", "Sk"))
            if silent or joiner:
                current += char
            elif current:
                found.append(current)
                current = ""
    return tuple(found)


def _quoted(stretches: tuple[str, ...], shown: int = 5) -> str:
    text = ", ".join(repr(stretch) for stretch in stretches[:shown])
    return text + (f" and {len(stretches) - shown} more" if len(stretches) > shown else "")


def unspoken_warning(utterance: Utterance) -> tuple[str, ...]:
    """The warning for what the text holds that is left silent (none where everything is spoken)."""
    if not utterance.unspoken:
        return ()
    return (
        f"The text holds characters Turkish speech cannot say; they are left silent: "
        f"{_quoted(utterance.unspoken)}. Write them out in Turkish (or give a <SAYAS SUB> reading) to "
        "have them spoken.",
    )


def _append_word(
    spoken: SpokenWord,
    pause_before: float,
    line_start: bool,
    words: list[Word],
    syllables: list[Syllable],
    letters: list[Letter],
) -> None:
    word_index = len(words)
    first_letter = len(letters)
    first_syllable = len(syllables)
    parts = syllabify(spoken.text)
    # A syllable without a vowel (only possible in vowelless words) borrows the word's nearest vowel.
    vowels = [syllable_vowel(part) for part in parts]
    position = 0
    for number, part in enumerate(parts):
        vowel = vowels[number] or _nearest_vowel(vowels, number)
        syllable_index = len(syllables)
        syllables.append(Syllable(part, word_index, len(letters), len(part)))
        for char in part:
            letters.append(
                Letter(
                    char=char,
                    offset=spoken.offsets[position],
                    word_index=word_index,
                    syllable_index=syllable_index,
                    viseme=viseme_for_letter(char, vowel),
                    is_vowel=char in VOWELS,
                )
            )
            position += 1
    words.append(
        Word(
            text=spoken.text,
            first_letter=first_letter,
            letter_count=len(letters) - first_letter,
            first_syllable=first_syllable,
            syllable_count=len(parts),
            style=spoken.style,
            pause_before=pause_before,
            line_start=line_start,
        )
    )


def _nearest_vowel(vowels: list[str | None], index: int) -> str | None:
    for distance in range(1, len(vowels)):
        for neighbour in (index - distance, index + distance):
            if 0 <= neighbour < len(vowels) and vowels[neighbour]:
                return vowels[neighbour]
    return None


def with_rate(utterance: Utterance, rate: float) -> Utterance:
    """The utterance with every word spoken rate times faster (markup rates multiply with it)."""
    if abs(rate - 1.0) < 1e-9:
        return utterance
    words = tuple(
        dataclasses.replace(word, style=dataclasses.replace(word.style, rate=word.style.rate * rate))
        for word in utterance.words
    )
    return dataclasses.replace(utterance, words=words)


def read_aloud(utterance: Utterance, pauses: Iterable[int] = ()) -> Utterance:
    """The utterance as a person reading the text aloud says it: a pause at each line break, as at a comma
    (a list an item a line, a script's lines), and before each word of `pauses` (indices). The voice reads
    a line break as a space; a recording of the text is aligned to this reading (speech/recording.py)."""
    comma = pause_seconds()["punctuation"]["comma"]
    before = set(pauses)
    words = list(utterance.words)
    for index, word in enumerate(words):
        if index and (word.line_start or index in before) and word.pause_before == 0:
            words[index] = replace(word, pause_before=comma)
            if not words[index - 1].ending:
                words[index - 1] = replace(words[index - 1], ending=PAUSE_ENDINGS["comma"])
    return replace(utterance, words=tuple(words))
