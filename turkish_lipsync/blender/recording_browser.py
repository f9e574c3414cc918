"""The file browser of the recording fields: it shows only what the decoders read (core/speech/decoders/),
recordings and videos with sound, and writes the chosen file into the field it was opened from."""

from __future__ import annotations

import bpy
from bpy.props import BoolProperty, EnumProperty, StringProperty

from ..core.speech.decoders import RECORDING_SUFFIXES

FILTER_GLOB = ";".join(f"*{suffix}" for suffix in RECORDING_SUFFIXES)


def _field(context, target: str):
    """(the data holding the field, its name) for target, or None (no speaker chosen in the cast)."""
    settings = context.scene.turkish_lipsync
    if target == "SPEECH":
        return settings, "recording"
    if 0 <= settings.cast_index < len(settings.cast):
        return settings.cast[settings.cast_index], "recording"
    return None


class TURKISH_LIPSYNC_OT_choose_recording(bpy.types.Operator):
    bl_idname = "turkish_lipsync.choose_recording"
    bl_label = "Choose Recording"
    bl_description = (
        "Browse for a recording: WAV, FLAC, OGG, MP3, M4A or AAC, or a video with sound (MP4, MOV, MKV, "
        "WebM); only these are shown"
    )
    bl_options = {"REGISTER", "UNDO"}

    filepath: StringProperty(subtype="FILE_PATH", options={"SKIP_SAVE"})
    filter_glob: StringProperty(default=FILTER_GLOB, options={"HIDDEN"})
    relative_path: BoolProperty(
        name="Relative Path",
        default=True,
        description="Store the path relative to the saved .blend file, so the two can move together",
    )
    target: EnumProperty(
        name="Field",
        items=(
            ("SPEECH", "Own Recording", "The Speech section's Own Recording"),
            ("SPEAKER", "Speaker Recording", "The chosen speaker's recording in the conversation"),
        ),
        options={"HIDDEN", "SKIP_SAVE"},
    )

    @classmethod
    def poll(cls, context) -> bool:
        return getattr(context.scene, "turkish_lipsync", None) is not None

    def invoke(self, context, _event):
        field = _field(context, self.target)
        if field is None:
            self.report({"ERROR"}, "Choose a speaker in the cast first")
            return {"CANCELLED"}
        holder, name = field
        current = getattr(holder, name)
        if current:
            self.filepath = bpy.path.abspath(current)
        if not self.properties.is_property_set("relative_path"):  # as the user's preferences default it
            self.relative_path = context.preferences.filepaths.use_relative_paths
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        field = _field(context, self.target)
        if field is None or not self.filepath:
            return {"CANCELLED"}
        holder, name = field
        chosen = self.filepath
        if self.relative_path and bpy.data.is_saved:
            try:
                chosen = bpy.path.relpath(chosen)
            except ValueError:  # on another drive than the .blend (Windows): kept absolute
                pass
        setattr(holder, name, chosen)
        return {"FINISHED"}


def register() -> None:
    bpy.utils.register_class(TURKISH_LIPSYNC_OT_choose_recording)


def unregister() -> None:
    bpy.utils.unregister_class(TURKISH_LIPSYNC_OT_choose_recording)
