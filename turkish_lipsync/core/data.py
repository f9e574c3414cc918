"""Loading the data tables of shapekeys/: one place, validated, errors name the file."""

from __future__ import annotations

import tomllib
from functools import cache
from pathlib import Path

from .errors import DataError

DATA_DIR = Path(__file__).resolve().parents[2] / "shapekeys"


@cache
def load_table(name: str) -> dict:
    """The parsed TOML file shapekeys/<name>.toml (cached: tables are read once per process)."""
    path = DATA_DIR / f"{name}.toml"
    try:
        with path.open("rb") as handle:
            return tomllib.load(handle)
    except FileNotFoundError:
        raise DataError(f"data file {path} is missing; reinstall the extension") from None
    except tomllib.TOMLDecodeError as error:
        raise DataError(f"data file {path} is not valid TOML: {error}") from None


def require(table: dict, key: str, kind: type, name: str) -> object:
    """table[key] checked to be of the given type; a DataError naming the file otherwise."""
    value = table.get(key)
    if not isinstance(value, kind):
        raise DataError(
            f"data file {DATA_DIR / (name + '.toml')}: entry {key!r} must be a {kind.__name__}, got {value!r}"
        )
    return value
