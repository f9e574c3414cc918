"""A head whose shape keys its bones drive (Faceit's ARKit control rig and rigs like it): speak through the
bones, not underneath them.

Keys written under a driver are overridden by it, and keys on meshes a rig drives fight the rig the animator
uses. So where the head's ARKit units (or our TR keys) are driven by drivers that read an armature's bones
(their transforms or custom properties), each driven key gets the pose of its controls that sets it to 1,
found by moving each control a little each way and reading the keys Blender evaluates (drivers may scale,
offset and clamp; the found pose is checked and refined where the response is not linear). Drivers that read
nothing Generate can move are refused with a message saying what to do.
"""

from __future__ import annotations

from dataclasses import dataclass

import bpy
import numpy as np
from mathutils import Quaternion, Vector

from ..core.base.errors import HeadError
from ..core.faces.arkit_names import match_arkit_keys
from ..core.faces.rig_poses import BoneMove, Pose, RigMapping
from . import compat
from .marked_curves import FACE_RIG, marked_paths
from .owned_keys import owned_keys

LINKING_VARIABLE = "tr_weight"  # the variable of the drivers blender/linking.py adds (not a rig's)
_AXES = {"X": 0, "Y": 1, "Z": 2}
_STEP_OF_LENGTH = 0.02  # a control moved this share of its bone's length (or these radians) to probe
_STEP_RADIANS = 0.02
_CLOSE_ENOUGH = 0.02  # a found pose sets its key within this of 1
_REFINEMENTS = 6


@dataclass(frozen=True)
class Control:
    """One channel of a bone a driver reads: location, rotation or scale along an axis, or a property."""

    bone: str
    kind: str  # "location", "rotation", "scale" or "property"
    axis: int = 0
    name: str = ""  # the property's name

    def move(self, amount: float) -> BoneMove:
        vector = [0.0, 0.0, 0.0]
        vector[self.axis] = amount
        if self.kind == "property":
            return BoneMove(properties={self.name: amount})
        return BoneMove(**{self.kind: tuple(vector)})


def driven_face_rig(head: bpy.types.Object, armature_hint: bpy.types.Object | None = None):
    """The FaceRig of a head whose keys its bones drive, or None where none of its keys is driven so."""
    from .face_rig import FaceRig

    key = head.data.shape_keys if head.type == "MESH" else None
    drivers = list(key.animation_data.drivers) if key is not None and key.animation_data else []
    targets = _driven_targets(head, [_block_name(fc.data_path) for fc in drivers])
    controls: dict[str, list[tuple[bpy.types.Object, Control]]] = {}
    unreadable = []
    for fcurve in drivers:
        target = targets.get(_block_name(fcurve.data_path))
        if target is None or any(v.name == LINKING_VARIABLE for v in fcurve.driver.variables):
            continue
        found = [control for v in fcurve.driver.variables for control in _controls_of(v)]
        if found:
            controls[target] = found
        else:
            unreadable.append(_block_name(fcurve.data_path))
    if unreadable:
        raise HeadError(
            f"{len(unreadable)} shape keys of {head.name!r} that speak are driven by drivers that read no "
            f"bone Generate can move ({', '.join(sorted(unreadable)[:4])}): keys written under a driver are "
            "overridden by it. Drive them from bones of an armature (as a control rig does), or remove those "
            "drivers, and generate again."
        )
    if not controls:
        return None
    armatures = [armature for found in controls.values() for armature, _control in found]
    armature = max(set(armatures), key=armatures.count) if armature_hint not in armatures else armature_hint
    poses, lost = _probe_poses(key, armature, controls)
    warnings = ()
    if lost:
        warnings = (
            f"The drivers of {head.name!r}'s keys {', '.join(sorted(lost)[:4])} did not reach 1 from any of "
            f"the {armature.name!r} bones they read, so those keys stay still; check their drivers.",
        )
    mapping = RigMapping("drivers", "Driven Keys", poses)
    return FaceRig(armature.name, mapping, warnings)


def _block_name(data_path: str) -> str:
    return data_path.split('"')[1] if data_path.startswith("key_blocks[") else ""


