"""Weight tracks to shape-key F-curves, in bulk.

Keys are written with ``keyframe_points.add`` and ``foreach_set``: one call per curve instead of one Python
call per key, which keeps a minute of speech at 37+ curves well under a second. Only the curves of our
keys (those our builds marked, blender/owned_keys.py) are written and replaced; a user's own key named
TR_viseme_a, and anything else the user animated on the same Key, survive.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import bpy
import numpy as np

from ..core.base.model import EMOTION_KEY_PREFIX, VISEME_KEY_PREFIX, Track, WeightTracks
from . import compat
from .marked_curves import INTERPOLATION_VALUES, LINKED_KEYS, marked_paths
from .owned_keys import owned_keys

ACTION_TAG = "turkish_lipsync_utterance"  # custom property on the actions we create
KEY_ID_TYPE = "KEY"


@dataclass(frozen=True)
class WrittenAction:
    """What was written on one shape-key datablock (names only: safe across undo)."""

    object_name: str
    key_name: str
    action_name: str
    curve_count: int
    key_count: int


def property_path(name: str) -> str:
    """The data path of an object's custom property."""
    return f'["{bpy.utils.escape_identifier(name)}"]'


def curve_data_path(shape_key_name: str) -> str:
    return f'key_blocks["{bpy.utils.escape_identifier(shape_key_name)}"].value'


def group_name_for(shape_key_name: str) -> str:
    if shape_key_name.startswith(VISEME_KEY_PREFIX):
        return "TR visemes"
    if shape_key_name.startswith(EMOTION_KEY_PREFIX):
        return "TR emotions"
    return "TR face"


def our_curve_paths(objects) -> set[str]:
    """The data paths of the curves of our keys on the objects (by our mark, not by name)."""
    return {curve_data_path(name) for obj in objects if obj is not None for name in owned_keys(obj).values()}


def _has_foreign_curves(action: bpy.types.Action, key: bpy.types.Key, ours: set[str]) -> bool:
    channels = compat.action_channels(action, key, KEY_ID_TYPE, create=False)
    return channels is not None and any(fc.data_path not in ours for fc in channels.fcurves)


def _action_for(key: bpy.types.Key, action_name: str, ours: set[str]) -> bpy.types.Action:
    """The action to write into: the current one when it animates anything else (kept whole), else ours."""
    current = key.animation_data.action if key.animation_data else None
    if current is not None and _has_foreign_curves(current, key, ours):
        return current
    existing = bpy.data.actions.get(action_name)
    if existing is not None and existing.get(ACTION_TAG):
        return existing
    action = bpy.data.actions.new(action_name)
    action[ACTION_TAG] = True
    return action


def _remove_our_curves(channels: compat.Channels, ours: set[str]) -> int:
    curves = [fc for fc in channels.fcurves if fc.data_path in ours]
    for fcurve in curves:
        channels.fcurves.remove(fcurve)
    return len(curves)


def _write_curve(channels: compat.Channels, name: str, key_name: str, frames, values, interp: int):
    """A curve for our key `name`, held by the shape key key_name."""
    fcurve = compat.new_fcurve(channels, curve_data_path(key_name), group_name_for(name))
    count = len(frames)
    fcurve.keyframe_points.add(count)
    coordinates = np.empty(2 * count, dtype=np.float32)
    coordinates[0::2] = frames
    coordinates[1::2] = values
    fcurve.keyframe_points.foreach_set("co", coordinates)
    fcurve.keyframe_points.foreach_set("interpolation", np.full(count, interp, dtype=np.int32))
    if interp == INTERPOLATION_VALUES["BEZIER"]:
        # Only Bezier segments use handles. Tracks come sorted, so linear and constant curves need no
        # update (sorting and handle recalculation would be 40% of the writing time).
        fcurve.update()
    return count


def shape_key_owners(objects) -> list[tuple[bpy.types.Object, bpy.types.Key]]:
    """Each distinct shape-key datablock among objects, with the first object that uses it."""
    seen: set[str] = set()
    owners = []
    for obj in objects:
        key = getattr(obj.data, "shape_keys", None) if obj is not None else None
        if key is None or key.name in seen:
            continue
        seen.add(key.name)
        owners.append((obj, key))
    return owners


def write_weight_tracks(
    objects, tracks: WeightTracks, start_frame: float, action_name: str
) -> tuple[WrittenAction, ...]:
    """Key every track on the head, and on each part whose keys it moves (teeth, tongue, eyes follow).

    Frames in ``tracks`` count from the utterance start at the scene frame rate; they are shifted by
    start_frame. The first object's action is named action_name, the others get their object name appended.
    """
    interpolation = INTERPOLATION_VALUES.get(tracks.interpolation)
    if interpolation is None:
        raise ValueError(
            f"unknown interpolation {tracks.interpolation!r}; use one of {list(INTERPOLATION_VALUES)}"
        )
    written = []
    for position, (obj, key) in enumerate(shape_key_owners(objects)):
        names = owned_keys(obj)  # our key -> the shape key holding it: only those are keyed
        # The head keys every track; its parts only the keys that move them (the teeth need no blink).
        wanted = set(names) if position == 0 else moving_keys(key, names)
        available = [t for t in tracks.tracks if t.name in wanted and len(t.frames)]
        if not available:
            continue
        ours = our_curve_paths([obj])
        name = action_name if position == 0 else f"{action_name}.{obj.name}"
        action = _action_for(key, name, ours)
        compat.assign_action(key, action, KEY_ID_TYPE)
        channels = compat.action_channels(action, key, KEY_ID_TYPE, create=True)
        _remove_our_curves(channels, ours)
        # Our keys without a track in this utterance rest at zero (no stale weight from an earlier run).
        keyed = {track.name for track in available}
        for our_name, key_name in names.items():
            if our_name not in keyed:
                key.key_blocks[key_name].value = 0.0
        key_count = 0
        for track in available:
            frames = np.asarray(track.frames, dtype=np.float64) + float(start_frame)
            key_count += _write_curve(
                channels, track.name, names[track.name], frames, track.values, interpolation
            )
        written.append(WrittenAction(obj.name, key.name, action.name, len(available), key_count))
    return tuple(written)


