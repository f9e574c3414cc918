"""Poses of a character's own, recorded from its armature: as it is posed now (Pose Mode, or a pose asset
applied from the Asset Shelf), or as an action (a pose asset is one) holds it at a frame. Kept with the
character's set-up on the armature (face_rig.RIG_PROPERTY), each replacing the mapping's pose of its target.
"""

from __future__ import annotations

import dataclasses
import re

import bpy
import numpy as np
from mathutils import Euler, Matrix, Quaternion, Vector

from ..core.base.errors import HeadError
from ..core.faces.rig_poses import BoneMove, Pose, pose_targets, rotation_vectors
from . import compat
from .face_rig import property_default, store_setup, stored_setup
from .marked_curves import FACE_RIG, LIVING, marked_paths

# A bone counts as posed where it is this far from its rest (armature units, radians, scale).
POSED = 1e-5
_BONE_CHANNEL = re.compile(
    r'^pose\.bones\["((?:[^"\\]|\\.)*)"\]\.(location|rotation_quaternion|rotation_euler|scale)$'
)
_BONE_PROPERTY = re.compile(r'^pose\.bones\["((?:[^"\\]|\\.)*)"\]\["((?:[^"\\]|\\.)*)"\]$')


def record_current_pose(armature: bpy.types.Object, target: str, frame: float) -> Pose:
    """The armature's pose now (every bone off its rest, every custom property of a bone off its default)
    as the pose of target; the bones our living layer turns (head, eyes) are left out, and so are bones as
    our speech keys have them at this frame (only what the user posed is recorded)."""
    _check_target(target)
    living = _living_bones(armature)
    ours = _our_speech_values(armature, frame)
    bones = {}
    for pose_bone in armature.pose.bones:
        if pose_bone.name in living:
            continue
        move = _move_of(
            _posed_basis(pose_bone, ours.get(pose_bone.name, {})), _properties_off_default(pose_bone)
        )
        if not move.is_rest(POSED):
            bones[pose_bone.name] = move
    return _stored(armature, target, Pose(bones, "posed in the panel"))


def _posed_basis(pose_bone: bpy.types.PoseBone, keyed: dict[tuple[str, int], float]) -> Matrix:
    """The bone's basis with the channels as our keys have them put back at rest (what the user posed)."""
    if not keyed or pose_bone.rotation_mode == "AXIS_ANGLE":
        return pose_bone.matrix_basis
    rotation = "rotation_quaternion" if pose_bone.rotation_mode == "QUATERNION" else "rotation_euler"
    values = {}
    for channel in ("location", rotation, "scale"):
        current = list(getattr(pose_bone, channel))
        rest = {"rotation_quaternion": [1.0, 0.0, 0.0, 0.0], "scale": [1.0, 1.0, 1.0]}.get(channel, [0.0] * 3)
        values[channel] = {
            index: rest[index] if keyed.get((channel, index)) == round(value, 5) else value
            for index, value in enumerate(current)
        }
    return _basis(values, pose_bone.rotation_mode)


def _our_speech_values(armature: bpy.types.Object, frame: float) -> dict[str, dict[tuple[str, int], float]]:
    """bone -> (channel, index) -> the value our face-rig keys give it at frame, rounded."""
    action = armature.animation_data.action if armature.animation_data else None
    ours = marked_paths(action, FACE_RIG)
    values: dict[str, dict[tuple[str, int], float]] = {}
    for fcurve in compat.all_action_fcurves(action) if ours else ():
        found = _BONE_CHANNEL.match(fcurve.data_path)
        if fcurve.data_path in ours and found:
            channel = (found.group(2), fcurve.array_index)
            values.setdefault(found.group(1), {})[channel] = round(fcurve.evaluate(frame), 5)
    return values


