"""The default head, importing heads, finding the head among objects."""

import pytest

bpy = pytest.importorskip("bpy")

from tests.heads_on_disk import HEADS  # noqa: E402
from turkish_lipsync.blender import heads  # noqa: E402
from turkish_lipsync.core.errors import HeadError  # noqa: E402


def test_reference_head_has_parented_parts_with_materials():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    objects = heads.create_reference_head(bpy.context, name="Speaker")
    head = objects["head"]
    assert head.name == "Speaker" and len(head.data.vertices) == 4311
    for part in ("upper_teeth", "lower_teeth", "tongue", "left_eye", "right_eye"):
        assert objects[part].parent == head
        assert objects[part].data.materials[0] is not None
    assert len(objects["left_eye"].data.materials) == 3  # sclera, iris, pupil
    bounds = [head.matrix_world @ v.co for v in head.data.vertices]
    assert min(v.y for v in bounds) < head.matrix_world.translation.y  # the face looks toward -Y
    assert heads.find_head(list(bpy.data.objects)) == head


def test_import_and_find_the_head_of_a_glb_with_separate_teeth():
    path = HEADS / "makehuman" / "mh_head_expression_units.glb"
    if not path.exists():
        pytest.skip(f"{path} not present")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    imported = heads.import_head(path)
    head = heads.find_head(imported)
    assert head.name == "head"
    parts = {obj.name for obj in heads.find_head_parts(head, imported)}
    assert {"teeth_upper", "teeth_lower", "tongue"} <= parts


def test_refusals_say_why(tmp_path):
    with pytest.raises(HeadError, match="use one of"):
        heads.import_head(tmp_path / "head.stl")
    with pytest.raises(HeadError, match="not found"):
        heads.import_head(tmp_path / "head.obj")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    empty = bpy.data.objects.new("empty", None)
    with pytest.raises(HeadError, match="mesh with faces"):
        heads.find_head([empty])
