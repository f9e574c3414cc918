"""Which shape keys are ours: a mark on the key datablock, not the TR_ prefix of a name.

A user may sculpt a key of their own and call it TR_viseme_a. Builds, rebuilds and the keyframe writer
touch only the keys our builds marked; ours are built beside a user's key of the same name under a free
one (TR_viseme_a.001), and the mark maps each of our keys' names (what the tracks and recipes call it)
to the key that holds it.
"""

from __future__ import annotations

import bpy

from ..core.base.model import OWNED_PREFIX

# On the mesh's Key datablock: our key's name -> the name of the shape key that holds it.
OWNED_KEYS_PROPERTY = "tr_owned_keys"
# Written by builds before the mark existed: their keys are ours (TR_* and these ARKit names).
LEGACY_BUILD_PROPERTY = "tr_key_sources"
LEGACY_ARKIT_PROPERTY = "tr_built_arkit_keys"


def owned_keys(obj: bpy.types.Object) -> dict[str, str]:
    """Our keys on obj that still exist: our name -> the shape key's name."""
    data = getattr(obj, "data", None)
    key = getattr(data, "shape_keys", None)
    if key is None:
        return {}
    blocks = key.key_blocks
    stored = key.get(OWNED_KEYS_PROPERTY)
    if stored is None:
        if data.get(LEGACY_BUILD_PROPERTY) is None:
            return {}  # never built here: every key on it is the user's
        legacy = set(data.get(LEGACY_ARKIT_PROPERTY, ()))
        return {
            block.name: block.name
            for block in blocks
            if block != key.reference_key and (block.name.startswith(OWNED_PREFIX) or block.name in legacy)
        }
    return {str(ours): str(name) for ours, name in stored.items() if str(name) in blocks}


def mark_owned(obj: bpy.types.Object, names: dict[str, str]) -> None:
    """Record our keys on obj's Key (replacing the previous record)."""
    obj.data.shape_keys[OWNED_KEYS_PROPERTY] = dict(names)


def disown(obj: bpy.types.Object, ours) -> None:
    """Hand some of our keys over to the user (they are theirs from now on, as if they had made them)."""
    names = owned_keys(obj)
    for name in ours:
        names.pop(name, None)
    if obj.data.shape_keys is not None:
        mark_owned(obj, names)


def free_name(blocks, wanted: str) -> str:
    """wanted, or wanted.001, .002 ... : the first name no shape key has."""
    if wanted not in blocks:
        return wanted
    number = 1
    while f"{wanted}.{number:03d}" in blocks:
        number += 1
    return f"{wanted}.{number:03d}"
