"""The viseme set (shapekeys/viseme_set.toml): the thesis's 36 vowel-context visemes + neutral, once.

Names, numbers, what each shows, its kind and its Rhubarb mouth shape come from here; the letter table, the
recipes, the motion classes and the cue shapes are checked against it when they load.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from .data import DATA_DIR, load_table
from .errors import DataError

TABLE = "viseme_set"
NEUTRAL = "neutral"
KINDS = ("rest", "vowel", "bilabial", "labiodental", "consonant")
RHUBARB_SHAPES: tuple[str, ...] = ("A", "B", "C", "D", "E", "F", "G", "H", "X")


@dataclass(frozen=True)
class Viseme:
    name: str  # the thesis's model name: a, bpa, ..., neutral
    number: int  # its number in the thesis (Appendix B order)
    kind: str  # one of KINDS
    meaning: str
    rhubarb: str  # one of RHUBARB_SHAPES


def _where(name: str, field: str) -> str:
    return f"data file {DATA_DIR / (TABLE + '.toml')}: [{name}] {field}"


@cache
def viseme_set() -> tuple[Viseme, ...]:
    """The 37 visemes in the thesis's numbering (0..35, neutral 36), validated."""
    visemes = []
    for name, entry in load_table(TABLE).items():
        if not isinstance(entry, dict):
            raise DataError(f"{_where(name, '')}must be a table with number, kind, meaning and rhubarb")
        number, kind = entry.get("number"), entry.get("kind")
        meaning, rhubarb = entry.get("meaning"), entry.get("rhubarb")
        if isinstance(number, bool) or not isinstance(number, int):
            raise DataError(f"{_where(name, 'number')} must be a whole number, got {number!r}")
        if kind not in KINDS:
            raise DataError(f"{_where(name, 'kind')} = {kind!r}: use one of {', '.join(KINDS)}")
        if not isinstance(meaning, str) or not meaning.strip():
            raise DataError(f"{_where(name, 'meaning')} must say what the viseme shows")
        if rhubarb not in RHUBARB_SHAPES:
            raise DataError(
                f"{_where(name, 'rhubarb')} = {rhubarb!r}: use one of {', '.join(RHUBARB_SHAPES)}"
            )
        visemes.append(Viseme(name, number, kind, meaning.strip(), rhubarb))
    visemes.sort(key=lambda viseme: viseme.number)
    if [viseme.number for viseme in visemes] != list(range(37)):
        raise DataError(
            f"data file {DATA_DIR / (TABLE + '.toml')}: the 37 visemes must be numbered 0..36 once each"
        )
    if visemes[-1].name != NEUTRAL or visemes[-1].kind != "rest":
        raise DataError(f"{_where(NEUTRAL, '')}must be number 36, of kind rest")
    return tuple(visemes)


def viseme_names() -> tuple[str, ...]:
    """The 37 names in the thesis's numbering (0..35, neutral 36)."""
    return tuple(viseme.name for viseme in viseme_set())


def visemes_of_kind(kind: str) -> frozenset[str]:
    if kind not in KINDS:
        raise ValueError(f"unknown viseme kind {kind!r}; use one of {', '.join(KINDS)}")
    return frozenset(viseme.name for viseme in viseme_set() if viseme.kind == kind)


def rhubarb_shape_of(viseme: str) -> str:
    return next(v.rhubarb for v in viseme_set() if v.name == viseme)


VISEME_NAMES: tuple[str, ...] = viseme_names()
BILABIAL_VISEMES = visemes_of_kind("bilabial")
LABIODENTAL_VISEMES = visemes_of_kind("labiodental")
VOWEL_VISEMES = visemes_of_kind("vowel")
