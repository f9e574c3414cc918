"""Visemes a head already has, in other conventions than ARKit: recognised by name, mapped onto the TR keys.

Oculus/Meta's 15 visemes, VRM's five vowels, the 21 Azure visemes and Preston Blair/Papagayo mouths each
have a table in shapekeys/conventions/ that writes every Turkish viseme as weights over that convention's
shapes, and names the ARKit units to add from the head's other basis (its ARKit keys or a transfer) for what
the convention cannot show (a VRM head has no lip closure, Papagayo no bitten lower lip). A user's own
mapping file has the same form, with the head's key names as the shapes.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..base.data import DATA_DIR, read_toml_file
from ..base.errors import DataError
from ..base.model import (
    EMOTIONS,
    VISEME_KEY_PREFIX,
    emotion_key_name,
    emotion_release_key_name,
    viseme_key_name,
)
from .recipes import EXTRA_KEYS, VISEME_NAMES, Recipes, combine_units, expand_units

CONVENTIONS_DIR = DATA_DIR / "conventions"
# What a convention may name besides visemes: the six emotions, the blinks and the brow raise.
EXPRESSIONS: tuple[str, ...] = (*EMOTIONS, *EXTRA_KEYS)
_MAX_WEIGHT = 2.0
# A vertex counts fully as mouth (released under a viseme) where a mouth shape moves it by at least this
# share of the largest mouth motion, and not at all below the floor (the eyes and brows a wide-open jaw
# barely stirs); in between it is released in proportion.
_MOUTH_SHARE = 0.25
_MOUTH_FLOOR = 0.05


@dataclass(frozen=True)
class VisemeMapping:
    """One TR viseme in a convention: its shapes' weights, and ARKit units for what the convention lacks."""

    shapes: Mapping[str, float]
    units: Mapping[str, float]
    fills: str  # what the units stand for, in the build report ("lip closure", "rounding")


@dataclass(frozen=True)
class Convention:
    name: str
    title: str
    prefixes: tuple[str, ...]  # dropped from key names before they are compared ("viseme", "fcl_mth")
    minimum: int  # shapes a head must have for its keys to count as this convention
    spellings: Mapping[str, tuple[str, ...]]  # shape -> accepted spellings (canonical form)
    visemes: Mapping[str, VisemeMapping]  # TR viseme -> mapping; a viseme left out takes its ARKit recipe
    # Emotion, blink or brow raise -> its alternatives in order of preference, each a combination of keys
    # (spelling -> weight): ["Happy", "Joy"] is two alternatives of one key each.
    expressions: Mapping[str, tuple[Mapping[str, float], ...]]
    exact: bool = False  # a user's mapping names the head's keys exactly as written


@dataclass(frozen=True)
class ConventionMatch:
    """Which of a head's keys are which shapes of a convention."""

    convention: Convention
    shapes: Mapping[str, str]  # shape -> head key name
    expressions: Mapping[str, Mapping[str, float]]  # expression -> head key name -> weight


@dataclass(frozen=True)
class KeyPlan:
    """How one TR key is made: the head's own keys, ARKit units from the other basis, or both."""

    shapes: Mapping[str, float]  # head key name -> weight
    units: Mapping[str, float]  # ARKit unit -> weight, taken from the fallback basis
    fills: str  # what the units add on top of own shapes ("" when the key is all one source)
    # For an emotion's mouth release: the head's own keys (-> weight) that make the emotion it releases.
    release_of: Mapping[str, float] = field(default_factory=dict)

    def describe(self, fallback: str | None) -> str:
        """Where the key came from, in words: 'own keys: aa_02 1', 'own keys: ih 0.2 + transfer (press)'."""
        if self.release_of:
            return f"mouth part of own keys: {_weights_text(self.release_of)}"
        own = f"own keys: {_weights_text(self.shapes)}"
        if not self.shapes:
            own = "rest shape"
        if not self.units:
            return own
        if fallback is None:
            return (
                f"{own} ({self.fills} missing: no other basis)" if self.fills else "at rest: no other basis"
            )
        if not self.shapes:
            return f"{fallback} ({self.fills})" if self.fills else fallback
        return f"{own} + {fallback} ({self.fills})"


def _weights_text(weights: Mapping[str, float]) -> str:
    return ", ".join(f"{name} {weight:g}" for name, weight in weights.items())


# ---------------------------------------------------------------- names


