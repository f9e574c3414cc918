"""The face-rig mappings that come with the extension (shapekeys/rigs/*.toml) and a character's own set-up
(stored with its armature as JSON): read and validated here, resolved on the armature by blender/face_rig.py.

A mapping file names the bones it moves (a role and the names a rig may give that bone, first found wins),
the length its moves are measured in (the distance between two bones' heads, so that a mapping fits a rig of
any size), and per target (an ARKit unit or a built key's name) each bone's turn (degrees, a rotation vector
in the character's frame: left, up, forward), move (in lengths) and custom properties. A unit ending in
Left is mirrored to its Right unit, bones renamed by the file's side suffixes (ending the name or a part of
it: lips.L, lid.T.L.002), unless the file writes it.
"""

from __future__ import annotations

import functools
import json
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from ..base.data import DATA_DIR, read_toml_file
from ..base.errors import DataError, HeadError
from .rig_poses import BoneMove, FrameMove, Pose, mirrored_move, pose_targets

RIGS_DIR = DATA_DIR / "rigs"
_MOVE_FIELDS = ("turn", "move", "scale", "properties", "length")
_LARGEST_TURN = 180.0
_LARGEST_MOVE = 10.0  # lengths


@dataclass(frozen=True)
class RigTemplate:
    """A mapping file: what it moves, for which targets, measured how."""

    name: str  # the file's stem
    title: str
    description: str
    roles: Mapping[str, tuple[str, ...]]  # role -> the bone names a rig may give it, in order
    length: tuple[str, str] | None  # the two bones whose heads are one length apart
    poses: Mapping[str, Mapping[str, FrameMove]]  # target -> role or bone name -> move
    path: Path = field(default=Path(), compare=False)

    def bones_needed(self) -> set[str]:
        """Roles and bone names the poses and the lengths use."""
        used = {bone for moves in self.poses.values() for bone in moves}
        lengths = {
            bone for moves in self.poses.values() for move in moves.values() for bone in move.length or ()
        }
        return used | lengths | set(self.length or ())


@functools.cache
def rig_templates() -> tuple[RigTemplate, ...]:
    """Every mapping that comes with the extension, by file name (read and validated once)."""
    return tuple(read_rig_template(path) for path in sorted(RIGS_DIR.glob("*.toml")))


def rig_template(name: str) -> RigTemplate:
    for template in rig_templates():
        if template.name == name:
            return template
    names = ", ".join(t.name for t in rig_templates())
    raise HeadError(f"There is no face-rig mapping named {name!r}; the extension has {names}.")


def read_rig_template(path: Path) -> RigTemplate:
    data = read_toml_file(path)
    rig = data.get("rig")
    if not isinstance(rig, dict) or not isinstance(rig.get("title"), str):
        raise DataError(f"{path}: needs a [rig] table with a title.")
    roles = {}
    for role, names in data.get("bones", {}).items():
        if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
            raise DataError(f"{path}: [bones] {role} must list the bone names a rig may give it.")
        roles[role] = tuple(names)
    length = rig.get("length")
    if length is not None and not _is_bone_pair(length):
        raise DataError(f'{path}: [rig] length must name two bones, such as ["lips.L", "lips.R"].')
    poses = {target: _read_moves(path, target, moves) for target, moves in data.get("poses", {}).items()}
    unknown = sorted(set(poses) - set(pose_targets()))
    if unknown:
        raise DataError(f"{path}: [poses] {', '.join(unknown)}: not an ARKit unit nor a built key's name.")
    if length is None and any(
        any(m.move) and not m.length for moves in poses.values() for m in moves.values()
    ):
        raise DataError(f"{path}: its poses move bones, so [rig] must give the length they are measured in.")
    poses = _with_mirrored(path, poses, data.get("mirror"))
    return RigTemplate(
        name=path.stem,
        title=rig["title"],
        description=str(rig.get("description", "")),
        roles=roles,
        length=tuple(length) if length else None,
        poses=poses,
        path=path,
    )


def _read_moves(path: Path, target: str, moves: object) -> dict[str, FrameMove]:
    if not isinstance(moves, dict) or not moves:
        raise DataError(
            f"{path}: [poses.{target}] must give each bone's move, such as jaw = {{ turn = ... }}."
        )
    read = {}
    for bone, move in moves.items():
        where = f"{path}: [poses.{target}] {bone}"
        if not isinstance(move, dict) or set(move) - set(_MOVE_FIELDS) or not move:
            raise DataError(f"{where}: give turn, move, scale or properties (and nothing else).")
        length = move.get("length")
        if length is not None and not _is_bone_pair(length):
            raise DataError(f'{where}: length must name two bones, such as ["lid.T.L.002", "lid.B.L.002"].')
        properties = move.get("properties", {})
        if not isinstance(properties, dict) or not all(_is_number(v) for v in properties.values()):
            raise DataError(f"{where}: properties must give numbers, such as {{ mouth_lock = 1.0 }}.")
        read[bone] = FrameMove(
            turn_degrees=_vector(where, "turn", move.get("turn"), _LARGEST_TURN),
            move=_vector(where, "move", move.get("move"), _LARGEST_MOVE),
            scale=_vector(where, "scale", move.get("scale"), _LARGEST_MOVE),
            properties={str(k): float(v) for k, v in properties.items()},
            length=tuple(length) if length else None,
        )
    return read