def _driven_targets(head: bpy.types.Object, driven: list[str]) -> dict[str, str]:
    """Driven key name -> what it stands for: an ARKit unit (its own keys), or our key's name."""
    targets = {key_name: unit for unit, key_name in match_arkit_keys([n for n in driven if n]).items()}
    ours = {key_name: name for name, key_name in owned_keys(head).items()}
    targets.update({name: ours[name] for name in driven if name in ours})
    return targets


def _controls_of(variable) -> list[tuple[bpy.types.Object, Control]]:
    """What of an armature a driver's variable reads."""
    found = []
    for target in variable.targets:
        armature = target.id
        if not isinstance(armature, bpy.types.Object) or armature.type != "ARMATURE":
            continue
        if variable.type == "TRANSFORMS" and target.bone_target in armature.pose.bones:
            kind, _, axis = target.transform_type.partition("_")
            if axis in _AXES:
                kinds = {"LOC": "location", "ROT": "rotation", "SCALE": "scale"}
                found.append((armature, Control(target.bone_target, kinds[kind], _AXES[axis])))
        elif variable.type == "SINGLE_PROP":
            control = _control_at(armature, target.data_path)
            if control is not None:
                found.append((armature, control))
    return found


def _control_at(armature: bpy.types.Object, path: str) -> Control | None:
    """pose.bones["b"].location[1] or pose.bones["b"]["prop"] as a Control."""
    if not path.startswith('pose.bones["'):
        return None
    bone, _, rest = path[len('pose.bones["') :].partition('"]')
    if bone not in armature.pose.bones:
        return None
    for kind in ("location", "scale"):
        if rest.startswith(f".{kind}[") and rest[-2:-1].isdigit():
            return Control(bone, kind, int(rest[-2]))
    if rest.startswith('["') and rest.endswith('"]'):
        return Control(bone, "property", name=rest[2:-2])
    return None


# ---------------------------------------------------------------- probing


def _probe_poses(
    key: bpy.types.Key, armature: bpy.types.Object, controls
) -> tuple[dict[str, Pose], set[str]]:
    """For each driven target, the amount of one of its controls that sets it to 1 (of the controls on this
    armature, the one that gets there with the least motion)."""
    names = {target: key_name for key_name, target in _names_by_target(key, controls).items()}
    order = list(names)
    poses: dict[str, Pose] = {}
    amounts: dict[str, float] = {}
    distinct = {control for found in controls.values() for owner, control in found if owner == armature}
    with _Probe(key, armature, distinct) as probe:
        rest = probe.values([names[t] for t in order])
        for control in sorted(distinct, key=lambda c: (c.bone, c.kind, c.axis, c.name)):
            readers = [t for t in order if control in {c for a, c in controls[t] if a == armature}]
            for sign in (1.0, -1.0):
                step = sign * probe.step(control)
                probe.set(control, step)
                slopes = (probe.values([names[t] for t in order]) - rest) / step
                for target in readers:
                    slope = slopes[order.index(target)]
                    if slope * sign <= 1e-9:
                        continue
                    guess = (1.0 - rest[order.index(target)]) / slope
                    amount = probe.amount_for_one(names[target], control, guess)
                    if amount is not None and abs(amount) < abs(amounts.get(target, np.inf)):
                        amounts[target] = amount
                        poses[target] = Pose(
                            {control.bone: control.move(amount)}, f"the drivers of {names[target]}"
                        )
                probe.set(control, 0.0)
    return poses, set(order) - set(poses)


def _names_by_target(key: bpy.types.Key, controls) -> dict[str, str]:
    """Driven key name -> the target it stands for, for the targets with controls."""
    by_target = {}
    driven = [_block_name(fcurve.data_path) for fcurve in key.animation_data.drivers]
    matched = match_arkit_keys([name for name in driven if name])
    for name in driven:
        for target in controls:
            if name and (name == target or matched.get(target) == name):
                by_target[name] = target
    return by_target


