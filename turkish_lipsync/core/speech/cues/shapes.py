"""Rhubarb's nine mouth shapes (shapekeys/rhubarb_shapes.toml) and the Turkish visemes each stands for."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from ...base.data import DATA_DIR, load_table, require
from ...base.errors import DataError
from ...base.visemes import RHUBARB_SHAPES, rhubarb_shape_of

TABLE = "rhubarb_shapes"
SHAPES = RHUBARB_SHAPES
REST = "X"


@dataclass(frozen=True)
class ShapeTable:
    preston_blair: dict[str, str]  # Rhubarb shape -> Preston Blair phoneme (Papagayo, Moho)
    from_preston_blair: dict[str, str]  # Preston Blair phoneme (and aliases) -> Rhubarb shape


def _where(section: str, key: str) -> str:
    return f"data file {DATA_DIR / (TABLE + '.toml')}: [{section}] {key}"


@cache
def shape_table() -> ShapeTable:
    table = load_table(TABLE)
    described = require(table, "shapes", dict, TABLE)
    if sorted(described) != sorted(SHAPES):
        raise DataError(f"{_where('shapes', '')}must describe exactly the shapes {', '.join(SHAPES)}")
    preston_blair = require(table, "preston_blair", dict, TABLE)
    if sorted(preston_blair) != sorted(SHAPES):
        raise DataError(f"{_where('preston_blair', '')}must name a phoneme for each of {', '.join(SHAPES)}")
    aliases = require(table, "preston_blair_aliases", dict, TABLE)
    for alias, shape in aliases.items():
        if shape not in SHAPES:
            raise DataError(f"{_where('preston_blair_aliases', alias)} = {shape!r}: use one of {SHAPES}")
    backwards = {phoneme.lower(): shape for shape, phoneme in preston_blair.items()}
    backwards.update({alias.lower(): shape for alias, shape in aliases.items()})
    return ShapeTable(dict(preston_blair), backwards)


def shape_for_viseme(viseme: str) -> str:
    return rhubarb_shape_of(viseme)


def uses_preston_blair(names) -> bool:
    """Whether a file's mouth names are Preston Blair's (AI, E, etc, ...) rather than Rhubarb's letters:
    "E" is in both sets (Rhubarb's rounded E, Preston Blair's open E), so the other names decide."""
    table = shape_table().from_preston_blair
    return any(name.lower() in table and name not in SHAPES for name in names)


def shape_for_phoneme(name: str, preston_blair: bool) -> str | None:
    """The Rhubarb shape of a mouth name in a cue file (None if unknown)."""
    if preston_blair:
        return shape_table().from_preston_blair.get(name.strip().lower())
    return name if name in SHAPES else None
