"""The living layers in the scene: the head turns, the eyes turn and keep their target while it does.

The rotations of `tracks.head_and_eyes` (the character's own frame) become, per moved object or bone:

- a head object and the parts that follow it without being its children: delta transforms (location and
  rotation) keyed about the head's pivot, so the user's own keys, constraints and transforms stay as they
  are (their static deltas are kept and composed with ours);
- eye objects: a turn about the eyeball's fitted centre, whatever the object's origin;
- a head or eye bone of an armature: its rotation, in the armature's action (ours when it has none),
  unless the user animates that bone there (then a warning says how to make room).

Ours are recognisable by a mark, not by name alone: every action we make carries ACTION_TAG, the curves we
add to a user's action are listed in its CURVES_PROPERTY, and the static deltas we found in REST_PROPERTY;
rerunning Generate removes exactly those and puts the user's values back.
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass

import bpy
import numpy as np

from ..core.base.errors import HeadError
from ..core.base.model import EYE_SIDES, WeightTracks
from ..core.base.rotations import eye_matrices, head_matrices
from ..core.motion.frames import decimated_keys
from . import compat, render
from .living_rig import LivingRig, find_rig
from .marked_curves import LIVING, remove_marked_channels, users_paths, write_marked_channels

ACTION_TAG = LIVING.action_tag  # on actions we create for the living motion
CURVES_PROPERTY = LIVING.curves_property  # on any action: the data paths of the curves we added to it
REST_PROPERTY = "tr_living_rest"  # on an object: its static delta transform before ours
# Keys are dropped where linear interpolation between their neighbours keeps every angle of the motion (yaw,
# pitch, roll of the head and of an eye, degrees) this close: a fortieth of the eyes' contact threshold and
# smaller than the microsaccades of a fixating eye, or the 0.44 mm a head turning that much shifts 10 cm
# from its pivot. Every channel of a moved object or bone is keyed on the same frames. (A tenth of a degree
# kept twice the keys, 130,000 for 14 minutes, and took 15 ms longer to key.)
ANGLE_TOLERANCE = 0.25


@dataclass(frozen=True)
class LivingResult:
    moved_objects: tuple[str, ...]
    moved_bones: tuple[str, ...]
    key_count: int
    warnings: tuple[str, ...]


# ---------------------------------------------------------------- before generating


@contextlib.contextmanager
def at_rest(scene: bpy.types.Scene):
    """The scene with our living motion muted and the objects' own deltas back, for reading the rest pose."""
    muted = []
    saved = []
    for obj in scene.objects:
        action = obj.animation_data.action if obj.animation_data else None
        ours = set(action.get(CURVES_PROPERTY, ())) if action is not None else set()
        for fcurve in compat.all_action_fcurves(action) if ours else ():
            if fcurve.data_path in ours and not fcurve.mute:
                fcurve.mute = True
                muted.append(fcurve)
        rest = _rest_of(obj, bool(ours))
        if rest is not None:
            saved.append((obj, _deltas_of(obj)))
            _set_deltas(obj, rest)
    changed = bool(muted or saved)  # else the scene is at rest as it is (an update costs 1.6 ms)
    if changed:
        bpy.context.view_layer.update()
    try:
        yield
    finally:
        for fcurve in muted:
            fcurve.mute = False
        for obj, values in saved:
            _set_deltas(obj, values)
        if changed:
            bpy.context.view_layer.update()


def rig_and_target(
    context: bpy.types.Context, head: bpy.types.Object, head_objects, target_name: str = ""
) -> tuple[LivingRig, np.ndarray]:
    """The head's rig at rest and the point its eyes seek: the target object, else the scene's camera, else
    where the render's own camera will stand."""
    scene = context.scene
    with at_rest(scene):
        rig = find_rig(head)
        if target_name:
            target = bpy.data.objects.get(target_name)
            if target is None:
                raise HeadError(
                    f"There is no object named {target_name!r} to look at: choose the gaze target."
                )
            point = np.array(target.matrix_world.translation)
        elif scene.camera is not None:
            point = np.array(scene.camera.matrix_world.translation)
        else:
            centre, distance, _sensor, _size = render.camera_placement(scene, head_objects, rig.frame)
            point = np.array(centre) + rig.frame[:, 2] * distance
    return rig, point


