"""F-curves we add to an object's action, marked as ours so that Generate again replaces exactly those.

The living face (head and eye turns), a face rig (its bones) and a linkable head's key weights (its custom
properties) key an object's action: the user's own action when the object has one (kept whole), else one
of ours. Each marks the data paths it added in a
property of the action, so every curve of the user's, and of the other layer, is left alone.
"""

from __future__ import annotations

from dataclasses import dataclass

import bpy
import numpy as np

from . import compat

OBJECT_ID = "OBJECT"
# Blender's BezTriple interpolation enum values, for foreach_set.
INTERPOLATION_VALUES = {"CONSTANT": 0, "LINEAR": 1, "BEZIER": 2}


@dataclass(frozen=True)
class CurveMark:
    """How one of our layers marks what it keys."""

    curves_property: str  # on any action: the data paths of the curves this layer added to it
    action_tag: str  # on the actions this layer creates
    group: str  # the F-curve group its curves are filed under
    action_prefix: str  # the name of the action it creates: prefix + the object's name


LIVING = CurveMark("tr_living_curves", "turkish_lipsync_living", "TR living", "TR_living.")
FACE_RIG = CurveMark("tr_face_rig_curves", "turkish_lipsync_face_rig", "TR face rig", "TR_face.")
# The weights of a linkable head's keys, on its object (blender/linking.py).
LINKED_KEYS = CurveMark("tr_linked_key_curves", "turkish_lipsync_linked_keys", "TR visemes", "TR_speech.")
MARKS = (LIVING, FACE_RIG, LINKED_KEYS)


def marked_paths(action: bpy.types.Action | None, mark: CurveMark) -> set[str]:
    return set(action.get(mark.curves_property, ())) if action is not None else set()


def users_paths(action: bpy.types.Action | None) -> set[str]:
    """The data paths of the action's curves that none of our layers added: the user's."""
    if action is None:
        return set()
    ours = set().union(*(marked_paths(action, mark) for mark in MARKS))
    return {fc.data_path for fc in compat.all_action_fcurves(action)} - ours


def write_marked_channels(
    owner: bpy.types.Object, channels: dict, mark: CurveMark, interpolation: str = "LINEAR"
) -> int:
    """F-curves for every channel (path -> (frames, (N, k) values)) in the owner's action (ours where it has
    none), keyed on those frames and marked; returns the count of keys."""
    action = owner.animation_data.action if owner.animation_data else None
    if action is None:
        action = bpy.data.actions.new(mark.action_prefix + owner.name)
        action[mark.action_tag] = True
    compat.assign_action(owner, action, OBJECT_ID)
    bag = compat.action_channels(action, owner, OBJECT_ID, create=True)
    mode = INTERPOLATION_VALUES[interpolation]
    written = 0
    for path, (frames, values) in channels.items():
        values = np.asarray(values, np.float64).reshape(len(frames), -1)
        coordinates = np.empty((len(frames), 2), np.float32)
        coordinates[:, 0] = frames
        modes = np.full(len(frames), mode, np.int32)
        for index in range(values.shape[1]):
            fcurve = compat.new_fcurve(bag, path, mark.group, index=index)
            fcurve.keyframe_points.add(len(frames))
            coordinates[:, 1] = values[:, index]
            fcurve.keyframe_points.foreach_set("co", coordinates.ravel())
            fcurve.keyframe_points.foreach_set("interpolation", modes)
            if interpolation == "BEZIER":
                fcurve.update()  # Bezier handles; linear and constant keys come sorted and need none
            written += len(frames)
    action[mark.curves_property] = sorted({*action.get(mark.curves_property, ()), *channels})
    return written


def remove_marked_channels(owner: bpy.types.Object, mark: CurveMark) -> int:
    """The layer's curves off the owner's action (the action too, where it is ours and nothing is left in
    it); returns how many curves were removed."""
    animation = owner.animation_data
    action = animation.action if animation else None
    if action is None or mark.curves_property not in action:
        return 0
    ours = marked_paths(action, mark)
    removed = 0
    bag = compat.action_channels(action, owner, OBJECT_ID, create=False)
    if bag is not None:
        for fcurve in [fc for fc in bag.fcurves if fc.data_path in ours]:
            bag.fcurves.remove(fcurve)
            removed += 1
    del action[mark.curves_property]
    if any(action.get(m.action_tag) for m in MARKS) and not compat.all_action_fcurves(action):
        animation.action = None
        bpy.data.actions.remove(action)
    return removed