def canonical_name(name: str, prefixes: Iterable[str] = ()) -> str:
    """A key name reduced for comparison: no exporter prefix, convention prefix, number or separator."""
    name = re.split(r"[|:]", name)[-1]
    head, dot, tail = name.rpartition(".")
    if dot and tail.isdigit():
        name = head  # Blender's duplicate suffix: "ah.001"
    elif dot and head and len(tail) > 1:
        name = tail  # "blendShape1.viseme_aa", "vrc.v_aa"
    name = re.sub(r"[\s.\-]+", "_", name.strip().lower())
    stripped = True
    while stripped:
        stripped = False
        for prefix in prefixes:
            if name.startswith(prefix + "_") and len(name) > len(prefix) + 1:
                name = name[len(prefix) + 1 :]
                stripped = True
    without_number = re.sub(r"_?\d+$", "", name)
    return (without_number or name).replace("_", "")


def _lookup(spellings: Mapping[str, tuple[str, ...]]) -> dict[str, str]:
    return {spelling: target for target, names in spellings.items() for spelling in names}


def match_convention(key_names: Iterable[str], convention: Convention) -> ConventionMatch:
    """The head's keys that are this convention's shapes and expressions.

    A shape takes the first of the head's keys spelt as it; an expression its first alternative whose keys
    the head all has.
    """
    shape_of = _lookup(convention.spellings)
    head_key: dict[str, str] = {}  # compared spelling -> the head's first key spelt so
    for key_name in key_names:
        head_key.setdefault(
            key_name if convention.exact else canonical_name(key_name, convention.prefixes), key_name
        )
    shapes: dict[str, str] = {}
    for compared, key_name in head_key.items():
        if compared in shape_of:
            shapes.setdefault(shape_of[compared], key_name)
    expressions: dict[str, dict[str, float]] = {}
    for expression, alternatives in convention.expressions.items():
        for combination in alternatives:
            if all(spelling in head_key for spelling in combination):
                expressions[expression] = {head_key[s]: weight for s, weight in combination.items()}
                break
    return ConventionMatch(convention, shapes, expressions)


def recognise_convention(
    key_names: Iterable[str], conventions: Iterable[Convention] | None = None
) -> ConventionMatch | None:
    """The convention most of the head's keys belong to (at least its minimum of shapes), or None.

    More matched shapes win; on a tie, the convention whose shapes are more completely present.
    """
    key_names = list(key_names)
    best: tuple[int, float] | None = None
    chosen = None
    for convention in conventions if conventions is not None else load_conventions():
        match = match_convention(key_names, convention)
        found = len(match.shapes)
        if found < convention.minimum:
            continue
        score = (found, found / len(convention.spellings))
        if best is None or score > best:
            best, chosen = score, match
    return chosen


# ---------------------------------------------------------------- the plan of every TR key


def plan_keys(match: ConventionMatch, recipes: Recipes) -> dict[str, KeyPlan]:
    """Every built key (recipes.key_recipes() names) as own shapes and fallback units."""
    convention = match.convention
    plans: dict[str, KeyPlan] = {}
    arkit = recipes.key_recipes()
    for viseme in VISEME_NAMES:
        key_name = viseme_key_name(viseme)
        mapping = convention.visemes.get(viseme)
        shapes = {}
        if mapping is not None:
            shapes = {match.shapes[s]: w for s, w in mapping.shapes.items() if s in match.shapes and w}
        if mapping is None or (mapping.shapes and not shapes):
            plans[key_name] = KeyPlan({}, arkit[key_name], "")  # the convention (or this head) lacks it
        else:
            plans[key_name] = KeyPlan(shapes, dict(mapping.units), mapping.fills)
    for emotion in EMOTIONS:
        own = match.expressions.get(emotion)
        key_name, release = emotion_key_name(emotion), emotion_release_key_name(emotion)
        if own is None:
            plans[key_name] = KeyPlan({}, arkit[key_name], "")
            plans[release] = KeyPlan({}, arkit[release], "")
        else:
            plans[key_name] = KeyPlan(dict(own), {}, "")
            plans[release] = KeyPlan({}, {}, "", release_of=dict(own))
    for extra, key_name in EXTRA_KEYS.items():
        own = match.expressions.get(extra)
        plans[key_name] = KeyPlan(dict(own), {}, "") if own else KeyPlan({}, arkit[key_name], "")
    return plans


