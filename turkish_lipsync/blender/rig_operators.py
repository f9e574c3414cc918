"""The Face Rig section's operators: a character's face-rig set-up kept with its armature, its own poses
recorded and cleared, and its keys made linkable for shots. Thin, as every operator: poll (saying why
not), then one call."""

from __future__ import annotations

import bpy
from bpy.props import StringProperty

from ..core.base.errors import LipSyncError
from ..core.faces.rig_mappings import OwnRig, rig_template
from . import face_rig, linking, pose_recording
from .heads import find_head_parts
from .operators import Outcome, ReportedOperator, chosen_head, head_chosen, object_mode, settings_of
from .owned_keys import owned_keys
from .properties import OWN_POSES


def chosen_armature(context) -> bpy.types.Object | None:
    head = chosen_head(context)
    return face_rig.face_armature(head) if head is not None else None


def armature_found(context) -> str | None:
    if chosen_head(context) is None:
        return "Choose the head object in the Lip Sync panel"
    if chosen_armature(context) is None:
        return "The head has no armature: give it an Armature modifier or an armature parent"
    return None


def armature_local(context) -> str | None:
    armature = chosen_armature(context)
    if armature is not None and face_rig.is_linked(armature):
        return "The armature is linked: set up its face rig in the character's own file"
    return None


def set_up(context) -> str | None:
    armature = chosen_armature(context)
    if armature is not None and not armature.get(face_rig.RIG_PROPERTY):
        return "The armature has no face-rig set-up to remove"
    return None


def object_or_pose_mode(context) -> str | None:
    return "Switch to Object or Pose Mode first" if context.mode not in ("OBJECT", "POSE") else None


def action_chosen(context) -> str | None:
    return (
        "Choose the Pose Action in the Face Rig section" if settings_of(context).pose_action is None else None
    )


def head_local_with_keys(context) -> str | None:
    head = chosen_head(context)
    if head is not None and face_rig.is_linked(head):
        return "The head is linked: make its keys linkable in the character's own file"
    if head is not None and not owned_keys(head):
        return "The head has no lip-sync shape keys yet: build them first"
    return None


class TURKISH_LIPSYNC_OT_use_face_rig(ReportedOperator, bpy.types.Operator):
    """Keep the chosen face-rig mapping with the head's armature: Generate then moves its bones"""

    bl_idname = "turkish_lipsync.use_face_rig"
    bl_label = "Use Face Rig"
    bl_options = {"REGISTER", "UNDO"}
    requirements = (object_or_pose_mode, armature_found, armature_local)

    @staticmethod
    def work(context) -> Outcome:
        settings = settings_of(context)
        armature = chosen_armature(context)
        own = face_rig.stored_setup(armature)
        mapping = "" if settings.face_rig == OWN_POSES else settings.face_rig
        roles = {"jaw": settings.jaw_bone} if mapping == "jaw_bone" and settings.jaw_bone else {}
        chosen = OwnRig(mapping, roles, own.poses)
        warnings = face_rig.check_setup(armature, chosen)
        face_rig.store_setup(armature, chosen)
        title = rig_template(mapping).title if mapping else "its own poses"
        return f"{armature.name} moves the face through {title} ({len(own.poses)} poses of its own)", warnings


class TURKISH_LIPSYNC_OT_stop_face_rig(ReportedOperator, bpy.types.Operator):
    """Remove the face-rig set-up and its recorded poses from the armature, and the rig's speech keys"""

    bl_idname = "turkish_lipsync.stop_face_rig"
    bl_label = "Stop Using Face Rig"
    bl_options = {"REGISTER", "UNDO"}
    requirements = (object_or_pose_mode, armature_found, armature_local, set_up)

    @staticmethod
    def work(context) -> Outcome:
        armature = chosen_armature(context)
        face_rig.store_setup(armature, OwnRig())
        removed = face_rig.remove_face_rig_motion(chosen_head(context))
        return f"{armature.name} no longer moves the face ({removed} speech curves removed)", ()


class TURKISH_LIPSYNC_OT_record_pose(ReportedOperator, bpy.types.Operator):
    """Record the armature's current pose as the pose of the chosen viseme, emotion or ARKit unit"""

    bl_idname = "turkish_lipsync.record_pose"
    bl_label = "Record Pose"
    bl_options = {"REGISTER", "UNDO"}
    requirements = (object_or_pose_mode, armature_found, armature_local)

    @staticmethod
    def work(context) -> Outcome:
        target = settings_of(context).pose_target
        pose = pose_recording.record_current_pose(
            chosen_armature(context), target, context.scene.frame_current
        )
        return f"Recorded {target}: {len(pose.bones)} bones", ()


class TURKISH_LIPSYNC_OT_record_action_pose(ReportedOperator, bpy.types.Operator):
    """Record the pose the Pose Action (or pose asset) holds at the Pose Frame as the chosen target's pose"""

    bl_idname = "turkish_lipsync.record_action_pose"
    bl_label = "Record from Action"
    bl_options = {"REGISTER", "UNDO"}
    requirements = (object_or_pose_mode, armature_found, armature_local, action_chosen)

    @staticmethod
    def work(context) -> Outcome:
        settings = settings_of(context)
        pose = pose_recording.record_action_pose(
            chosen_armature(context), settings.pose_target, settings.pose_action, settings.pose_frame
        )
        return f"Recorded {settings.pose_target} from {pose.source}: {len(pose.bones)} bones", ()


class TURKISH_LIPSYNC_OT_clear_pose(ReportedOperator, bpy.types.Operator):
    """Forget this recorded pose (the mapping's own pose of its target, if any, is used again)"""

    bl_idname = "turkish_lipsync.clear_pose"
    bl_label = "Clear Pose"
    bl_options = {"REGISTER", "UNDO"}
    requirements = (object_or_pose_mode, armature_found, armature_local)

    target: StringProperty(name="Pose For", description="The target whose recorded pose is cleared")

    def work(self, context) -> Outcome:
        if not pose_recording.clear_pose(chosen_armature(context), self.target):
            raise LipSyncError(f"There is no recorded pose for {self.target!r} to clear.")
        return f"Cleared the pose of {self.target}", ()


class TURKISH_LIPSYNC_OT_make_keys_linkable(ReportedOperator, bpy.types.Operator):
    """Drive the head's lip-sync keys by its own properties, so that shots that link it can animate them"""

    bl_idname = "turkish_lipsync.make_keys_linkable"
    bl_label = "Make Keys Linkable"
    bl_options = {"REGISTER", "UNDO"}
    requirements = (object_mode, head_chosen, head_local_with_keys)

    @staticmethod
    def work(context) -> Outcome:
        head = chosen_head(context)
        driven = linking.make_keys_linkable(head, find_head_parts(head))
        return f"{driven} keys of {head.name} and its parts are driven by its properties: save this file", ()


CLASSES = (
    TURKISH_LIPSYNC_OT_use_face_rig,
    TURKISH_LIPSYNC_OT_stop_face_rig,
    TURKISH_LIPSYNC_OT_record_pose,
    TURKISH_LIPSYNC_OT_record_action_pose,
    TURKISH_LIPSYNC_OT_clear_pose,
    TURKISH_LIPSYNC_OT_make_keys_linkable,
)

register, unregister = bpy.utils.register_classes_factory(CLASSES)
