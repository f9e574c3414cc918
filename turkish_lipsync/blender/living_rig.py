"""How a head turns its eyes and itself: eye objects, eyeball islands, eye bones, look keys; a head bone or
the head object; the head's own frame and the pivot it turns about. Read from the scene, bpy-free math in
core/faces/eyes.py.

A rig is found again at every Generate (names only are kept), with our own motion taken out first, so the
rest pose it reads is the user's.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import bpy
import numpy as np

from ..core.base.model import EYE_SIDES
from ..core.faces.eyes import own_look_keys, round_pieces, sphere_fit
from ..core.motion.living import GazeSetup
from . import mesh
from .heads import find_head_parts

# Eyes sit about this many eye separations above and in front of the top of the neck (the atlanto-occipital
# joint), where a head without a head bone nods and turns.
PIVOT_BELOW_EYES = 1.2
PIVOT_BEHIND_EYES = 1.35
REACH_DEGREES = 50.0  # a target further from the face's facing than this is out of the eyes' reach
TYPICAL_EYE_SEPARATION = 0.45  # of the head's width, where no eyes are found
_HEAD_BONE = re.compile(r"(^|[^a-z])head($|[^a-z])", re.IGNORECASE)
_NECK_BONE = re.compile(r"neck", re.IGNORECASE)
_EYE_BONE = re.compile(r"eye(?!lid|brow|lash)", re.IGNORECASE)
_LEFT = re.compile(r"(\.|_|-|\b)(l|left)(\b|_|\.|$)|left", re.IGNORECASE)


@dataclass(frozen=True)
class Eye:
    side: str
    centre: np.ndarray  # world, rest
    object_name: str | None = None  # an eye object that turns as a whole
    bone_name: str | None = None  # an eye bone of the armature


@dataclass(frozen=True, eq=False)
class LivingRig:
    """Names and rest geometry of what moves (world space)."""

    head: str
    frame: np.ndarray  # (3, 3) columns: the character's left, up, forward in world axes
    pivot: np.ndarray  # (3,) where the head turns
    eyes: dict[str, Eye]  # by side; empty when none was found
    eyes_turn_by: str  # "objects", "bones", "keys" or "none"
    armature: str | None = None
    head_bone: str | None = None
    parts: tuple[str, ...] = ()  # meshes that follow the head (teeth, tongue, eyes, lashes)
    warnings: tuple[str, ...] = field(default_factory=tuple)

    def to_head(self, points: np.ndarray) -> np.ndarray:
        """World points in the head's frame, relative to the pivot."""
        return (np.asarray(points, np.float64) - self.pivot) @ self.frame

    def gaze_setup(self, target: np.ndarray | None) -> tuple[GazeSetup, str]:
        """The core's view of the eyes and of a world-space target point (straight ahead without one), and
        a warning where the target lies out of the eyes' reach (behind or far beside the face)."""
        if len(self.eyes) == 2:
            left, right = (self.to_head(self.eyes[side].centre) for side in EYE_SIDES)
        else:
            left, right = np.array([0.03, 0.075, 0.085]), np.array([-0.03, 0.075, 0.085])
        middle = (left + right) / 2
        kwargs = {
            "eye_separation": float(np.linalg.norm(left - right)),
            "eyes_above_pivot": float(middle[1]),
            "eyes_before_pivot": float(middle[2]),
        }
        if target is None:
            return GazeSetup(**kwargs), ""
        seen = self.to_head(target) - middle
        distance = max(float(np.linalg.norm(seen)), 0.05)
        yaw = float(np.degrees(np.arctan2(seen[0], seen[2])))
        pitch = float(np.degrees(np.arctan2(seen[1], np.hypot(seen[0], seen[2]))))
        if abs(yaw) > REACH_DEGREES or abs(pitch) > REACH_DEGREES:
            warning = (
                f"The gaze target is {abs(yaw):.0f} degrees to the side of where {self.head!r} faces (and "
                f"{pitch:.0f} up), out of the eyes' reach, so they look straight ahead instead; place the "
                "camera or the target in front of the face."
            )
            return GazeSetup(target_distance=distance, **kwargs), warning
        return GazeSetup(target_yaw=yaw, target_pitch=pitch, target_distance=distance, **kwargs), ""


def find_rig(head: bpy.types.Object, parts: list[bpy.types.Object] | None = None) -> LivingRig:
    parts = [p for p in (find_head_parts(head) if parts is None else parts) if p is not head]
    vertices = mesh.world_rest_coordinates(head).astype(np.float64)
    low, high = vertices.min(axis=0), vertices.max(axis=0)
    centre, size = (low + high) / 2, float(np.max(high - low))
    armature = armature_of(head)
    head_bone = (_bone_named(armature, _HEAD_BONE) or _bone_named(armature, _NECK_BONE)) if armature else None
    warnings: list[str] = []
    found, turn_by = _eye_centres(head, parts, armature, vertices, size)
    found = _pair(found, centre)
    eye_middle = np.mean([point for point, _ in found], axis=0) if found else centre
    frame = _frame(eye_middle, centre, size)
    eyes = {}
    for point, names in found:
        side = "left" if (point - centre) @ frame[:, 0] > 0 else "right"
        eyes[side] = Eye(side, point, **names)
    if len(eyes) < 2:
        eyes, turn_by = {}, "none"
        warnings.append(
            f"No eyes were found on {head.name!r} (eye objects, eyeballs, eye bones or look keys), so its "
            "eyes stay still; the head still moves and blinks."
        )
    separation = (
        float(np.linalg.norm(eyes["left"].centre - eyes["right"].centre))
        if eyes
        else TYPICAL_EYE_SEPARATION * float(np.ptp(vertices @ frame[:, 0]))
    )
    if armature is not None and head_bone is not None:
        pivot = _bone_head(armature, head_bone)
    else:
        pivot = (
            eye_middle
            - frame[:, 1] * PIVOT_BELOW_EYES * separation
            - frame[:, 2] * PIVOT_BEHIND_EYES * separation
        )
    return LivingRig(
        head=head.name,
        frame=frame,
        pivot=pivot,
        eyes=eyes,
        eyes_turn_by=turn_by,
        armature=armature.name if armature is not None and head_bone else None,
        head_bone=head_bone,
        parts=tuple(p.name for p in parts),
        warnings=tuple(warnings),
    )