def unmatched_names(match: ConventionMatch) -> tuple[str, ...]:
    """Warnings for what a user's own mapping names but the head lacks (a misspelt or missing key): each
    such viseme or expression falls back to its ARKit recipe, and the user must hear which."""
    convention = match.convention
    if not convention.exact:
        return ()
    missing = sorted(name for name in convention.spellings if name not in match.shapes)
    expressions = sorted(name for name in convention.expressions if name not in match.expressions)
    warnings = []
    if missing:
        warnings.append(
            f"{convention.title} names keys the head does not have: {', '.join(map(repr, missing))}; the "
            "visemes that use only them are built from their ARKit recipe. Check the spelling (names are "
            "compared exactly)."
        )
    if expressions:
        warnings.append(
            f"{convention.title} maps {', '.join(expressions)} to keys the head does not have; they are "
            "built from their ARKit recipe."
        )
    return tuple(warnings)


def mouth_weights(mouth_shapes: Iterable[np.ndarray], vertex_count: int) -> np.ndarray:
    """(N,) 0..1: how much each vertex is mouth, by how far the head's own mouth shapes move it."""
    motion = np.zeros(vertex_count, dtype=np.float32)
    for deltas in mouth_shapes:
        motion = np.maximum(motion, np.linalg.norm(deltas, axis=1))
    largest = float(motion.max()) if vertex_count else 0.0
    if largest <= 0:
        return motion
    return np.clip((motion / largest - _MOUTH_FLOOR) / (_MOUTH_SHARE - _MOUTH_FLOOR), 0.0, 1.0)


def convention_key_deltas(
    plans: Mapping[str, KeyPlan],
    own_shapes: Mapping[str, np.ndarray],
    units: Mapping[str, np.ndarray],
    vertex_count: int,
) -> dict[str, np.ndarray]:
    """(N, 3) deltas of every planned key: own shapes (missing ones count as 0) plus fallback units.

    An own emotion's mouth release is that emotion's motion where the head's own visemes move the face,
    negated.
    """
    viseme_shapes = {
        name for key, plan in plans.items() if key.startswith(VISEME_KEY_PREFIX) for name in plan.shapes
    }
    mouth = mouth_weights((own_shapes[name] for name in viseme_shapes if name in own_shapes), vertex_count)
    result: dict[str, np.ndarray] = {}
    for key_name, plan in plans.items():
        deltas = combine_units(plan.units, units, vertex_count)
        for name, weight in plan.shapes.items():
            if name in own_shapes:
                deltas += np.float32(weight) * own_shapes[name]
        for name, weight in plan.release_of.items():
            if name in own_shapes:
                deltas -= np.float32(weight) * own_shapes[name] * mouth[:, None]
        result[key_name] = deltas
    return result


# ---------------------------------------------------------------- tables


def _weights(path: Path, where: str, table: object, allowed: Iterable[str] | None) -> dict[str, float]:
    if not isinstance(table, dict):
        raise DataError(f"{path}: [{where}] shapes must be a table like {{ aa = 1.0 }}.")
    allowed = set(allowed) if allowed is not None else None
    weights: dict[str, float] = {}
    for name, weight in table.items():
        if isinstance(weight, bool) or not isinstance(weight, int | float):
            raise DataError(f"{path}: [{where}] {name} = {weight!r}: the weight must be a number.")
        if not -_MAX_WEIGHT <= weight <= _MAX_WEIGHT:
            raise DataError(f"{path}: [{where}] {name} = {weight}: weights must lie in ±{_MAX_WEIGHT}.")
        if allowed is not None and name not in allowed:
            raise DataError(f"{path}: [{where}] {name!r} is not one of the shapes listed under [shapes].")
        weights[name] = float(weight)
    return weights


def _spelling_list(path: Path, where: str, value: object, exact: bool) -> tuple[str, ...]:
    names = [value] if isinstance(value, str) else value
    if not isinstance(names, list) or not names or not all(isinstance(n, str) and n for n in names):
        raise DataError(f"{path}: [{where}] must be a key name or a list of spellings, got {value!r}.")
    return tuple(names if exact else dict.fromkeys(canonical_name(n) for n in names))


def _read_visemes(path: Path, data: dict, shapes: Iterable[str] | None) -> dict[str, VisemeMapping]:
    table = data.get("visemes", {})
    if not isinstance(table, dict):
        raise DataError(f"{path}: [visemes] must hold [visemes.<TR viseme>] tables.")
    unknown = [name for name in table if name not in VISEME_NAMES]
    if unknown:
        raise DataError(f"{path}: unknown TR visemes {unknown}; use the names of shapekeys/visemes.toml.")
    visemes: dict[str, VisemeMapping] = {}
    for name, entry in table.items():
        where = f"visemes.{name}"
        if not isinstance(entry, dict):
            raise DataError(f"{path}: [{where}] must be a table with shapes (and optional units, fills).")
        units = expand_units(path, where, entry.get("units", {}))
        fills = entry.get("fills", "")
        if units and not (isinstance(fills, str) and fills):
            raise DataError(
                f'{path}: [{where}] has units: say what they fill in, e.g. fills = "lip closure".'
            )
        visemes[name] = VisemeMapping(_weights(path, where, entry.get("shapes", {}), shapes), units, fills)
    return visemes


