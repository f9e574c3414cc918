"""Rhubarb's nine mouth shapes and the Turkish visemes each stands for (shapekeys/rhubarb_shapes.toml)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from ...base.data import DATA_DIR, load_table, require
from ...base.errors import DataError
from ...text.visemes import viseme_names

TABLE = "rhubarb_shapes"
SHAPES: tuple[str, ...] = ("A", "B", "C", "D", "E", "F", "G", "H", "X")
REST = "X"


@dataclass(frozen=True)
class ShapeTable:
    viseme_shapes: dict[str, str]  # Turkish viseme -> Rhubarb shape
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
    visemes = require(table, "visemes", dict, TABLE)
    missing = sorted(set(viseme_names()) - set(visemes))
    unknown = sorted(set(visemes) - set(viseme_names()))
    if missing or unknown:
        raise DataError(f"{_where('visemes', '')}missing {missing or 'none'}, unknown {unknown or 'none'}")
    for viseme, shape in visemes.items():
        if shape not in SHAPES:
            raise DataError(f"{_where('visemes', viseme)} = {shape!r}: use one of {', '.join(SHAPES)}")
    preston_blair = require(table, "preston_blair", dict, TABLE)
    if sorted(preston_blair) != sorted(SHAPES):
        raise DataError(f"{_where('preston_blair', '')}must name a phoneme for each of {', '.join(SHAPES)}")
    aliases = require(table, "preston_blair_aliases", dict, TABLE)
    for alias, shape in aliases.items():
        if shape not in SHAPES:
            raise DataError(f"{_where('preston_blair_aliases', alias)} = {shape!r}: use one of {SHAPES}")
    backwards = {phoneme.lower(): shape for shape, phoneme in preston_blair.items()}
    backwards.update({alias.lower(): shape for alias, shape in aliases.items()})
    return ShapeTable(dict(visemes), dict(preston_blair), backwards)


def shape_for_viseme(viseme: str) -> str:
    return shape_table().viseme_shapes[viseme]


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
