"""Loading the data tables of shapekeys/: one place, validated, errors name the file."""

from __future__ import annotations

import tomllib
from functools import cache
from pathlib import Path

from .errors import DataError

DATA_DIR = Path(__file__).resolve().parents[3] / "shapekeys"


@cache
def load_table(name: str) -> dict:
    """The parsed TOML file shapekeys/<name>.toml (cached: tables are read once per process)."""
    return read_toml_file(DATA_DIR / f"{name}.toml", "reinstall the extension")


def read_toml_file(path: Path, remedy: str = "check the file") -> dict:
    """Any TOML file (our tables, a user's own mapping): errors name the file and say what to do."""
    try:
        with Path(path).open("rb") as handle:
            return tomllib.load(handle)
    except FileNotFoundError:
        raise DataError(f"data file {path} is missing; {remedy}") from None
    except OSError as error:
        raise DataError(f"data file {path} cannot be read ({error.strerror}); {remedy}") from None
    except tomllib.TOMLDecodeError as error:
        raise DataError(f"data file {path} is not valid TOML: {error}; {remedy}") from None


def require(table: dict, key: str, kind: type, name: str) -> object:
    """table[key] checked to be of the given type; a DataError naming the file otherwise."""
    value = table.get(key)
    if not isinstance(value, kind):
        raise DataError(
            f"data file {DATA_DIR / (name + '.toml')}: entry {key!r} must be a {kind.__name__}, got {value!r}"
        )
    return value