def _vector(where: str, name: str, value: object, largest: float) -> tuple[float, float, float]:
    if value is None:
        return (0.0, 0.0, 0.0)
    if not (isinstance(value, list) and len(value) == 3 and all(_is_number(v) for v in value)):
        raise DataError(f"{where}: {name} must be three numbers: left, up, forward.")
    if max(abs(v) for v in value) > largest:
        raise DataError(f"{where}: {name} {value} is beyond ±{largest:g}; check the figures.")
    return tuple(float(v) for v in value)


def _is_bone_pair(value: object) -> bool:
    return isinstance(value, list) and len(value) == 2 and all(isinstance(n, str) and n for n in value)


def _is_number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def _with_mirrored(path: Path, poses: dict, mirror: object) -> dict[str, dict[str, FrameMove]]:
    """Each unit ending in Left mirrored to its Right unit (bones renamed by the side suffixes)."""
    if mirror is None:
        return poses
    if not (
        isinstance(mirror, dict)
        and isinstance(mirror.get("left"), str)
        and isinstance(mirror.get("right"), str)
    ):
        raise DataError(f'{path}: [mirror] must give the side suffixes, left = ".L" and right = ".R".')
    left, right = mirror["left"], mirror["right"]

    # A side's suffix ends the name or a part of it ("lips.L", "lid.T.L.002").
    side = re.compile(f"({re.escape(left)}|{re.escape(right)})(?=\\.|$)")

    def other_side(bone: str) -> str:
        return side.sub(lambda found: right if found.group(1) == left else left, bone)

    mirrored = dict(poses)
    for target, moves in poses.items():
        partner = target[: -len("Left")] + "Right" if target.endswith("Left") else None
        if partner is not None and partner not in poses:
            mirrored[partner] = {
                other_side(bone): mirrored_move(move, other_side) for bone, move in moves.items()
            }
    return mirrored


# ---------------------------------------------------------------- a character's own set-up, as JSON


@dataclass(frozen=True)
class OwnRig:
    """What a character's armature keeps: the mapping it uses (a template's name, or "" for none), the bones
    chosen for the template's roles, and the poses recorded for it (replacing the template's)."""

    mapping: str = ""
    roles: Mapping[str, str] = field(default_factory=dict)
    poses: Mapping[str, Pose] = field(default_factory=dict)

    def is_empty(self) -> bool:
        return not self.mapping and not self.poses


def own_rig_to_json(own: OwnRig) -> str:
    poses = {
        target: {
            "source": pose.source,
            "bones": {
                bone: {
                    "location": [float(v) for v in move.location],
                    "rotation": [float(v) for v in move.rotation],
                    "scale": [float(v) for v in move.scale],
                    "properties": {name: float(value) for name, value in move.properties.items()},
                }
                for bone, move in pose.bones.items()
            },
        }
        for target, pose in own.poses.items()
    }
    return json.dumps({"mapping": own.mapping, "roles": dict(own.roles), "poses": poses}, ensure_ascii=False)


def own_rig_from_json(text: str, where: str) -> OwnRig:
    """A stored set-up; a damaged one is an error naming where it is kept, never a silent default."""
    try:
        data = json.loads(text)
        poses = {}
        for target, pose in data.get("poses", {}).items():
            bones = {
                bone: BoneMove(
                    location=_stored_vector(move["location"]),
                    rotation=_stored_vector(move["rotation"]),
                    scale=_stored_vector(move["scale"]),
                    properties={str(k): float(v) for k, v in move.get("properties", {}).items()},
                )
                for bone, move in pose["bones"].items()
            }
            poses[str(target)] = Pose(bones, str(pose.get("source", "")))
        return OwnRig(
            str(data.get("mapping", "")), {str(k): str(v) for k, v in data.get("roles", {}).items()}, poses
        )
    except (ValueError, KeyError, TypeError, AttributeError) as error:
        raise HeadError(
            f"The face-rig set-up kept in {where} is damaged ({error}); press 'Use Face Rig' again to "
            "replace it (its recorded poses are lost)."
        ) from None


def _stored_vector(values) -> tuple[float, float, float]:
    vector = tuple(float(v) for v in values)
    if len(vector) != 3 or not all(math.isfinite(v) for v in vector):
        raise ValueError(f"{list(values)} is not three numbers")
    return vector
