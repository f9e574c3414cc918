"""Viseme and emotion recipes: each built key as weights over the 52 ARKit face units.

The recipes are data (shapekeys/visemes.toml, shapekeys/emotions.toml) so they can be tuned without
touching code; this module validates them on load and turns them into key deltas with numpy.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..base.data import DATA_DIR, read_toml_file
from ..base.errors import DataError
from ..base.model import (
    BLINK_KEYS,
    BROW_RAISE_KEY,
    EMOTION_KEY_PREFIX,
    EMOTIONS,
    emotion_key_name,
    emotion_release_key_name,
    viseme_key_name,
)
from ..base.visemes import VISEME_NAMES
from .arkit_names import ARKIT_UNITS, is_mouth_unit

VISEMES_FILE = DATA_DIR / "visemes.toml"
EMOTIONS_FILE = DATA_DIR / "emotions.toml"

EXTRA_KEYS: dict[str, str] = {
    "blink_left": BLINK_KEYS[0],
    "blink_right": BLINK_KEYS[1],
    "brow_raise": BROW_RAISE_KEY,
}
_MAX_WEIGHT = 2.0


@dataclass(frozen=True)
class Recipe:
    """One key: ARKit unit -> weight, and the thesis's words for the shape."""

    name: str
    description: str
    units: Mapping[str, float]


@dataclass(frozen=True)
class Recipes:
    visemes: Mapping[str, Recipe]  # 37, by thesis model name
    emotions: Mapping[str, Recipe]  # 6, by EMOTIONS name
    extras: Mapping[str, Recipe]  # blink_left, blink_right, brow_raise

    def key_recipes(self) -> dict[str, dict[str, float]]:
        """Every built key name (model.py naming) -> its unit weights, including the mouth releases."""
        keys: dict[str, dict[str, float]] = {}
        for name in VISEME_NAMES:
            keys[viseme_key_name(name)] = dict(self.visemes[name].units)
        for name in EMOTIONS:
            keys[emotion_key_name(name)] = dict(self.emotions[name].units)
        for name in EMOTIONS:
            units = self.emotions[name].units
            keys[emotion_release_key_name(name)] = {u: -w for u, w in units.items() if is_mouth_unit(u)}
        for name, key_name in EXTRA_KEYS.items():
            keys[key_name] = dict(self.extras[name].units)
        return keys


def expand_units(path: Path, where: str, table: object) -> dict[str, float]:
    """Validate one units table; a unit without side ("mouthSmile") sets both sides."""
    if not isinstance(table, dict):
        raise DataError(f"{path}: [{where}] units must be a table like {{ jawOpen = 0.3 }}.")
    units: dict[str, float] = {}
    for unit, weight in table.items():
        if isinstance(weight, bool) or not isinstance(weight, int | float):
            raise DataError(f"{path}: [{where}] {unit} = {weight!r}: the weight must be a number.")
        if not -_MAX_WEIGHT <= weight <= _MAX_WEIGHT:
            raise DataError(f"{path}: [{where}] {unit} = {weight}: weights must lie in ±{_MAX_WEIGHT}.")
        if unit in ARKIT_UNITS:
            targets = [unit]
        elif unit + "Left" in ARKIT_UNITS and unit + "Right" in ARKIT_UNITS:
            targets = [unit + "Left", unit + "Right"]
        else:
            raise DataError(
                f"{path}: [{where}] {unit!r} is not one of the 52 ARKit units; check its spelling."
            )
        for target in targets:
            if target in units:
                raise DataError(f"{path}: [{where}] sets {target} twice.")
            units[target] = float(weight)
    return units


def _read_section(path: Path, data: dict, section: str, names: tuple[str, ...]) -> dict[str, Recipe]:
    table = data.get(section)
    if not isinstance(table, dict):
        raise DataError(f"{path}: missing the [{section}.<name>] tables.")
    missing = [name for name in names if name not in table]
    unknown = [name for name in table if name not in names]
    if missing or unknown:
        raise DataError(f"{path}: [{section}] missing {missing or 'none'}, unknown {unknown or 'none'}.")
    recipes: dict[str, Recipe] = {}
    for name in names:
        entry = table[name]
        if not isinstance(entry, dict) or "units" not in entry:
            raise DataError(f"{path}: [{section}.{name}] needs a units table.")
        recipes[name] = Recipe(
            name, str(entry.get("description", "")), expand_units(path, f"{section}.{name}", entry["units"])
        )
    return recipes


def load_recipes(visemes_file: Path = VISEMES_FILE, emotions_file: Path = EMOTIONS_FILE) -> Recipes:
    """Read and validate both recipe files (cached for the default files)."""
    if visemes_file == VISEMES_FILE and emotions_file == EMOTIONS_FILE:
        return _default_recipes()
    return _read_recipes(visemes_file, emotions_file)


@functools.cache
def _default_recipes() -> Recipes:
    return _read_recipes(VISEMES_FILE, EMOTIONS_FILE)


def _read_recipes(visemes_file: Path, emotions_file: Path) -> Recipes:
    visemes = _read_section(visemes_file, read_toml_file(visemes_file), "visemes", VISEME_NAMES)
    emotions_data = read_toml_file(emotions_file)
    emotions = _read_section(emotions_file, emotions_data, "emotions", EMOTIONS)
    extras = _read_section(emotions_file, emotions_data, "extras", tuple(EXTRA_KEYS))
    return Recipes(visemes=visemes, emotions=emotions, extras=extras)


def combine_units(
    weights: Mapping[str, float], units: Mapping[str, np.ndarray], vertex_count: int
) -> np.ndarray:
    """The deltas of one recipe: the weighted sum of the unit deltas it names (missing units count as 0)."""
    deltas = np.zeros((vertex_count, 3), dtype=np.float32)
    for unit, weight in weights.items():
        unit_deltas = units.get(unit)
        if unit_deltas is not None and weight:
            deltas += np.float32(weight) * unit_deltas
    return deltas


def key_deltas(
    units: Mapping[str, np.ndarray], vertex_count: int, *, recipes: Recipes | None = None
) -> dict[str, np.ndarray]:
    """Deltas (vertex_count, 3) of every built key from a head's ARKit unit deltas."""
    recipes = recipes or load_recipes()
    return {
        key_name: combine_units(weights, units, vertex_count)
        for key_name, weights in recipes.key_recipes().items()
    }


def empower(deltas: Mapping[str, np.ndarray], rho: float) -> dict[str, np.ndarray]:
    """Thesis eq. 5.2, P = N + rho (E - N): every emotion key's delta times rho, its mouth release alike
    so that the release still cancels the emotion's mouth; every other key as it is."""
    if not rho > 0:
        raise DataError(f"The empowering constant rho must be positive (got {rho}); the thesis uses 3.")
    return {
        name: delta * np.float32(rho) if name.startswith(EMOTION_KEY_PREFIX) else delta
        for name, delta in deltas.items()
    }
