"""Face rigs: poses of an armature for the visemes, emotions or ARKit units, and the bone motion a speech's
weight tracks give through them (bpy-free; blender/face_rig.py reads and keys the armature).

A pose is what each bone it moves does from its rest: a location and a turn in the bone's own rest axes, a
scale added to 1, and custom properties (the sliders a rig's drivers read) added to their rest values.
A target is a built key's name (TR_viseme_a, TR_emotion_happy, TR_blink_left, TR_eye_left_look_up) or
an ARKit unit (jawOpen). A track with a pose of its own moves the rig by that pose; any other track moves
it through its recipe's ARKit units, those the rig has poses for: a rig with one pose per unit speaks every
viseme, and a pose recorded for one viseme replaces what the units would make of it.

Weights combine as the shape keys they stand in for do, linearly, in the bones' local (pose) space: at
every frame a bone's location is the weighted sum of the poses' locations, its scale 1 plus the weighted
sum of theirs less 1, a property its rest value plus the weighted sum of the poses' changes, and its turn
the weighted sum of the poses' rotation vectors (axis times angle: the logarithm of each pose's quaternion,
summed and turned back into a quaternion). The rotation sum is the weighted sum of quaternions taken about
identity, in the tangent space where it is exact for one pose at any weight (a pose at 0.5 is the slerp
halfway from rest, and at 1 the pose), commutative, and additive as shape keys are (a negative weight, an
emotion's mouth release, takes its turn back). Pose libraries and Rhubarb Lipsync NG blend one pose at a
time from the current one, which suits cue after cue but not the dozen overlapping weights
co-articulation gives a frame.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ..base.model import (
    EMOTION_MOUTH_RELEASE_SUFFIX,
    EMOTIONS,
    LOOK_KEYS,
    OWNED_PREFIX,
    VISEME_KEY_PREFIX,
    WeightTracks,
    emotion_key_name,
    emotion_release_key_name,
)
from .arkit_names import ARKIT_UNITS, is_mouth_unit
from .recipes import Recipes, load_recipes

ZERO = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class BoneMove:
    """One bone's part of a pose, from its rest pose, in the bone's own rest axes (armature units)."""

    location: tuple[float, float, float] = ZERO
    rotation: tuple[float, float, float] = ZERO  # rotation vector: axis times angle in radians
    scale: tuple[float, float, float] = ZERO  # added to the rest scale of 1
    properties: Mapping[str, float] = field(default_factory=dict)  # custom property -> change from rest

    def is_rest(self, tolerance: float = 1e-6) -> bool:
        moves = np.abs(np.concatenate([self.location, self.rotation, self.scale]))
        return bool(moves.max() <= tolerance) and all(abs(v) <= tolerance for v in self.properties.values())

    def scaled(self, factor: float) -> BoneMove:
        return BoneMove(
            tuple(factor * v for v in self.location),
            tuple(factor * v for v in self.rotation),
            tuple(factor * v for v in self.scale),
            {name: factor * value for name, value in self.properties.items()},
        )


@dataclass(frozen=True)
class Pose:
    """What the armature does for one target: bone name -> its move; where the pose came from."""

    bones: Mapping[str, BoneMove]
    source: str = ""


@dataclass(frozen=True)
class RigMapping:
    """The poses of one rig, by target (a built key's name or an ARKit unit)."""

    name: str
    title: str
    poses: Mapping[str, Pose]

    def bones(self) -> set[str]:
        return {bone for pose in self.poses.values() for bone in pose.bones}


def pose_targets(recipes: Recipes | None = None) -> tuple[str, ...]:
    """Every name a pose may be recorded for: the built keys a track may carry, then the 52 ARKit units."""
    keys = [name for name in (recipes or load_recipes()).key_recipes() if not is_release(name)]
    return (*keys, *LOOK_KEYS, *ARKIT_UNITS)


def pose_target_label(target: str) -> str:
    """How the panel names a pose target: TR_viseme_a as "viseme a", ARKit's units as they are."""
    return target.removeprefix(OWNED_PREFIX).replace("_", " ")


def is_release(name: str) -> bool:
    return name.endswith(EMOTION_MOUTH_RELEASE_SUFFIX)


def with_own_poses(mapping: RigMapping | None, own: Mapping[str, Pose], name: str, title: str) -> RigMapping:
    """The mapping with the user's own poses added, each replacing the mapping's pose of its target."""
    poses = dict(mapping.poses) if mapping is not None else {}
    poses.update(own)
    return RigMapping(name, title, poses)


# ---------------------------------------------------------------- from tracks to bone motion


@dataclass(frozen=True, eq=False)
class BoneMotion:
    """The bones' channels at the frames to key (utterance frames, 0 = its start), and what moves them."""

    frames: np.ndarray  # (K,)
    weights: np.ndarray  # (K, targets): each pose's weight there
    locations: dict[str, np.ndarray]  # bone -> (K, 3), in its rest axes
    rotations: dict[str, np.ndarray]  # bone -> (K, 4) quaternions w, x, y, z
    scales: dict[str, np.ndarray]  # bone -> (K, 3), 1 at rest
    properties: dict[tuple[str, str], np.ndarray]  # (bone, property) -> (K,) change from the rest value
    driven: frozenset[str]  # the tracks the rig moves (a head's shape keys need not key them)
    interpolation: str

    def at(self, keep: np.ndarray) -> BoneMotion:
        """The motion at some of its frames only (indices into frames)."""

        def pick(channels: dict) -> dict:
            return {name: values[keep] for name, values in channels.items()}

        return BoneMotion(
            frames=self.frames[keep],
            weights=self.weights[keep],
            locations=pick(self.locations),
            rotations=pick(self.rotations),
            scales=pick(self.scales),
            properties=pick(self.properties),
            driven=self.driven,
            interpolation=self.interpolation,
        )


def target_weights(
    tracks: WeightTracks, mapping: RigMapping, recipes: Recipes | None = None
) -> tuple[tuple[str, ...], np.ndarray, dict[str, Pose], frozenset[str]]:
    """(targets, (frames, targets) weights at every frame, the poses by target, the tracks that drive them).

    A track with a pose takes it; any other adds its recipe's units to theirs; an emotion's mouth release
    takes the mouth bones of its emotion's own pose back (its recipe's units do the same for unit poses)."""
    recipes_by_key = (recipes or load_recipes()).key_recipes()
    poses = dict(mapping.poses)
    poses.update(_release_poses(mapping))
    names, weights = tracks.sample(np.arange(tracks.frame_count, dtype=np.float64))
    columns: dict[str, np.ndarray] = {}
    driven = set()
    for column, name in enumerate(names):
        if name in poses:
            columns[name] = columns.get(name, 0.0) + weights[:, column]
            driven.add(name)
            continue
        for unit, share in recipes_by_key.get(name, {}).items():
            if unit in poses and share:
                columns[unit] = columns.get(unit, 0.0) + share * weights[:, column]
                driven.add(name)
    targets = tuple(columns)
    matrix = np.stack([columns[t] for t in targets], axis=1) if targets else np.zeros((len(weights), 0))
    return targets, matrix, {t: poses[t] for t in targets}, frozenset(driven)


def _release_poses(mapping: RigMapping) -> dict[str, Pose]:
    """Each emotion posed as a whole gets its mouth release: the negated moves of the bones any viseme or
    mouth unit of the mapping moves (its mouth bones), so that closures close under the emotion."""
    mouth = {
        bone
        for target, pose in mapping.poses.items()
        if target.startswith(VISEME_KEY_PREFIX) or is_mouth_unit(target)
        for bone in pose.bones
    }
    releases = {}
    for emotion in EMOTIONS:
        pose = mapping.poses.get(emotion_key_name(emotion))
        if pose is not None:
            bones = {bone: move.scaled(-1.0) for bone, move in pose.bones.items() if bone in mouth}
            releases[emotion_release_key_name(emotion)] = Pose(bones, f"the mouth of {pose.source}")
    return releases


def bone_motion(tracks: WeightTracks, mapping: RigMapping, recipes: Recipes | None = None) -> BoneMotion:
    """Every bone's channels the mapping's poses give the tracks at each frame of the utterance (see the
    module's note on blending)."""
    targets, weights, poses, driven = target_weights(tracks, mapping, recipes)
    locations, rotations, scales, properties = {}, {}, {}, {}
    for bone in sorted({b for pose in poses.values() for b in pose.bones}):
        moves = [poses[t].bones.get(bone, BoneMove()) for t in targets]
        channels = {
            kind: np.array([getattr(m, kind) for m in moves]).reshape(-1, 3)
            for kind in ("location", "rotation", "scale")
        }
        if np.any(channels["location"]):
            locations[bone] = np.einsum("kt,tc->kc", weights, channels["location"])
        if np.any(channels["rotation"]):
            rotations[bone] = quaternions(np.einsum("kt,tc->kc", weights, channels["rotation"]))
        if np.any(channels["scale"]):
            scales[bone] = 1.0 + np.einsum("kt,tc->kc", weights, channels["scale"])
        for name in sorted({p for m in moves for p in m.properties}):
            changes = np.array([m.properties.get(name, 0.0) for m in moves])
            properties[(bone, name)] = np.einsum("kt,t->k", weights, changes)
    return BoneMotion(
        frames=np.arange(len(weights), dtype=np.float64),
        weights=weights,
        locations=locations,
        rotations=rotations,
        scales=scales,
        properties=properties,
        driven=driven,
        interpolation=tracks.interpolation,
    )


def quaternions(rotation_vectors: np.ndarray) -> np.ndarray:
    """(N, 4) unit quaternions w, x, y, z of (N, 3) rotation vectors (the exponential map)."""
    vectors = np.asarray(rotation_vectors, np.float64).reshape(-1, 3)
    angles = np.linalg.norm(vectors, axis=1)
    half = angles / 2
    # sin(a/2)/a, with its limit 1/2 where the angle vanishes.
    factor = np.where(angles > 1e-12, np.sin(half) / np.where(angles > 1e-12, angles, 1.0), 0.5)
    return np.column_stack([np.cos(half), vectors * factor[:, None]])


def rotation_vectors(quaternion_values: np.ndarray) -> np.ndarray:
    """(N, 3) rotation vectors of (N, 4) quaternions w, x, y, z (the logarithm; the shorter way round)."""
    q = np.asarray(quaternion_values, np.float64).reshape(-1, 4)
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    q = np.where(q[:, :1] < 0, -q, q)
    sines = np.linalg.norm(q[:, 1:], axis=1)
    angles = 2 * np.arctan2(sines, q[:, 0])
    factor = np.where(sines > 1e-12, angles / np.where(sines > 1e-12, sines, 1.0), 2.0)
    return q[:, 1:] * factor[:, None]


# ---------------------------------------------------------------- poses given in the character's frame


@dataclass(frozen=True)
class FrameMove:
    """A bone's move as a mapping file writes it: in the character's frame (left, up, forward)."""

    turn_degrees: tuple[float, float, float] = ZERO  # rotation vector, degrees
    move: tuple[float, float, float] = ZERO  # in lengths: the mapping's, or this move's own
    scale: tuple[float, float, float] = ZERO  # in the bone's own axes, added to 1
    properties: Mapping[str, float] = field(default_factory=dict)
    length: tuple[str, str] | None = None  # two bones whose heads are this move's length apart


def resolve_moves(
    poses: Mapping[str, Mapping[str, FrameMove]],
    bone_axes: Mapping[str, np.ndarray],
    length_of,
    source: str,
) -> dict[str, Pose]:
    """Poses in the bones' own axes from moves in the character's frame: bone_axes gives each bone's rest
    axes as the columns of a (3, 3) matrix in the character's frame, length_of(pair) a move's length in
    armature units (the mapping's for None)."""
    resolved = {}
    for target, moves in poses.items():
        bones = {}
        for bone, move in moves.items():
            to_bone = np.asarray(bone_axes[bone], np.float64).T
            length = length_of(move.length) if any(move.move) else 1.0
            bones[bone] = BoneMove(
                location=tuple(float(v) for v in to_bone @ (np.asarray(move.move) * length)),
                rotation=tuple(float(v) for v in to_bone @ np.radians(move.turn_degrees)),
                scale=tuple(move.scale),
                properties=dict(move.properties),
            )
        resolved[target] = Pose(bones, source)
    return resolved


def mirrored_move(move: FrameMove, other_side) -> FrameMove:
    """The same move on the other side of the face: a move's left component and a turn's up and forward
    components change sign (a turn is an axial vector); other_side renames a bone to its twin."""
    left, up, forward = move.move
    turn_left, turn_up, turn_forward = move.turn_degrees
    return FrameMove(
        turn_degrees=(turn_left, -turn_up, -turn_forward),
        move=(-left, up, forward),
        scale=move.scale,
        properties=dict(move.properties),
        length=tuple(other_side(bone) for bone in move.length) if move.length else None,
    )