# ---------------------------------------------------------------- keying


def key_living_motion(
    context: bpy.types.Context,
    rig: LivingRig | None,
    tracks: WeightTracks,
    start_frame: float,
    *,
    clear: bool = True,
) -> LivingResult:
    """Replace our living motion with the tracks' rotations (or just remove it when they have none: then
    the rig is not needed). clear=False keys beside the living motion already there: the next character
    of a conversation, after the first cleared the scene of the last Generate's."""
    if clear:
        remove_living_motion(context.scene)
        context.view_layer.update()  # the rest pose, without our deltas, for the parents' frames
    motion = tracks.head_and_eyes
    if rig is None or motion is None or not len(motion.head):
        return LivingResult((), (), 0, ())
    keyed = _KeyedMotion(rig, motion, float(start_frame))
    warnings: list[str] = list(rig.warnings)
    moved_objects, moved_bones, key_count = [], [], 0
    head_moved_by_bone = rig.armature is not None
    eye_objects = {eye.object_name: side for side, eye in rig.eyes.items() if eye.object_name}
    movers = [] if head_moved_by_bone else [rig.head, *rig.parts]
    for name in dict.fromkeys([*movers, *eye_objects]):
        obj = bpy.data.objects.get(name)
        if obj is None:
            continue
        parent_moves = _parent_moves(obj, rig, set(movers))
        if name in eye_objects:
            parts = (eye_objects[name],) if parent_moves else ("head", eye_objects[name])
        elif parent_moves:
            continue  # a child of the head follows it
        else:
            parts = ("head",)
        written, problem = _key_object(obj, *keyed.world(parts))
        if problem:
            warnings.append(problem)
        elif written:
            moved_objects.append(name)
            key_count += written
    if rig.armature is not None:
        armature = bpy.data.objects[rig.armature]
        bones = {rig.head_bone: keyed.world(("head",))}
        if rig.eyes_turn_by == "bones":
            bones |= {rig.eyes[side].bone_name: keyed.world((side,)) for side in EYE_SIDES}
        written, problem = _key_bones(armature, bones)
        if problem:
            warnings.append(problem)
        else:
            key_count += written
            moved_bones.extend(bones)
    return LivingResult(tuple(moved_objects), tuple(moved_bones), key_count, tuple(warnings))


class _KeyedMotion:
    """World motions of the head, an eye, or an eye carried by the head, at the frames their keys need."""

    def __init__(self, rig: LivingRig, motion, start_frame: float):
        self.rig, self.motion, self.start_frame = rig, motion, start_frame
        self._worlds: dict[tuple[str, ...], tuple[np.ndarray, np.ndarray]] = {}

    def world(self, parts: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray]:
        """(scene frames, (K, 4, 4) world motions) of the parts composed ('head', then an eye side): keyed
        where linear interpolation would leave one of their angles more than ANGLE_TOLERANCE off, and
        computed only there."""
        if parts not in self._worlds:
            angles = {"head": self.motion.head, **{side: self._eye(side) for side in self.rig.eyes}}
            keep = decimated_keys(np.hstack([angles[part] for part in parts]), ANGLE_TOLERANCE)
            world = np.broadcast_to(np.eye(4), (keep.size, 4, 4))
            for part in parts:
                if part == "head":
                    turn = _about(self.rig.pivot, self.rig.frame, head_matrices(angles[part][keep]))
                else:
                    turn = _about(
                        self.rig.eyes[part].centre, self.rig.frame, eye_matrices(angles[part][keep])
                    )
                world = world @ turn
            self._worlds[parts] = (keep + self.start_frame, world)
        return self._worlds[parts]

    def _eye(self, side: str) -> np.ndarray:
        return getattr(self.motion, f"{side}_eye")


def _about(point: np.ndarray, frame: np.ndarray, rotations: np.ndarray) -> np.ndarray:
    """(N, 4, 4) world motions: the head-frame rotations turned about a world point."""
    world = frame @ rotations @ frame.T
    motion = np.zeros((len(rotations), 4, 4))
    motion[:, :3, :3] = world
    motion[:, :3, 3] = point - world @ point
    motion[:, 3, 3] = 1.0
    return motion