def _read_expressions(path: Path, data: dict, exact: bool) -> dict[str, tuple[dict[str, float], ...]]:
    """Each expression: alternatives in order, each a key name or a table combining keys with weights."""
    table = data.get("expressions", {})
    if not isinstance(table, dict) or any(name not in EXPRESSIONS for name in table):
        raise DataError(f"{path}: [expressions] may name only {', '.join(EXPRESSIONS)}.")
    expressions: dict[str, tuple[dict[str, float], ...]] = {}
    for name, value in table.items():
        where = f"expressions.{name}"
        alternatives = []
        for item in value if isinstance(value, list) else [value]:
            if isinstance(item, dict) and item:
                weights = _weights(path, where, item, None)
            elif isinstance(item, str) and item:
                weights = {item: 1.0}
            else:
                raise DataError(
                    f"{path}: [{where}] must be key names or tables like {{ Brows_Up = 1.0 }}, got {item!r}."
                )
            alternatives.append(weights if exact else {canonical_name(key): w for key, w in weights.items()})
        if not alternatives:
            raise DataError(f"{path}: [{where}] names no key.")
        expressions[name] = tuple(alternatives)
    return expressions


def read_convention(path: Path) -> Convention:
    """One convention table of shapekeys/conventions/, validated."""
    data = read_toml_file(path)
    header = data.get("convention")
    if not isinstance(header, dict) or not isinstance(header.get("title"), str):
        raise DataError(f"{path}: needs a [convention] table with a title.")
    prefixes = header.get("prefixes", [])
    minimum = header.get("minimum")
    if not isinstance(prefixes, list) or not all(isinstance(p, str) for p in prefixes):
        raise DataError(f"{path}: [convention] prefixes must be a list of strings.")
    shapes_table = data.get("shapes")
    if not isinstance(shapes_table, dict) or not shapes_table:
        raise DataError(f"{path}: needs a [shapes] table: shape = [spellings].")
    spellings = {
        shape: _spelling_list(path, f"shapes.{shape}", [shape, *(v if isinstance(v, list) else [v])], False)
        for shape, v in shapes_table.items()
    }
    if not isinstance(minimum, int) or not 1 <= minimum <= len(spellings):
        raise DataError(f"{path}: [convention] minimum must be a whole number from 1 to {len(spellings)}.")
    return Convention(
        name=path.stem,
        title=header["title"],
        prefixes=tuple(re.sub(r"[\s.\-]+", "_", p.lower()) for p in prefixes),
        minimum=minimum,
        spellings=spellings,
        visemes=_read_visemes(path, data, spellings),
        expressions=_read_expressions(path, data, exact=False),
    )


def load_conventions(folder: Path = CONVENTIONS_DIR) -> tuple[Convention, ...]:
    """Every convention table in the folder, by file name."""
    paths = sorted(folder.glob("*.toml"))
    if not paths:
        raise DataError(f"No convention tables in {folder}; reinstall the extension.")
    return tuple(read_convention(path) for path in paths)


def read_user_mapping(path: str | Path) -> Convention:
    """A user's own mapping file: the head's keys for the TR visemes and expressions.

    [visemes.<TR viseme>] shapes = { "Their Key" = weight } (optional units and fills), [expressions]
    happy = "Key"; names are the head's, exactly as written; TR visemes left out take their ARKit recipe.
    """
    path = Path(path)
    if not path.is_file():
        raise DataError(
            f"Mapping file not found: {path}. Choose a TOML file mapping TR visemes to your keys."
        )
    data = read_toml_file(path)
    visemes = _read_visemes(path, data, None)
    expressions = _read_expressions(path, data, exact=True)
    names = [name for mapping in visemes.values() for name in mapping.shapes]
    if not names and not expressions:
        raise DataError(
            f"{path} maps no TR viseme or expression to a key; see the manual (Heads: a mapping file) for "
            "its form."
        )
    return Convention(
        name=path.name,
        title=f"own mapping {path.name}",
        prefixes=(),
        minimum=1,
        spellings={name: (name,) for name in dict.fromkeys(names)},
        visemes=visemes,
        expressions=expressions,
        exact=True,
    )
