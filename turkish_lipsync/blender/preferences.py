"""Add-on preferences: where the speech engine lives when the bundled one cannot be used."""

from __future__ import annotations

import bpy
from bpy.props import StringProperty

from ..core.speech.espeak import choose_library


def addon_package(blender_layer_package: str) -> str:
    """The package Blender enables, from this layer's: "bl_ext.<repo>.turkish_lipsync" when installed."""
    return (
        blender_layer_package.removesuffix(".blender").removesuffix(".turkish_lipsync") or "turkish_lipsync"
    )


ADDON_PACKAGE = addon_package(__package__ or "")


class TurkishLipSyncPreferences(bpy.types.AddonPreferences):
    bl_idname = ADDON_PACKAGE

    engine_library: StringProperty(
        name="eSpeak NG Library",
        subtype="FILE_PATH",
        description="A libespeak-ng to use instead of the bundled one (empty: bundled, then the system's)",
    )
    engine_data: StringProperty(
        name="eSpeak NG Data",
        subtype="DIR_PATH",
        description="The espeak-ng-data folder that belongs to that library (empty: the library's own)",
    )

    def draw(self, _context) -> None:
        layout = self.layout
        layout.prop(self, "engine_library")
        layout.prop(self, "engine_data")


def addon_preferences(context: bpy.types.Context) -> TurkishLipSyncPreferences | None:
    """The preferences, or None where the add-on is not enabled through Blender (scripts, tests)."""
    addon = context.preferences.addons.get(ADDON_PACKAGE)
    return addon.preferences if addon is not None else None


def configure_speech_engine(context: bpy.types.Context) -> None:
    """Hand the preferences' engine paths to the speech engine (an explicit call, before each use)."""
    preferences = addon_preferences(context)
    if preferences is None:
        return
    library, data = preferences.engine_library, preferences.engine_data
    choose_library(bpy.path.abspath(library) if library else None, bpy.path.abspath(data) if data else None)


CLASSES = (TurkishLipSyncPreferences,)

register, unregister = bpy.utils.register_classes_factory(CLASSES)
