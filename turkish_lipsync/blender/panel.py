"""The Lip Sync tab in the 3D Viewport's sidebar: head and keys, text and recording, timing, render."""

from __future__ import annotations

import bpy

from ..core.base.errors import LipSyncError
from .face_rig import face_armature, stored_setup
from .shapekeys import KEY_SOURCES_PROPERTY


class TURKISH_LIPSYNC_UL_cast(bpy.types.UIList):
    """The cast: each speaker of the script, the head that plays them and their voice."""

    def draw_item(
        self, _context, layout, _data, member, _icon, _active_data, _active_property, _index=0, _flt_flag=0
    ):
        row = layout.row(align=True)
        row.label(text=member.name, icon="USER", translate=False)
        row.prop(member, "head", text="")
        row.prop(member, "voice", text="")


class VIEW3D_PT_turkish_lipsync(bpy.types.Panel):
    bl_label = "Turkish Lip Sync"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Lip Sync"

    def draw(self, context) -> None:
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.turkish_lipsync
        self.draw_head(layout, settings)
        self.draw_key_sources(layout, settings.head)
        self.draw_face_rig(layout, settings)
        layout.separator()
        self.draw_speech(layout, settings)
        self.draw_cast(layout, settings)
        self.draw_living(layout, settings)
        column = layout.column()
        column.operator("turkish_lipsync.generate", icon="PLAY_SOUND")
        layout.separator()
        self.draw_render(layout, settings)
        layout.separator()
        self.draw_export(layout, settings)

    @staticmethod
    def draw_head(layout, settings) -> None:
        """The head and what its keys are built from."""
        column = layout.column(heading="Head")
        column.prop(settings, "head")
        column.prop(settings, "key_source")
        if settings.key_source == "obj_folder":
            column.prop(settings, "obj_folder")
        if settings.key_source in ("auto", "convention"):
            column.prop(settings, "mapping_file")
        column.prop(settings, "arkit_keys")
        column.prop(settings, "empowered")
        row = column.row()
        row.active = settings.empowered
        row.prop(settings, "rho")
        if settings.key_source in ("auto", "transfer"):
            # The landmarks register the reference head onto this one; the user may correct them first.
            row = column.row(align=True)
            row.operator("turkish_lipsync.show_landmarks", icon="EMPTY_DATA")
            row.operator("turkish_lipsync.clear_landmarks", icon="X", text="")
        column.operator("turkish_lipsync.build_shape_keys", icon="SHAPEKEY_DATA")
        column.operator("turkish_lipsync.make_keys_linkable", icon="LINKED")

    @staticmethod
    def draw_speech(layout, settings) -> None:
        """What is spoken, from which recording or cue file, and how it is timed and moved."""
        column = layout.column(heading="Speech")
        column.prop(settings, "source_kind", expand=True)
        if settings.source_kind == "TEXT":
            column.prop(settings, "text")
        else:
            column.prop(settings, "file_path")
        row = column.row(align=True)
        row.prop(settings, "recording")
        row.operator("turkish_lipsync.choose_recording", text="", icon="FILEBROWSER").target = "SPEECH"
        column.prop(settings, "cue_file")
        column.prop(settings, "timing")
        column.prop(settings, "rate")
        column.prop(settings, "emotion_strength")
        column.prop(settings, "motion")
        column.prop(settings, "interpolation")
        column.prop(settings, "audio_folder")

    @staticmethod
    def draw_render(layout, settings) -> None:
        column = layout.column(heading="Render")
        column.prop(settings, "render_engine")
        column.prop(settings, "render_samples")
        column.prop(settings, "output_path")
        column.operator("turkish_lipsync.render", icon="RENDER_ANIMATION")

    @staticmethod
    def draw_export(layout, settings) -> None:
        column = layout.column(heading="Export")
        column.prop(settings, "export_format")
        column.prop(settings, "export_path")
        column.operator("turkish_lipsync.export_animation", icon="EXPORT")
        column.prop(settings, "gltf_path")
        column.operator("turkish_lipsync.export_gltf", icon="EXPORT")

    @staticmethod
    def draw_cast(layout, settings) -> None:
        """A script with speakers: who plays each one, with which voice, and their recordings."""
        header, body = layout.panel("TURKISH_LIPSYNC_cast", default_closed=not len(settings.cast))
        header.label(text="Conversation")
        if body is None:
            return
        body.operator("turkish_lipsync.fill_cast", icon="COMMUNITY")
        body.template_list("TURKISH_LIPSYNC_UL_cast", "", settings, "cast", settings, "cast_index", rows=3)
        if 0 <= settings.cast_index < len(settings.cast):
            member = settings.cast[settings.cast_index]
            column = body.column()
            column.prop(member, "head")
            column.prop(member, "gender")
            column.prop(member, "voice")
            voiced = column.column(align=True)
            voiced.active = member.voice != "AUTO"
            voiced.prop(member, "pitch")
            voiced.prop(member, "voice_rate")
            column.prop(member, "emotion_strength")
            row = column.row(align=True)
            row.prop(member, "recording")
            row.operator("turkish_lipsync.choose_recording", text="", icon="FILEBROWSER").target = "SPEAKER"
        body.prop(settings, "line_recordings")

    @staticmethod
    def draw_living(layout, settings) -> None:
        """The living layers: each on, off or as the motion has it, with its amount; the seed and target."""
        header, body = layout.panel("TURKISH_LIPSYNC_living", default_closed=False)
        header.label(text="Living Face")
        if body is None:
            return
        for layer, amount in (
            ("gaze_layer", "gaze_amount"),
            ("blinks_layer", "blink_amount"),
            ("head_motion_layer", "head_amount"),
            ("expression_layer", "expression_amount"),
        ):
            row = body.row(align=True)
            row.prop(settings, layer, expand=True)
            sub = row.row(align=True)
            sub.active = getattr(settings, layer) != "OFF"
            sub.prop(settings, amount, text="")
        body.prop(settings, "gaze_target")
        body.prop(settings, "seed")

    @staticmethod
    def draw_face_rig(layout, settings) -> None:
        """A sub-panel for a head its armature moves: the mapping kept with the armature, the poses of the
        character's own (recorded from its pose or from an action), each with a button to clear it."""
        head = settings.head
        armature = face_armature(head) if head is not None else None
        header, body = layout.panel("TURKISH_LIPSYNC_face_rig", default_closed=armature is None)
        header.label(text="Face Rig")
        if body is None:
            return
        body.prop(settings, "face_rig")
        if settings.face_rig == "jaw_bone":  # the armature's bones to choose from, where it has one
            body.prop_search(settings, "jaw_bone", armature.data, "bones") if armature else body.prop(
                settings, "jaw_bone"
            )
        row = body.row(align=True)
        row.operator("turkish_lipsync.use_face_rig", icon="ARMATURE_DATA")
        row.operator("turkish_lipsync.stop_face_rig", icon="X", text="")
        body.prop(settings, "pose_target")
        body.operator("turkish_lipsync.record_pose", icon="POSE_HLT")
        body.prop(settings, "pose_action")
        body.prop(settings, "pose_frame")
        body.operator("turkish_lipsync.record_action_pose", icon="ACTION")
        if armature is None:
            return
        try:
            own = stored_setup(armature)
        except LipSyncError as error:
            body.label(text=str(error), icon="ERROR", translate=False)
            return
        column = body.column(align=True)
        column.use_property_split = False
        for target, pose in own.poses.items():
            row = column.row(align=True)
            row.label(text=target.removeprefix("TR_"), translate=False)
            row.label(text=pose.source, translate=False)
            row.operator("turkish_lipsync.clear_pose", text="", icon="X").target = target

    @staticmethod
    def draw_key_sources(layout, head) -> None:
        """A closed sub-panel listing where each built key came from (the head's own keys, a transfer...)."""
        sources = head.data.get(KEY_SOURCES_PROPERTY) if head is not None and head.type == "MESH" else None
        if not sources:
            return
        header, body = layout.panel("TURKISH_LIPSYNC_key_sources", default_closed=True)
        header.label(text="Key Sources")
        if body is None:
            return
        body.use_property_split = False
        for key_name, source in sources.items():
            row = body.row()
            row.label(text=key_name.removeprefix("TR_"), translate=False)
            row.label(text=source, translate=False)


CLASSES = (TURKISH_LIPSYNC_UL_cast, VIEW3D_PT_turkish_lipsync)

register, unregister = bpy.utils.register_classes_factory(CLASSES)
