"""A head whose face its armature moves: the rig's poses found, resolved on its bones and keyed.

A character's set-up (the mapping it uses, the bones chosen for the mapping's roles, the poses recorded in
the panel) is kept on its armature object as JSON (RIG_PROPERTY), so it is saved with the character and read
wherever the character is linked. Without a set-up, a head whose ARKit or TR keys its bones drive through
drivers (Faceit's control rig) speaks through those bones (rig_drivers.py). The bones are keyed on the
armature's action (its own when it has one, kept whole; else one of ours), marked as ours (marked_curves.py):
Generate again replaces exactly those, and a channel the user animates there is left alone, with a warning.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import bpy
import numpy as np
from mathutils import Quaternion

from ..core.base.errors import HeadError
from ..core.base.model import LOOK_KEYS, WeightTracks
from ..core.faces.rig_mappings import OwnRig, own_rig_from_json, own_rig_to_json, rig_template
from ..core.faces.rig_poses import Pose, RigMapping, bone_motion, resolve_moves, with_own_poses
from ..core.motion.frames import decimated_keys
from . import rig_drivers
from .living_rig import Eye, LivingRig, armature_of
from .marked_curves import FACE_RIG, remove_marked_channels, users_paths, write_marked_channels

RIG_PROPERTY = "tr_face_rig"  # on the armature object: the character's set-up (OwnRig as JSON)
# Keys are dropped where linear interpolation between their neighbours keeps every pose's weight this
# close: a thousandth of a full viseme, under 0.03 degrees of a jaw that opens 22 degrees at weight 1.
WEIGHT_TOLERANCE = 1e-3
# Targets that turn the eyes: with poses for them the rig turns the eyes, not the living layer.
EYE_TARGETS = frozenset(LOOK_KEYS) | {
    f"eyeLook{way}{side}" for way in ("Up", "Down", "In", "Out") for side in ("Left", "Right")
}


@dataclass(frozen=True)
class FaceRig:
    """A head's face rig, resolved: the armature's name and the poses in its bones' own axes."""

    armature: str
    mapping: RigMapping
    warnings: tuple[str, ...] = ()

    @property
    def turns_eyes(self) -> bool:
        return bool(EYE_TARGETS & set(self.mapping.poses))


@dataclass(frozen=True)
class FaceRigResult:
    driven: frozenset[str]  # the tracks the rig moved
    key_count: int
    warnings: tuple[str, ...]


# ---------------------------------------------------------------- the character's set-up


def is_linked(obj: bpy.types.ID) -> bool:
    """Linked from a library, or a library override of linked data: what is stored on it is the library's."""
    return obj.library is not None or obj.override_library is not None


def library_path(obj: bpy.types.ID) -> str:
    """The file a linked or overridden ID comes from ("" for a local one)."""
    library = obj.library
    if library is None and obj.override_library is not None and obj.override_library.reference is not None:
        library = obj.override_library.reference.library
    return bpy.path.abspath(library.filepath) if library is not None else ""


def stored_setup(armature: bpy.types.Object) -> OwnRig:
    text = armature.get(RIG_PROPERTY)
    if not text:
        return OwnRig()
    return own_rig_from_json(str(text), f"the armature {armature.name!r} ({RIG_PROPERTY})")


def store_setup(armature: bpy.types.Object, own: OwnRig) -> None:
    """Keep the set-up with the character; refused on a linked character (it would not be saved)."""
    if is_linked(armature):
        raise HeadError(
            f"The armature {armature.name!r} is linked from {library_path(armature)}: set up its face rig "
            "there, in the character's own file, save it, and reload the library here."
        )
    if own.is_empty():
        armature.pop(RIG_PROPERTY, None)
    else:
        armature[RIG_PROPERTY] = own_rig_to_json(own)


def face_armature(head: bpy.types.Object) -> bpy.types.Object | None:
    """The armature that deforms the head or is its parent."""
    armature = armature_of(head)
    return armature if armature is not None and armature.type == "ARMATURE" else None


# ---------------------------------------------------------------- finding and resolving


