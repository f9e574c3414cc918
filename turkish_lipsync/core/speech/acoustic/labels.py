"""What the recogniser tells apart: the Turkish letters as sounds, and silence.

ğ is left out: it is not a sound of its own (the vowel before it lengthens; eSpeak NG drops it), so its
frames count as that vowel's. q, w and x never reach a spoken text (normalisation spells them k, v, ks).
"""

from __future__ import annotations

from functools import cache

import numpy as np

from ...base.data import DATA_DIR, load_table
from ...base.errors import DataError
from ...base.model import Timeline
from ..features import ANALYSIS_RATE, HOP, WINDOW

SILENCE = "_"
LETTERS = "abcçdefghıijklmnoöprsştuüvyz"
CLASSES: tuple[str, ...] = (SILENCE, *LETTERS)
CLASS_INDEX = {name: index for index, name in enumerate(CLASSES)}
VOWEL_LETTERS = frozenset("aeıioöuü")
VOWEL_CLASSES = np.array(sorted(CLASS_INDEX[letter] for letter in VOWEL_LETTERS))
BILABIAL_LETTERS = frozenset("bmp")
FRAME_SECONDS = HOP / ANALYSIS_RATE


@cache
def near_sounds() -> np.ndarray:
    """classes x classes: True where the row's letter counts as heard when the column's is
    (shapekeys/near_sounds.toml), and on the diagonal."""
    groups = load_table("near_sounds").get("groups")
    near = np.eye(len(CLASSES), dtype=bool)
    if not isinstance(groups, list):
        raise DataError(f"data file {DATA_DIR / 'near_sounds.toml'}: 'groups' must be a list of letter lists")
    for group in groups:
        unknown = [letter for letter in group if letter not in LETTERS] if isinstance(group, list) else group
        if unknown:
            raise DataError(
                f"data file {DATA_DIR / 'near_sounds.toml'}: group {group!r} holds {unknown!r}, which are "
                f"not letters the acoustic model hears (those are {LETTERS})"
            )
        members = [CLASS_INDEX[letter] for letter in group]
        near[np.ix_(members, members)] = True
    return near


def frame_times(count: int) -> np.ndarray:
    """Centre time (seconds) of each analysis frame."""
    return (np.arange(count) * HOP + WINDOW / 2) / ANALYSIS_RATE


def frame_labels(timeline: Timeline, count: int, stretch: float = 1.0) -> np.ndarray:
    """The class of each of `count` frames from a timeline's letters (times multiplied by stretch).

    A frame belongs to the letter whose span holds its centre; a ğ's span goes to the letter before it.
    """
    labels = np.zeros(count, np.uint8)
    times = frame_times(count)
    previous = 0
    for phone in timeline.phones:
        name = phone.letter if phone.letter in CLASS_INDEX else None
        if name is None and phone.letter == "ğ":
            name = None if previous == 0 else CLASSES[previous]
        if name is None:
            continue
        first, stop = np.searchsorted(times, (phone.start * stretch, phone.end * stretch))
        labels[first:stop] = CLASS_INDEX[name]
        previous = CLASS_INDEX[name]
    return labels
