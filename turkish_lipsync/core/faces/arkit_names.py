"""The 52 ARKit face units, and matching a head's own shape-key names to them.

Artists and exporters spell the same unit in many ways (jawOpen, JawOpen, jaw_open, JAW_OPEN,
eyeBlink_L, EyeBlinkLeft, "blendShape1.jawOpen", "ARKit_mouthSmile_R"), so names are compared
after reducing them to a canonical form: no prefix, lower case, no separators, side as "left"/"right".
"""

from __future__ import annotations

import re

ARKIT_UNITS: tuple[str, ...] = (
    "browDownLeft",
    "browDownRight",
    "browInnerUp",
    "browOuterUpLeft",
    "browOuterUpRight",
    "cheekPuff",
    "cheekSquintLeft",
    "cheekSquintRight",
    "eyeBlinkLeft",
    "eyeBlinkRight",
    "eyeLookDownLeft",
    "eyeLookDownRight",
    "eyeLookInLeft",
    "eyeLookInRight",
    "eyeLookOutLeft",
    "eyeLookOutRight",
    "eyeLookUpLeft",
    "eyeLookUpRight",
    "eyeSquintLeft",
    "eyeSquintRight",
    "eyeWideLeft",
    "eyeWideRight",
    "jawForward",
    "jawLeft",
    "jawOpen",
    "jawRight",
    "mouthClose",
    "mouthDimpleLeft",
    "mouthDimpleRight",
    "mouthFrownLeft",
    "mouthFrownRight",
    "mouthFunnel",
    "mouthLeft",
    "mouthLowerDownLeft",
    "mouthLowerDownRight",
    "mouthPressLeft",
    "mouthPressRight",
    "mouthPucker",
    "mouthRight",
    "mouthRollLower",
    "mouthRollUpper",
    "mouthShrugLower",
    "mouthShrugUpper",
    "mouthSmileLeft",
    "mouthSmileRight",
    "mouthStretchLeft",
    "mouthStretchRight",
    "mouthUpperUpLeft",
    "mouthUpperUpRight",
    "noseSneerLeft",
    "noseSneerRight",
    "tongueOut",
)

# Units that move the mouth: the part of an emotion that a viseme must be able to override.
MOUTH_UNIT_PREFIXES: tuple[str, ...] = ("mouth", "jaw", "tongue", "cheekPuff")

# Units that must be present before a head's own keys count as an ARKit basis: the mouth cannot
# speak without opening and closing, and the emotions need the smile and the brows.
ESSENTIAL_UNITS: tuple[str, ...] = ("jawOpen", "mouthClose", "mouthFunnel", "mouthPucker")


def is_mouth_unit(unit: str) -> bool:
    return unit.startswith(MOUTH_UNIT_PREFIXES)


def _canonical(name: str) -> str:
    """Reduce a key name to lower-case letters with the side spelt out at the end ("...left")."""
    # Drop exporter prefixes: "blendShape1.jawOpen", "Face|mouthClose", "ARKit:eyeBlink_L".
    name = re.split(r"[|:]", name)[-1]
    head, dot, tail = name.rpartition(".")
    if dot and len(tail) > 2:
        name = tail
    elif dot:
        name = head + "_" + tail  # "cheekSquint.R": the dot is a side separator
    for prefix in ("arkit_", "arkit", "bs_", "blendshape_"):
        if name.lower().startswith(prefix) and len(name) > len(prefix) + 3:
            name = name[len(prefix) :]
            break
    # Side suffixes: _L, .L, -L, _l, Left, _left, L (after a lower-case letter: eyeBlinkL).
    side = ""
    match = re.search(r"(?:[_\-\s]?(left|right)|[_\-\s]([lr])|(?<=[a-z])([LR]))$", name, re.IGNORECASE)
    if match:
        token = (match.group(1) or match.group(2) or match.group(3)).lower()
        side = "left" if token.startswith("l") else "right"
        name = name[: match.start()]
    letters = re.sub(r"[^a-z0-9]", "", name.lower())
    return letters + side


_CANONICAL_UNITS: dict[str, str] = {_canonical(unit): unit for unit in ARKIT_UNITS}


def arkit_unit_for_key(key_name: str) -> str | None:
    """The ARKit unit a shape-key name stands for, or None."""
    return _CANONICAL_UNITS.get(_canonical(key_name))


def match_arkit_keys(key_names: list[str] | tuple[str, ...]) -> dict[str, str]:
    """Map ARKit unit -> the head's key name, for every key that names a unit (first one wins)."""
    matched: dict[str, str] = {}
    for key_name in key_names:
        unit = arkit_unit_for_key(key_name)
        if unit is not None and unit not in matched:
            matched[unit] = key_name
    return matched


def has_arkit_basis(matched: dict[str, str]) -> bool:
    """True when the matched keys are enough to build visemes and emotions from."""
    return all(unit in matched for unit in ESSENTIAL_UNITS) and len(matched) >= 20


def missing_units(units) -> tuple[str, ...]:
    """The ARKit units a basis (unit -> deltas) lacks."""
    return tuple(unit for unit in ARKIT_UNITS if unit not in units)


def missing_units_warning(head_name: str, missing: tuple[str, ...]) -> str:
    shown = ", ".join(missing[:8]) + (f" and {len(missing) - 8} more" if len(missing) > 8 else "")
    return (
        f"{head_name!r} lacks {len(missing)} of the 52 ARKit units ({shown}); the visemes and emotions that "
        "use them are weaker. Add those keys, or choose the transfer source to carry them over."
    )