def find_face_rig(head: bpy.types.Object, frame: np.ndarray) -> FaceRig | None:
    """The head's face rig, its poses resolved on the bones; None where the head has none.

    frame: the character's left, up, forward as columns in world axes (living_rig.find_rig's)."""
    armature = face_armature(head)
    own = stored_setup(armature) if armature is not None else OwnRig()
    if own.is_empty():
        return rig_drivers.driven_face_rig(head, armature)
    warnings: list[str] = []
    template_poses, title = {}, "Own Poses"
    if own.mapping:
        template = rig_template(own.mapping)
        title = template.title
        bones = _role_bones(template, armature, own.roles)
        frame_of_bones = _bone_axes(armature, frame)

        def length_of(pair) -> float:
            first, second = (armature.data.bones[bones[name]].head_local for name in pair or template.length)
            return (first - second).length

        poses = {
            target: {bones[bone]: move for bone, move in moves.items()}
            for target, moves in template.poses.items()
        }
        axes = {bone: frame_of_bones(bone) for moves in poses.values() for bone in moves}
        template_poses = resolve_moves(poses, axes, length_of, template.title)
    own_poses, missing = {}, set()
    for target, pose in own.poses.items():
        kept = {bone: move for bone, move in pose.bones.items() if bone in armature.pose.bones}
        missing |= set(pose.bones) - set(kept)
        own_poses[target] = Pose(kept, pose.source)
    if missing:
        warnings.append(
            f"The armature {armature.name!r} has no bones {', '.join(sorted(missing))} that recorded poses "
            "move: those parts of the poses are left out. Record the poses again on this rig."
        )
    mapping = with_own_poses(RigMapping(own.mapping, title, template_poses), own_poses, own.mapping, title)
    return FaceRig(armature.name, mapping, tuple(warnings))


def check_setup(armature: bpy.types.Object, own: OwnRig) -> tuple[str, ...]:
    """A HeadError where the set-up's mapping needs bones the armature lacks (before it is kept)."""
    if own.mapping:
        _role_bones(rig_template(own.mapping), armature, own.roles)
    return ()


def _role_bones(template, armature: bpy.types.Object, chosen) -> dict[str, str]:
    """Every role and bone name the template uses -> the armature's bone (the user's choice, else the first
    of the role's names the armature has, compared exactly and then ignoring case)."""
    names = {bone.name.lower(): bone.name for bone in armature.data.bones}
    found, missing = {}, []
    for used in sorted(template.bones_needed()):
        candidates = [chosen[used]] if used in chosen else list(template.roles.get(used, (used,)))
        bone = next((c for c in candidates if c in armature.data.bones), None)
        bone = bone or next((names[c.lower()] for c in candidates if c.lower() in names), None)
        if bone is None:
            named = " or ".join(repr(c) for c in candidates)
            missing.append(f"{used} bone ({named})" if used in template.roles else f"bone {used!r}")
        found[used] = bone
    if missing:
        raise HeadError(
            f"The armature {armature.name!r} has no {', '.join(missing)} for the {template.title} mapping: "
            "choose the bone in the panel's Face Rig section, or another mapping."
        )
    return found


def _bone_axes(armature: bpy.types.Object, frame: np.ndarray):
    """bone -> its rest axes (columns) in the character's frame."""
    rotation = armature.matrix_world.to_3x3().normalized()
    frame_in_armature = np.array(rotation.inverted_safe()) @ np.asarray(frame, np.float64)

    def axes(bone_name: str) -> np.ndarray:
        bone_axes = np.array(armature.data.bones[bone_name].matrix_local.to_3x3().normalized())
        return frame_in_armature.T @ bone_axes

    return axes


def hand_eyes_to_rig(rig: LivingRig, face: FaceRig | None) -> LivingRig:
    """The living layer's rig without its eyes' objects and bones where the face rig turns the eyes (their
    centres still aim the gaze)."""
    if face is None or not face.turns_eyes or not rig.eyes:
        return rig
    eyes = {side: Eye(side, eye.centre) for side, eye in rig.eyes.items()}
    return dataclasses.replace(rig, eyes=eyes, eyes_turn_by="face rig")


# ---------------------------------------------------------------- keying


