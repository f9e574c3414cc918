"""A character kept in its own file and linked into shots with a library override.

A linked mesh's data stays linked in the shot: a shot cannot add shape keys to it, and keys (or their
animation) given to an override of the mesh alone are dropped when the library changes and the override is
resynced. What an override keeps is what its objects' overridable properties hold, their animation included.
So, in the character's own file, our keys are made linkable: each is driven by a custom property of the head
object of the same name (library-overridable), which makes the mesh part of every override of the character
(its keys read an overridden object); Generate then keys those properties on the head's action, in the
character's own file and in every shot alike. Rigs need nothing of this: an override animates its bones.
"""

from __future__ import annotations

import bpy
import numpy as np

from ..core.base.errors import HeadError
from ..core.base.model import WeightTracks
from .keyframes import curve_data_path, property_path
from .marked_curves import LINKED_KEYS, remove_marked_channels, write_marked_channels
from .owned_keys import owned_keys
from .rig_drivers import LINKING_VARIABLE

# The head's properties stay within what a key may weigh.
PROPERTY_RANGE = (-2.0, 2.0)


def make_keys_linkable(head: bpy.types.Object, parts) -> int:
    """Drive our keys on the head and its parts by the head's properties of their names; returns how many
    keys were driven (those already driven so are left as they are)."""
    if head.library is not None or head.override_library is not None:
        raise HeadError(
            f"{head.name!r} is linked: make its keys linkable in the character's own file, then save it."
        )
    names = owned_keys(head)
    if not names:
        raise HeadError(f"{head.name!r} has no lip-sync shape keys to make linkable: build them first.")
    for name in names:
        if name not in head.keys():
            head[name] = 0.0
            head.id_properties_ui(name).update(min=PROPERTY_RANGE[0], max=PROPERTY_RANGE[1], default=0.0)
        head.property_overridable_library_set(property_path(name), True)
    driven = 0
    for obj in [head, *parts]:
        key = obj.data.shape_keys if obj.type == "MESH" else None
        if key is None:
            continue
        for name, key_name in owned_keys(obj).items():
            if name in names and not _driven_by_head(key, key_name):
                fcurve = key.key_blocks[key_name].driver_add("value")
                fcurve.driver.type = "SUM"
                variable = fcurve.driver.variables.new()
                variable.name = LINKING_VARIABLE
                variable.type = "SINGLE_PROP"
                variable.targets[0].id = head
                variable.targets[0].data_path = property_path(name)
                driven += 1
    return driven


def _driven_by_head(key: bpy.types.Key, key_name: str) -> bool:
    drivers = key.animation_data.drivers if key.animation_data else ()
    path = curve_data_path(key_name)
    return any(
        fc.data_path == path and any(v.name == LINKING_VARIABLE for v in fc.driver.variables)
        for fc in drivers
    )


def is_linkable(head: bpy.types.Object) -> bool:
    """Whether the head's keys are driven by its own properties (Generate keys those)."""
    key = head.data.shape_keys if head.type == "MESH" else None
    names = owned_keys(head)
    return key is not None and bool(names) and all(_driven_by_head(key, n) for n in names.values())


def write_property_tracks(
    head: bpy.types.Object, tracks: WeightTracks, start_frame: float
) -> tuple[str, int]:
    """The tracks of our keys on the head's properties that drive them, replacing ours; returns the action's
    name and the count of keys."""
    remove_marked_channels(head, LINKED_KEYS)
    names = owned_keys(head)
    channels = {}
    for track in tracks.tracks:
        if track.name in names and len(track.frames):
            channels[property_path(track.name)] = (
                np.asarray(track.frames) + float(start_frame),
                track.values,
            )
    for name in set(names) - {t.name for t in tracks.tracks if len(t.frames)}:
        head[name] = 0.0  # our keys without a track in this utterance rest (no stale weight)
    interpolation = (
        tracks.interpolation if tracks.interpolation in ("LINEAR", "BEZIER", "CONSTANT") else "LINEAR"
    )
    written = write_marked_channels(head, channels, LINKED_KEYS, interpolation) if channels else 0
    action = head.animation_data.action if head.animation_data else None
    return (action.name if action is not None else ""), written