def _parent_moves(obj: bpy.types.Object, rig: LivingRig, movers: set[str]) -> bool:
    parent = obj.parent
    if parent is None:
        return False
    if parent.name in movers:
        return True
    if rig.armature is not None and parent.name == rig.armature and obj.parent_type == "BONE":
        bone = parent.data.bones.get(obj.parent_bone)
        while bone is not None:
            if bone.name == rig.head_bone:
                return True
            bone = bone.parent
    return False


def _key_object(obj: bpy.types.Object, frames: np.ndarray, motion_world: np.ndarray) -> tuple[int, str]:
    """Key obj's delta transforms at the frames so that it moves by motion_world (N, 4, 4) from its rest
    pose."""
    mode = obj.rotation_mode
    if mode == "AXIS_ANGLE":
        return 0, f"{obj.name!r} rotates by axis and angle, which has no delta rotation: it stays still."
    rotation_path = "delta_rotation_quaternion" if mode == "QUATERNION" else "delta_rotation_euler"
    action = obj.animation_data.action if obj.animation_data else None
    if action is not None:
        if users_paths(action) & {"delta_location", rotation_path}:
            return 0, (
                f"{obj.name!r} already has animated delta transforms of its own, so the head's and eyes' "
                "motion was not keyed on it; clear them (Object > Animation) to let it move."
            )
    rest = _rest_of(obj, action is not None and CURVES_PROPERTY in action) or _deltas_of(obj)
    obj[REST_PROPERTY] = rest
    location = np.array(obj.location)
    rest_location = np.array(rest["location"])
    # The parent's world frame and its inverse. Small matrices by mathutils: numpy would hand each to BLAS,
    # whose threads then spin a tenth of a second on the other cores.
    parent = obj.matrix_world @ obj.matrix_basis.inverted_safe()
    parent_frame, parent_inverse = np.array(parent), np.array(parent.inverted_safe())
    local = parent_inverse @ motion_world @ parent_frame
    rotation, shift = local[:, :3, :3], local[:, :3, 3]
    rest_rotation = _rest_delta_matrix(rest, mode)
    delta_location = np.einsum("nij,j->ni", rotation, location + rest_location) + shift - location
    delta_rotation = rotation @ rest_rotation
    rotation_values = _quaternions(delta_rotation) if mode == "QUATERNION" else _eulers(delta_rotation, mode)
    channels = {"delta_location": (frames, delta_location), rotation_path: (frames, rotation_values)}
    return write_marked_channels(obj, channels, LIVING), ""


def _key_bones(
    armature: bpy.types.Object, bones: dict[str, tuple[np.ndarray, np.ndarray]]
) -> tuple[int, str]:
    """Each bone turned by its world motion relative to its rest (bone -> (frames, (N, 4, 4) motions)),
    keyed in the armature's action (ours when it has none); refused for a bone whose rotation the user
    animates there."""
    armature_rotation = armature.matrix_world.to_3x3()  # mathutils, as in _key_object
    armature_rotation *= 1.0 / (np.cbrt(abs(armature_rotation.determinant())) or 1.0)
    action = armature.animation_data.action if armature.animation_data else None
    theirs = users_paths(action)
    channels = {}
    for bone_name, (frames, motion) in bones.items():
        bone = armature.data.bones[bone_name]
        rest = armature_rotation @ bone.matrix_local.to_3x3()
        local = np.array(rest.inverted_safe()) @ motion[:, :3, :3] @ np.array(rest)
        pose = armature.pose.bones[bone_name]
        path = f'pose.bones["{bpy.utils.escape_identifier(bone_name)}"].'
        if pose.rotation_mode == "QUATERNION":
            path, values = path + "rotation_quaternion", _quaternions(local)
        elif pose.rotation_mode != "AXIS_ANGLE":
            path, values = path + "rotation_euler", _eulers(local, pose.rotation_mode)
        else:
            return (
                0,
                f"The bone {bone_name!r} rotates by axis and angle: set it to quaternion to let it move.",
            )
        if path in theirs:
            return 0, (
                f"The bone {bone_name!r} is animated by {action.name!r} already, so the head's motion was "
                "not keyed on it; key it on a layer of your own (NLA) and generate again."
            )
        channels[path] = (frames, values)
    return write_marked_channels(armature, channels, LIVING), ""


