"""The panel reference's facts (docs/_ext/panel_fields.py) on the real add-on: what the panel draws, read
from panel.py, and what the registered RNA says of it; and that what it cannot describe is found."""

import ast
import sys
from pathlib import Path

import pytest

bpy = pytest.importorskip("bpy")

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "docs" / "_ext"))

import panel_fields  # noqa: E402

pytestmark = pytest.mark.usefixtures("registered_extension")


def _drawn():
    return panel_fields.drawn_by_the_panels()


def test_the_reference_describes_everything_the_panel_draws():
    assert [path.name for path in panel_fields.panel_sources()] == ["panel.py"]
    drawn = _drawn()
    assert panel_fields.reference_problems(drawn, panel_fields.settings_rna()) == []
    assert list(dict.fromkeys(item.section for item in drawn)) == [
        "Head",
        "Face Rig",
        "Speech",
        "Conversation",
        "Living Face",
        "Render",
        "Export",
    ]
    names = [item.name for item in drawn]
    assert names[:2] == ["head", "key_source"] and "turkish_lipsync.generate" in names
    # the loop over the living layers is unrolled: every layer and its amount
    for layer in ("gaze", "blinks", "head_motion", "expression"):
        assert f"{layer}_layer" in names


def test_conditions_read_as_the_panel_shows_them():
    struct = panel_fields.settings_rna()
    by_name = {item.name: item for item in _drawn()}

    def shown(name):
        return [panel_fields.condition_text(c, struct) for c in by_name[name].shown_when]

    def active(name):
        return [panel_fields.condition_text(c, struct) for c in by_name[name].active_when]

    assert shown("obj_folder") == ["Shape-Key Source is Folder of OBJ Models"]
    assert shown("mapping_file") == ["Shape-Key Source is Auto or Own Visemes"]
    assert shown("text") == ["Source is Text"] and shown("file_path") == ["Source is not Text"]
    assert active("rho") == ["Empowered Emotions is on"]
    assert active("gaze_amount") == ["Gaze is not Off"]


def test_the_chosen_cast_row_is_described_through_the_settings():
    struct = panel_fields.settings_rna()
    member = {item.name: item for item in _drawn() if item.struct == "member"}
    assert {"head", "voice", "pitch", "recording"} <= set(member)
    assert panel_fields.path_of(member["pitch"]) == "cast[i].pitch"
    assert panel_fields.struct_of("member", struct).properties["pitch"].name == "Voice Pitch"
    pitch = member["pitch"]
    shown = [panel_fields.condition_text(c, struct) for c in pitch.shown_when]
    assert shown == ["a row of the Cast list is chosen"]
    assert [panel_fields.condition_text(c, struct) for c in pitch.active_when] == ["Voice is not Auto"]


def test_a_property_without_description_or_turkish_name_is_found():
    class UndocumentedSettings(bpy.types.PropertyGroup):
        speed: bpy.props.FloatProperty(name="Undocumented Speed")
        style: bpy.props.EnumProperty(
            name="Timing", description="Documented", items=(("A", "Phone", ""), ("B", "Unnamed Item", "Told"))
        )

    bpy.utils.register_class(UndocumentedSettings)
    try:
        struct = UndocumentedSettings.bl_rna
        assert panel_fields.property_problems(struct, "speed") == [
            "UndocumentedSettings.speed has no description",
            "UndocumentedSettings.speed: its name 'Undocumented Speed' has no Turkish translation",
        ]
        assert panel_fields.property_problems(struct, "style") == [
            "UndocumentedSettings.style: the item 'A' has no description",
            "UndocumentedSettings.style: the item name 'Unnamed Item' has no Turkish",
        ]
    finally:
        bpy.utils.unregister_class(UndocumentedSettings)


def test_a_field_the_settings_lack_and_another_data_block_are_found():
    source = """
class VIEW3D_PT_other(bpy.types.Panel):
    bl_label = "Turkish Lip Sync"

    def draw(self, context):
        settings = context.scene.turkish_lipsync
        column = self.layout.column(heading="Head")
        column.prop(settings, "head")
        column.prop(settings, "no_such_field")
        column.prop(context.scene.render, "fps")
        column.operator("turkish_lipsync.no_such_operator")
"""
    drawn = panel_fields.drawn_by_panel(source, "other_panel.py")
    assert [(item.section, item.name) for item in drawn] == [
        ("Head", "head"),
        ("Head", "no_such_field"),
        ("Head", "fps"),
        ("Head", "turkish_lipsync.no_such_operator"),
    ]
    problems = panel_fields.reference_problems(drawn, panel_fields.settings_rna())
    assert problems == [
        "other_panel.py:9: TurkishLipSyncSettings has no property 'no_such_field'",
        "other_panel.py:10: draws context.scene.render.fps, a property of another data block than the "
        "add-on's settings, which the reference cannot describe",
        "other_panel.py:11: no operator turkish_lipsync.no_such_operator is registered",
    ]


def test_an_unknown_condition_is_shown_as_code():
    test = ast.parse("len(settings.text.lines) > 3", mode="eval").body
    assert panel_fields.condition_text(test, panel_fields.settings_rna()) == "`len(settings.text.lines) > 3`"