def _eye_centres(head, parts, armature, vertices: np.ndarray, size: float) -> tuple[list, str]:
    """The eyes' centres (each with what turns it) and how they turn: objects of their own, else bones,
    else islands of the head's mesh, else what look keys move ("none" where fewer than two are found)."""
    found: list[tuple[np.ndarray, dict]] = []
    for part in parts:
        if part.type == "MESH" and len(part.data.vertices) >= 12:
            points = mesh.world_rest_coordinates(part).astype(np.float64)
            ball_centre, radius, spread = sphere_fit(points)
            if spread < 0.25 and 0.01 * size < radius < 0.06 * size:
                found.append((ball_centre, {"object_name": part.name}))
    if len(found) >= 2:
        return found, "objects"
    if armature is not None:
        found = [
            (_bone_head(armature, bone.name), {"bone_name": bone.name})
            for bone in armature.data.bones
            if _EYE_BONE.search(bone.name) and not bone.children
        ]
        if len(found) == 2:
            return found, "bones"
    balls = round_pieces(vertices, mesh.triangles(head), size)
    found = [(ball.centre, {}) for ball in balls]
    moved = _look_key_centres(head, vertices) if len(found) < 2 else []
    found = found if len(found) >= 2 else moved
    return found, "keys" if len(found) >= 2 else "none"


def _frame(eye_middle: np.ndarray, centre: np.ndarray, size: float) -> np.ndarray:
    """Left, up, forward as columns: up is the world's Z, forward the horizontal way from the head's
    centre to its eyes (-Y where the eyes sit less than 2 % of the head's size off its centre)."""
    up = np.array([0.0, 0.0, 1.0])
    forward = eye_middle - centre
    forward[2] = 0.0
    length = np.linalg.norm(forward)
    forward = forward / length if length > 0.02 * size else np.array([0.0, -1.0, 0.0])
    left = np.cross(up, forward)
    return np.column_stack([left, up, forward])


def _pair(found: list[tuple[np.ndarray, dict]], centre: np.ndarray) -> list[tuple[np.ndarray, dict]]:
    """The two candidates that mirror each other best across the head (eyes come in pairs): as high and as
    far from the head's centre as each other; the higher pair where two pairs fit alike."""
    if len(found) <= 2:
        return found
    best, pair = np.inf, found[:2]
    for i in range(len(found)):
        for j in range(i + 1, len(found)):
            a, b = found[i][0] - centre, found[j][0] - centre
            if np.linalg.norm(a - b) < 1e-6:
                continue
            mismatch = abs(a[2] - b[2]) + abs(np.linalg.norm(a[:2]) - np.linalg.norm(b[:2]))
            score = mismatch - 1e-3 * (a[2] + b[2])
            if score < best:
                best, pair = score, [found[i], found[j]]
    return pair


def _look_key_centres(head: bpy.types.Object, world: np.ndarray) -> list[tuple[np.ndarray, dict]]:
    """Painted eyes: the middle of what the head's own look keys move, on each side of the head."""
    keys = head.data.shape_keys
    if keys is None:
        return []
    looks = own_look_keys([block.name for block in keys.key_blocks])
    names = {name for name, _both in looks.values()}
    if not names:
        return []
    count = len(head.data.vertices)
    rest = mesh.read_coordinates(keys.reference_key.points, count)
    moved = np.zeros(count, bool)
    for name in names:
        displacement = np.linalg.norm(
            mesh.read_coordinates(keys.key_blocks[name].points, count) - rest, axis=1
        )
        moved |= displacement > 0.1 * displacement.max(initial=0.0) + 1e-9
    if moved.sum() < 2:
        return []
    points = world[moved]
    middle_x = float(np.median(world[:, 0]))
    across = points[:, 0] - middle_x
    sides = [points[across > 0], points[across <= 0]]
    if min(len(s) for s in sides) == 0:
        return []
    return [(s.mean(axis=0), {}) for s in sides]


def armature_of(head: bpy.types.Object) -> bpy.types.Object | None:
    for modifier in head.modifiers:
        if modifier.type == "ARMATURE" and modifier.object is not None:
            return modifier.object
    parent = head.parent
    return parent if parent is not None and parent.type == "ARMATURE" else None


def _bone_named(armature: bpy.types.Object, pattern: re.Pattern) -> str | None:
    matches = [bone.name for bone in armature.data.bones if pattern.search(bone.name)]
    return min(matches, key=len) if matches else None


def _bone_head(armature: bpy.types.Object, bone_name: str) -> np.ndarray:
    bone = armature.data.bones[bone_name]
    point = np.array([*bone.head_local, 1.0])
    return (np.array(armature.matrix_world) @ point)[:3]