# ---------------------------------------------------------------- removing


def remove_living_motion(scene: bpy.types.Scene) -> int:
    """Our living motion off every object of the scene, their own deltas back; returns curves removed."""
    removed = 0
    for obj in scene.objects:
        action = obj.animation_data.action if obj.animation_data else None
        rest = _rest_of(obj, action is not None and CURVES_PROPERTY in action)
        removed += remove_marked_channels(obj, LIVING)
        if rest is not None:
            _set_deltas(obj, rest)
        obj.pop(REST_PROPERTY, None)
    return removed


def _rest_of(obj: bpy.types.Object, moved_by_us: bool):
    """The object's own static deltas under ours: as we kept them, else (a library override reopened: the
    properties we add to one are not saved) those of the linked object it overrides; None where we never
    moved it."""
    if REST_PROPERTY in obj:
        return obj[REST_PROPERTY]
    override = obj.override_library
    if moved_by_us and override is not None and override.reference is not None:
        return _deltas_of(override.reference)
    return None


# ---------------------------------------------------------------- delta transforms and rotations


def _deltas_of(obj: bpy.types.Object) -> dict:
    return {
        "location": list(obj.delta_location),
        "euler": list(obj.delta_rotation_euler),
        "quaternion": list(obj.delta_rotation_quaternion),
    }


def _set_deltas(obj: bpy.types.Object, values) -> None:
    obj.delta_location = tuple(values["location"])
    obj.delta_rotation_euler = tuple(values["euler"])
    obj.delta_rotation_quaternion = tuple(values["quaternion"])


def _rest_delta_matrix(rest, mode: str) -> np.ndarray:
    from mathutils import Euler, Quaternion

    if mode == "QUATERNION":
        return np.array(Quaternion(rest["quaternion"]).to_matrix())
    return np.array(Euler(rest["euler"], mode).to_matrix())


def _quaternions(rotations: np.ndarray) -> np.ndarray:
    """(N, 4) w, x, y, z of (N, 3, 3) rotations (Shepperd's method), continuous in sign."""
    m = np.asarray(rotations, np.float64).reshape(-1, 3, 3)
    trace = np.einsum("nii->n", m)
    candidates = np.stack([trace, m[:, 0, 0], m[:, 1, 1], m[:, 2, 2]], axis=1)
    best = candidates.argmax(axis=1)
    q = np.empty((len(m), 4))
    for case in range(4):
        rows = best == case
        r = m[rows]
        if case == 0:
            s = np.sqrt(1.0 + trace[rows]) * 2
            q[rows] = np.stack(
                [
                    s / 4,
                    (r[:, 2, 1] - r[:, 1, 2]) / s,
                    (r[:, 0, 2] - r[:, 2, 0]) / s,
                    (r[:, 1, 0] - r[:, 0, 1]) / s,
                ],
                axis=1,
            )
        else:
            i = case - 1
            j, k = (i + 1) % 3, (i + 2) % 3
            s = np.sqrt(1.0 + r[:, i, i] - r[:, j, j] - r[:, k, k]) * 2
            part = np.empty((rows.sum(), 4))
            part[:, 0] = (r[:, k, j] - r[:, j, k]) / s
            part[:, 1 + i] = s / 4
            part[:, 1 + j] = (r[:, j, i] + r[:, i, j]) / s
            part[:, 1 + k] = (r[:, k, i] + r[:, i, k]) / s
            q[rows] = part
    q *= np.where(q[:, :1] < 0, -1.0, 1.0)
    return q


def _eulers(rotations: np.ndarray, order: str) -> np.ndarray:
    """(N, 3) Euler angles of (N, 3, 3) rotations in the given order (small turns: no wrapping)."""
    m = np.asarray(rotations, np.float64).reshape(-1, 3, 3)
    if order == "XYZ":  # R = Rz Ry Rx, Blender's default
        y = np.arcsin(np.clip(-m[:, 2, 0], -1, 1))
        return np.stack([np.arctan2(m[:, 2, 1], m[:, 2, 2]), y, np.arctan2(m[:, 1, 0], m[:, 0, 0])], axis=1)
    from mathutils import Matrix

    return np.array([tuple(Matrix(r.tolist()).to_euler(order)) for r in m]).reshape(-1, 3)