def record_action_pose(
    armature: bpy.types.Object, target: str, action: bpy.types.Action, frame: float
) -> Pose:
    """What the action (a pose asset, or any action) holds for the armature's bones at frame, as the pose
    of target."""
    _check_target(target)
    channels: dict[str, dict[str, list]] = {}
    for fcurve in compat.all_action_fcurves(action):
        found = _BONE_CHANNEL.match(fcurve.data_path)
        if found and found.group(1) in armature.pose.bones:
            values = channels.setdefault(found.group(1), {}).setdefault(found.group(2), {})
            values[fcurve.array_index] = fcurve.evaluate(frame)
        found = _BONE_PROPERTY.match(fcurve.data_path)
        if found and found.group(1) in armature.pose.bones:
            bone = armature.pose.bones[found.group(1)]
            properties = channels.setdefault(found.group(1), {}).setdefault("properties", {})
            properties[found.group(2)] = fcurve.evaluate(frame) - _default(bone, found.group(2))
    bones = {}
    for name, values in channels.items():
        properties = {k: v for k, v in values.get("properties", {}).items() if abs(v) > POSED}
        move = _move_of(_basis(values, armature.pose.bones[name].rotation_mode), properties)
        if not move.is_rest(POSED):
            bones[name] = move
    if not bones:
        raise HeadError(
            f"The action {action.name!r} moves none of {armature.name!r}'s bones at frame {frame:g}: choose "
            "the action (or pose asset) made for this rig, and the frame that holds the pose."
        )
    return _stored(armature, target, Pose(bones, f"{action.name}, frame {frame:g}"))


def clear_pose(armature: bpy.types.Object, target: str) -> bool:
    own = stored_setup(armature)
    if target not in own.poses:
        return False
    poses = {name: pose for name, pose in own.poses.items() if name != target}
    store_setup(armature, dataclasses.replace(own, poses=poses))
    return True


def _stored(armature: bpy.types.Object, target: str, pose: Pose) -> Pose:
    if not pose.bones:
        raise HeadError(
            f"{armature.name!r} is at its rest pose: pose the bones for {target} (Pose Mode) first, then "
            "record the pose."
        )
    own = stored_setup(armature)
    store_setup(armature, dataclasses.replace(own, poses={**own.poses, target: pose}))
    return pose


def _check_target(target: str) -> None:
    if target not in pose_targets():
        raise HeadError(
            f"{target!r} is neither a viseme, an emotion nor an ARKit unit a pose can be made for."
        )


def _living_bones(armature: bpy.types.Object) -> set[str]:
    action = armature.animation_data.action if armature.animation_data else None
    return {path.split('"')[1] for path in marked_paths(action, LIVING) if path.startswith("pose.bones")}


def _move_of(basis: Matrix, properties: dict[str, float]) -> BoneMove:
    location, rotation, scale = basis.decompose()
    return BoneMove(
        location=tuple(location),
        rotation=tuple(rotation_vectors(np.array([tuple(rotation)]))[0]),
        scale=tuple(np.array(scale) - 1.0),
        properties=properties,
    )


def _basis(values: dict, rotation_mode: str) -> Matrix:
    """A pose bone's basis matrix from the action's channels (missing ones at rest)."""
    location = Vector([values.get("location", {}).get(i, 0.0) for i in range(3)])
    if "rotation_quaternion" in values:
        rotation = Quaternion(
            [values["rotation_quaternion"].get(i, 1.0 if i == 0 else 0.0) for i in range(4)]
        )
    else:
        order = rotation_mode if rotation_mode not in ("QUATERNION", "AXIS_ANGLE") else "XYZ"
        rotation = Euler(
            [values.get("rotation_euler", {}).get(i, 0.0) for i in range(3)], order
        ).to_quaternion()
    scale = Vector([values.get("scale", {}).get(i, 1.0) for i in range(3)])
    return Matrix.LocRotScale(location, rotation.normalized(), scale)


def _properties_off_default(pose_bone: bpy.types.PoseBone) -> dict[str, float]:
    changed = {}
    for name in pose_bone.keys():
        value = pose_bone[name]
        if isinstance(value, int | float) and not isinstance(value, bool):
            change = float(value) - _default(pose_bone, name)
            if abs(change) > POSED:
                changed[name] = change
    return changed


def _default(pose_bone: bpy.types.PoseBone, name: str) -> float:
    default = property_default(pose_bone, name)
    return 0.0 if default is None else default
