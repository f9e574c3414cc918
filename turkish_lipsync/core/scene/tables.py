"""The validated contents of shapekeys/conversation.toml: turn-taking, the cast's voices, placement, tones."""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

from ..base.data import DATA_DIR, load_table, require
from ..base.errors import DataError
from ..text.tables import turkish_lower

TABLE = "conversation"
PATH = DATA_DIR / f"{TABLE}.toml"


@dataclass(frozen=True)
class Turns:
    gap_median: float
    gap_spread: float
    gap_min: float
    gap_max: float
    overlap: float
    same_speaker_gap: float


@dataclass(frozen=True)
class Voices:
    female: tuple[str, ...]
    male: tuple[str, ...]
    pitch_steps: tuple[float, ...]
    rate_steps: tuple[float, ...]

    def of(self, gender: str) -> tuple[str, ...]:
        return self.female if gender == "female" else self.male


@dataclass(frozen=True)
class Placement:
    spacing: float
    arc_step: float
    arc_span: float
    max_turn: float
    camera_distance: float


@dataclass(frozen=True)
class Tone:
    skin: tuple[float, float, float]
    hair: tuple[float, float, float]


@dataclass(frozen=True)
class ConversationTable:
    turns: Turns
    voices: Voices
    names: dict[str, str]  # lower-case given name -> "female" or "male"
    placement: Placement
    tones: tuple[Tone, ...]


def _numbers(section: dict, name: str, keys: tuple[str, ...], high: float = math.inf) -> dict[str, float]:
    values = {}
    for key in keys:
        value = section.get(key)
        if isinstance(value, bool) or not isinstance(value, int | float) or not 0 <= value <= high:
            raise DataError(
                f"data file {PATH}: [{name}] {key} must be a number in 0..{high:g}, got {value!r}"
            )
        values[key] = float(value)
    return values


def _strings(section: dict, name: str, key: str) -> tuple[str, ...]:
    values = section.get(key)
    if not isinstance(values, list) or not values or not all(isinstance(v, str) and v for v in values):
        raise DataError(f"data file {PATH}: [{name}] {key} must be a list of names")
    return tuple(values)


def _colour(value, where: str) -> tuple[float, float, float]:
    if (
        not isinstance(value, list)
        or len(value) != 3
        or not all(isinstance(c, int | float) and not isinstance(c, bool) and 0 <= c <= 1 for c in value)
    ):
        raise DataError(
            f"data file {PATH}: {where} must be three numbers in 0..1 (linear RGB), got {value!r}"
        )
    return tuple(float(c) for c in value)


@cache
def conversation_table() -> ConversationTable:
    table = load_table(TABLE)
    turns = Turns(
        **_numbers(
            require(table, "turns", dict, TABLE),
            "turns",
            ("gap_median", "gap_spread", "gap_min", "gap_max", "overlap", "same_speaker_gap"),
            10.0,
        )
    )
    if not turns.gap_min <= turns.gap_median <= turns.gap_max:
        raise DataError(f"data file {PATH}: [turns] needs gap_min <= gap_median <= gap_max")
    voices_section = require(table, "voices", dict, TABLE)
    steps = {}
    for key in ("pitch_steps", "rate_steps"):
        values = voices_section.get(key)
        if (
            not isinstance(values, list)
            or not values
            or not all(
                isinstance(v, int | float) and not isinstance(v, bool) and 0.5 <= v <= 2 for v in values
            )
        ):
            raise DataError(f"data file {PATH}: [voices] {key} must be a list of multipliers in 0.5..2")
        steps[key] = tuple(float(v) for v in values)
    voices = Voices(
        _strings(voices_section, "voices", "female"), _strings(voices_section, "voices", "male"), **steps
    )
    names_section = require(table, "names", dict, TABLE)
    names = {}
    for gender in ("female", "male"):
        for name in _strings(names_section, "names", gender):
            names[turkish_lower(name)] = gender
    placement = Placement(
        **_numbers(
            require(table, "placement", dict, TABLE),
            "placement",
            ("spacing", "arc_step", "arc_span", "max_turn", "camera_distance"),
            360.0,
        )
    )
    tones_list = require(table, "tones", list, TABLE)
    tones = tuple(
        Tone(
            _colour(tone.get("skin"), f"[[tones]] {number} skin"),
            _colour(tone.get("hair"), f"[[tones]] {number} hair"),
        )
        for number, tone in enumerate(tones_list, start=1)
        if isinstance(tone, dict)
    )
    if len(tones) != len(tones_list) or not tones:
        raise DataError(f"data file {PATH}: [[tones]] must be tables with skin and hair colours")
    return ConversationTable(turns, voices, names, placement, tones)