class _Probe:
    """The controls moved one at a time, the driven keys read as Blender evaluates them; every control put
    back as it was (and our keys on them, muted meanwhile, unmuted) when done."""

    _CHANNELS = ("location", "rotation_quaternion", "rotation_euler", "scale")

    def __init__(self, key: bpy.types.Key, armature: bpy.types.Object, controls) -> None:
        self.key, self.armature, self.controls = key, armature, controls
        bones = armature.pose.bones
        self.saved = {
            c.bone: tuple(tuple(getattr(bones[c.bone], channel)) for channel in self._CHANNELS)
            for c in controls
        }
        self.rests = {
            (c.bone, c.name): float(bones[c.bone][c.name]) for c in controls if c.kind == "property"
        }
        action = armature.animation_data.action if armature.animation_data else None
        ours = marked_paths(action, FACE_RIG)
        self.muted = (
            [fc for fc in compat.all_action_fcurves(action) if fc.data_path in ours] if action else []
        )

    def __enter__(self) -> _Probe:
        for fcurve in self.muted:
            fcurve.mute = True
        for control in self.controls:  # poses are from the rest pose: every control starts there
            self.set(control, 0.0)
        return self

    def __exit__(self, *_exception) -> None:
        for fcurve in self.muted:
            fcurve.mute = False
        bones = self.armature.pose.bones
        for bone, values in self.saved.items():
            for channel, value in zip(self._CHANNELS, values, strict=True):
                setattr(bones[bone], channel, value)
        for (bone, name), value in self.rests.items():
            bones[bone][name] = value
        bpy.context.view_layer.update()

    def step(self, control: Control) -> float:
        if control.kind == "location":
            return _STEP_OF_LENGTH * self.armature.data.bones[control.bone].length
        return _STEP_RADIANS

    def values(self, names: list[str]) -> np.ndarray:
        bpy.context.view_layer.update()
        evaluated = self.key.evaluated_get(bpy.context.evaluated_depsgraph_get())
        return np.array([evaluated.key_blocks[name].value for name in names])

    def set(self, control: Control, amount: float) -> None:
        pose_bone = self.armature.pose.bones[control.bone]
        if control.kind == "property":
            pose_bone[control.name] = self.rests[(control.bone, control.name)] + amount
        elif control.kind == "location":
            pose_bone.location[control.axis] = amount
        elif control.kind == "scale":
            pose_bone.scale[control.axis] = 1.0 + amount
        elif pose_bone.rotation_mode == "QUATERNION":
            axis = Vector((0.0, 0.0, 0.0))
            axis[control.axis] = 1.0
            pose_bone.rotation_quaternion = Quaternion(axis, amount)
        else:
            pose_bone.rotation_euler[control.axis] = amount

    def amount_for_one(self, key_name: str, control: Control, guess: float) -> float | None:
        """The amount of the control setting the key to 1, from a first guess: secant steps where the
        driver is not linear; None where it does not get there."""
        previous_amount, previous_value = 0.0, float(self.values([key_name])[0])
        amount = guess
        for _ in range(_REFINEMENTS):
            self.set(control, amount)
            value = float(self.values([key_name])[0])
            if abs(value - 1.0) <= _CLOSE_ENOUGH:
                return amount
            if abs(value - previous_value) < 1e-9:
                return None
            amount, previous_amount, previous_value = (
                amount + (1.0 - value) * (amount - previous_amount) / (value - previous_value),
                amount,
                value,
            )
        return None


def has_driven_keys(head: bpy.types.Object) -> bool:
    """Whether any of the head's ARKit or TR keys is driven by an armature's bones (cheap: no probing)."""
    key = head.data.shape_keys if head.type == "MESH" else None
    drivers = list(key.animation_data.drivers) if key is not None and key.animation_data else []
    targets = _driven_targets(head, [_block_name(fc.data_path) for fc in drivers])
    return any(
        _block_name(fc.data_path) in targets
        and not any(v.name == LINKING_VARIABLE for v in fc.driver.variables)
        and any(_controls_of(v) for v in fc.driver.variables)
        for fc in drivers
    )
