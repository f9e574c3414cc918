"""Registering the Blender layer: everything appears, everything goes, the Turkish UI covers it all."""

import pytest

bpy = pytest.importorskip("bpy")

from turkish_lipsync import blender  # noqa: E402
from turkish_lipsync.blender import (  # noqa: E402
    operators,
    panel,
    preferences,
    properties,
    rig_operators,
    translations,
)

OPERATOR_CLASSES = (*operators.CLASSES, *rig_operators.CLASSES)

OPERATOR_IDS = ("build_shape_keys", "generate", "render", "use_face_rig", "record_pose", "make_keys_linkable")


def _registered_types() -> set[str]:
    return {name for name in dir(bpy.types) if "TURKISH_LIPSYNC" in name or "turkish_lipsync" in name}


def test_register_and_unregister_twice_leave_nothing_behind():
    before = _registered_types()
    for _ in range(2):
        blender.register()
        try:
            assert hasattr(bpy.context.scene, "turkish_lipsync")
            for operator in OPERATOR_IDS:
                assert hasattr(bpy.ops.turkish_lipsync, operator)
                assert "REGISTER" in getattr(bpy.types, f"TURKISH_LIPSYNC_OT_{operator}").bl_options
                assert "UNDO" in getattr(bpy.types, f"TURKISH_LIPSYNC_OT_{operator}").bl_options
            assert panel.VIEW3D_PT_turkish_lipsync.is_registered
            assert panel.VIEW3D_PT_turkish_lipsync.bl_category == "Lip Sync"
            assert preferences.TurkishLipSyncPreferences.is_registered
        finally:
            blender.unregister()
        assert not hasattr(bpy.types.Scene, "turkish_lipsync")
        assert _registered_types() == before


def test_settings_default_to_the_documented_modes():
    blender.register()
    try:
        settings = bpy.context.scene.turkish_lipsync
        assert (settings.timing, settings.motion, settings.interpolation) == ("phone", "natural", "AUTO")
        assert settings.render_engine == "AUTO"
        assert settings.emotion_strength == pytest.approx(1.0)
        assert settings.rate == pytest.approx(1.0)
    finally:
        blender.unregister()


def test_preferences_belong_to_the_package_blender_enables():
    # Installed as an extension, this layer is bl_ext.<repository>.turkish_lipsync.turkish_lipsync.blender.
    installed = "bl_ext.user_default.turkish_lipsync.turkish_lipsync.blender"
    assert preferences.addon_package(installed) == "bl_ext.user_default.turkish_lipsync"
    assert preferences.addon_package("") == "turkish_lipsync"
    # That Blender then finds the preferences under the installed package (addon_preferences) is checked on
    # the real install (tools/release/build_extension.py --check, tests/blender/test_extension_zip.py).


def _ui_texts() -> set[str]:
    """Every label, tooltip and enum item a user sees in the panel, operators and preferences."""
    texts = {panel.VIEW3D_PT_turkish_lipsync.bl_label, panel.VIEW3D_PT_turkish_lipsync.bl_category}
    texts |= {"Head", "Speech", "Render"}
    for cls in OPERATOR_CLASSES:
        texts |= {cls.bl_label, cls.__doc__}
        properties_ = cls.bl_rna.properties
        declared = [properties_[name] for name in getattr(cls, "__annotations__", {}) if name in properties_]
        texts |= {prop.name for prop in declared} | {prop.description for prop in declared}
    for cls in (*properties.CLASSES, preferences.TurkishLipSyncPreferences):
        for prop in cls.bl_rna.properties:
            if prop.identifier in ("rna_type", "name", "bl_idname"):
                continue
            texts |= {prop.name, prop.description}
            if prop.type == "ENUM":
                for item in prop.enum_items:
                    texts |= {item.name, item.description}
    return {text for text in texts if text}


def test_every_ui_text_has_a_turkish_translation():
    blender.register()
    try:
        missing = sorted(_ui_texts() - set(translations.TURKISH))
    finally:
        blender.unregister()
    assert missing == []


def test_poll_messages_are_translated():
    """Every reason an operator's requirements give for not running (shown on its button) is translated."""
    import ast
    import inspect

    requirements = {
        requirement for cls in OPERATOR_CLASSES for requirement in getattr(cls, "requirements", ())
    }

    def said(value):  # what a return statement can give: a string, or either side of "x if c else y"
        if isinstance(value, ast.IfExp):
            return said(value.body) + said(value.orelse)
        return [value.value] if isinstance(value, ast.Constant) and isinstance(value.value, str) else []

    messages = [
        message
        for requirement in requirements
        for returned in ast.walk(ast.parse(inspect.getsource(requirement)))
        if isinstance(returned, ast.Return) and returned.value is not None
        for message in said(returned.value)
    ]
    assert len(messages) >= 12
    assert [m for m in messages if m not in translations.TURKISH] == []


def test_turkish_table_is_registered_under_the_tr_locale():
    table = translations.translation_table()
    assert set(table) == {"tr_TR"}
    assert table["tr_TR"][("Operator", "Generate Animation")] == "Animasyonu Üret"
    assert table["tr_TR"][("*", "Speaking Rate")] == "Konuşma Hızı"