def moving_keys(key: bpy.types.Key, names: dict[str, str]) -> set[str]:
    """Those of our keys (our name -> the shape key holding it) that move this mesh at all: a part has
    every key of the head (so the names line up), but a key that leaves it where it is (the teeth's
    blink) needs no curve."""
    blocks = key.key_blocks
    count = len(blocks[0].points) if len(blocks) else 0
    reference = {}
    moving = set()
    for name, key_name in names.items():
        block = blocks.get(key_name)
        if block is None:
            continue
        relative = block.relative_key
        if relative.name not in reference:
            reference[relative.name] = np.empty(3 * count, np.float32)
            relative.points.foreach_get("co", reference[relative.name])
        coordinates = np.empty(3 * count, np.float32)
        block.points.foreach_get("co", coordinates)
        if block != relative and np.any(np.abs(coordinates - reference[relative.name]) > 1e-7):
            moving.add(name)
    return moving


def remove_weight_tracks(objects) -> int:
    """Remove our F-curves from the objects' shape keys; returns how many were removed."""
    removed = 0
    for obj, key in shape_key_owners(objects):
        action = key.animation_data.action if key.animation_data else None
        if action is None:
            continue
        channels = compat.action_channels(action, key, KEY_ID_TYPE, create=False)
        if channels is None:
            continue
        removed += _remove_our_curves(channels, our_curve_paths([obj]))
    return removed


def _our_curves(objects) -> list[tuple[str, bpy.types.FCurve]]:
    """(our key's name, its curve) of every curve of our keys on the objects' shape keys, and of the head's
    own properties that drive them where its keys are linkable (blender/linking.py)."""
    curves = []
    head = objects[0] if objects else None
    action = head.animation_data.action if head is not None and head.animation_data else None
    linked = marked_paths(action, LINKED_KEYS)
    if linked:
        ours = {property_path(name): name for name in owned_keys(head)}
        curves += [
            (ours[fc.data_path], fc)
            for fc in compat.all_action_fcurves(action)
            if fc.data_path in linked & set(ours)
        ]
    for obj, key in shape_key_owners(objects):
        action = key.animation_data.action if key.animation_data else None
        channels = compat.action_channels(action, key, KEY_ID_TYPE, create=False) if action else None
        if channels is None:
            continue
        ours = {curve_data_path(key_name): name for name, key_name in owned_keys(obj).items()}
        curves += [(ours[fc.data_path], fc) for fc in channels.fcurves if fc.data_path in ours]
    return curves


def key_fingerprint(objects) -> str:
    """A digest of every key of our curves on the objects' shape keys: it changes when a key is edited."""
    digest = hashlib.sha1()
    for _name, fcurve in sorted(_our_curves(objects), key=lambda pair: pair[1].data_path):
        count = len(fcurve.keyframe_points)
        coordinates = np.empty(2 * count, dtype=np.float32)
        fcurve.keyframe_points.foreach_get("co", coordinates)
        digest.update(fcurve.data_path.encode("utf-8"))
        digest.update(coordinates.tobytes())
    return digest.hexdigest()


def read_weight_tracks(objects, start_frame: int, frame_count: int, fps: float) -> WeightTracks:
    """Our keys' weights as the head has them now, frames counted from start_frame (the inverse of
    write_weight_tracks): the keys themselves where all curves are linear or constant, else sampled."""
    curves = {}
    for name, fcurve in _our_curves(objects):
        curves.setdefault(name, fcurve)  # the head's curve first, then its parts'
    interpolations = set()
    for fcurve in curves.values():
        count = len(fcurve.keyframe_points)
        modes = np.empty(count, dtype=np.int32)
        fcurve.keyframe_points.foreach_get("interpolation", modes)
        interpolations |= set(modes.tolist())
    by_value = {value: name for name, value in INTERPOLATION_VALUES.items()}
    if len(interpolations) <= 1 and interpolations <= {
        INTERPOLATION_VALUES["LINEAR"],
        INTERPOLATION_VALUES["CONSTANT"],
    }:
        interpolation = by_value[interpolations.pop()] if interpolations else "LINEAR"
        tracks = []
        for name, fcurve in curves.items():
            count = len(fcurve.keyframe_points)
            coordinates = np.empty(2 * count, dtype=np.float64)
            fcurve.keyframe_points.foreach_get("co", coordinates)
            tracks.append(Track(name, coordinates[0::2] - start_frame, coordinates[1::2]))
    else:
        interpolation = "LINEAR"
        frames = np.arange(frame_count, dtype=np.float64)
        tracks = [
            Track(name, frames, np.array([fcurve.evaluate(start_frame + f) for f in frames]))
            for name, fcurve in curves.items()
        ]
    return WeightTracks(fps=fps, frame_count=frame_count, interpolation=interpolation, tracks=tuple(tracks))