def key_face_rig(face: FaceRig, tracks: WeightTracks, start_frame: float) -> FaceRigResult:
    """Replace our keys on the rig's bones with the motion the tracks give through its poses."""
    armature = bpy.data.objects[face.armature]
    remove_marked_channels(armature, FACE_RIG)
    motion = bone_motion(tracks, face.mapping)
    if tracks.interpolation == "LINEAR" and len(motion.frames) > 2 and motion.weights.shape[1]:
        motion = motion.at(decimated_keys(motion.weights, WEIGHT_TOLERANCE))
    frames = motion.frames + float(start_frame)
    channels = {}
    for bone, values in motion.locations.items():
        channels[_bone_path(bone, "location")] = values
    for bone, values in motion.rotations.items():
        path, converted = _rotation_channel(armature.pose.bones[bone], values)
        channels[path] = converted
    for bone, values in motion.scales.items():
        channels[_bone_path(bone, "scale")] = values
    warnings = list(face.warnings)
    for (bone, name), changes in motion.properties.items():
        rest = _property_rest(armature.pose.bones[bone], name)
        if rest is None:
            warnings.append(
                f"The bone {bone!r} has no property {name!r} for the face rig to key; it is left out."
            )
        else:
            channels[property_path(bone, name)] = rest + changes
    action = armature.animation_data.action if armature.animation_data else None
    theirs = users_paths(action) & set(channels)
    if theirs:
        warnings.append(
            f"{len(theirs)} channels of {armature.name!r} the face rig moves are animated by "
            f"{action.name!r} already ({', '.join(sorted(theirs)[:3])}...), so they were not keyed; move "
            "your keys to an NLA strip of your own (or clear them) and generate again."
        )
    written = write_marked_channels(
        armature,
        {path: (frames, values) for path, values in channels.items() if path not in theirs},
        FACE_RIG,
        tracks.interpolation if tracks.interpolation in ("LINEAR", "BEZIER", "CONSTANT") else "LINEAR",
    )
    return FaceRigResult(motion.driven, written, tuple(warnings))


def remove_face_rig_motion(head: bpy.types.Object) -> int:
    armature = face_armature(head)
    return remove_marked_channels(armature, FACE_RIG) if armature is not None else 0


def _bone_path(bone: str, channel: str) -> str:
    return f'pose.bones["{bpy.utils.escape_identifier(bone)}"].{channel}'


def property_path(bone: str, name: str) -> str:
    """The data path of a pose bone's custom property."""
    return f'pose.bones["{bpy.utils.escape_identifier(bone)}"]["{bpy.utils.escape_identifier(name)}"]'


def _rotation_channel(pose_bone: bpy.types.PoseBone, quaternions: np.ndarray) -> tuple[str, np.ndarray]:
    """The rotation channel of the bone's rotation mode and the values for it."""
    mode = pose_bone.rotation_mode
    if mode == "QUATERNION":
        return _bone_path(pose_bone.name, "rotation_quaternion"), quaternions
    if mode == "AXIS_ANGLE":
        angles = 2 * np.arccos(np.clip(quaternions[:, 0], -1.0, 1.0))
        sines = np.sqrt(np.maximum(1.0 - quaternions[:, 0] ** 2, 0.0))
        axes = np.where(
            sines[:, None] > 1e-9, quaternions[:, 1:] / np.maximum(sines, 1e-9)[:, None], [0, 1, 0]
        )
        return _bone_path(pose_bone.name, "rotation_axis_angle"), np.column_stack([angles, axes])
    eulers, previous = [], None
    for value in quaternions:
        euler = Quaternion(value).to_euler(mode, previous) if previous else Quaternion(value).to_euler(mode)
        eulers.append(tuple(euler))
        previous = euler
    return _bone_path(pose_bone.name, "rotation_euler"), np.array(eulers)


def property_default(pose_bone: bpy.types.PoseBone, name: str) -> float | None:
    """A bone's numeric custom property's default, where the rig gave one (None otherwise)."""
    try:
        default = pose_bone.id_properties_ui(name).as_dict().get("default")
    except TypeError:  # not a number
        return None
    return float(default) if isinstance(default, int | float) and not isinstance(default, bool) else None


def _property_rest(pose_bone: bpy.types.PoseBone, name: str) -> float | None:
    """A custom property's rest value: its default where the rig gave one, else its value now."""
    if name not in pose_bone.keys() or not isinstance(pose_bone[name], int | float):
        return None
    default = property_default(pose_bone, name)
    return float(pose_bone[name]) if default is None else default
