"""The default head, importing heads, finding the head among objects."""

import pytest

bpy = pytest.importorskip("bpy")

import numpy as np  # noqa: E402

from lab.kit.heads_on_disk import HEADS  # noqa: E402
from turkish_lipsync.blender import heads, shapekeys  # noqa: E402
from turkish_lipsync.core.base.errors import HeadError  # noqa: E402
from turkish_lipsync.core.faces.reference import load_reference_head  # noqa: E402


def test_reference_head_has_parented_parts_with_materials():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    objects = heads.create_reference_head(bpy.context, name="Speaker")
    head = objects["head"]
    reference = load_reference_head()
    assert head.name == "Speaker" and len(head.data.vertices) == len(reference.parts["skin"])
    for part in heads.PART_OBJECT_SUFFIXES:
        assert objects[part].parent == head
        assert len(objects[part].data.vertices) == len(reference.parts[part])
        assert objects[part].data.materials[0] is not None
    bounds = [head.matrix_world @ v.co for v in head.data.vertices]
    assert min(v.y for v in bounds) < head.matrix_world.translation.y  # the face looks toward -Y
    assert heads.find_head(list(bpy.data.objects)) == head


def _image_nodes(material):
    return [node for node in material.node_tree.nodes if node.type == "TEX_IMAGE"]


def test_skin_materials_read_real_textures_through_the_head_uvs():
    """Not pink: every image the skin uses has pixels, and the lips mask lies on the lips of the UV layout."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    head = heads.create_reference_head(bpy.context)["head"]
    assert {layer.name for layer in head.data.uv_layers} == {heads.UV_MAP, "Eyebrows"}
    skin = head.data.materials[0]
    images = {node.image.name: node.image for node in _image_nodes(skin)}
    assert {"TR_lips", "TR_eyelids", "TR_inside_mouth", "TR_eyebrows"} <= set(images)
    red = {}
    for name, image in images.items():
        width, height = image.size
        assert width >= 256 and height >= 256 and image.packed_file is not None, name
        pixels = np.empty(width * height * 4, np.float32)
        image.pixels.foreach_get(pixels)
        red[name] = pixels.reshape(height, width, 4)[:, :, 0]
        assert red[name].max() > 0.9 and red[name].min() < 0.1, name  # a mask, not a missing-image fill
    height, width = red["TR_lips"].shape
    reference = load_reference_head()
    skin_part = reference.parts["skin"]
    local = {int(v): i for i, v in enumerate(skin_part)}
    uv_layer = head.data.uv_layers[heads.UV_MAP].data
    loops = head.data.loops

    def mask_at_vertex(vertex):
        corner = next(i for i, loop in enumerate(loops) if loop.vertex_index == vertex)
        u, v = uv_layer[corner].uv
        return red["TR_lips"][min(int(v * height), height - 1), min(int(u * width), width - 1)]

    assert mask_at_vertex(local[reference.landmark_vertices["upper_lip"]]) > 0.5
    assert mask_at_vertex(local[reference.landmark_vertices["nose_tip"]]) < 0.1
    # Painted eyebrows: dark over the brow, nothing at the nose or on the back of the head.
    brows = np.array([reference.landmark_vertices["brow_left"], reference.landmark_vertices["brow_right"]])
    assert (reference.eyebrow_cover(brows) > 0.4).all()
    back = reference.eyebrow_uvs(skin_part[reference.vertices[skin_part, 1] > 0.0])
    assert (back < 0).all()


def test_eyes_are_procedural_and_every_material_is_set_for_workbench_too():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    objects = heads.create_reference_head(bpy.context)
    eye = objects["left_eye"].data.materials[0]
    assert any(node.type == "TEX_COORD" for node in eye.node_tree.nodes)
    for obj in objects.values():
        for material in obj.data.materials:
            shader = next(node for node in material.node_tree.nodes if node.type == "BSDF_PRINCIPLED")
            assert shader.outputs["BSDF"].is_linked, material.name
            assert tuple(material.diffuse_color)[:3] != (0.8, 0.8, 0.8), material.name  # not the default


def _key_motion(obj, key_name):
    keys = obj.data.shape_keys.key_blocks
    count = len(obj.data.vertices)
    rest, moved = np.empty(count * 3, np.float32), np.empty(count * 3, np.float32)
    keys[0].points.foreach_get("co", rest)
    keys[key_name].points.foreach_get("co", moved)
    return (moved - rest).reshape(-1, 3)


def test_eyelashes_close_with_the_blink_keys_and_the_brows_rise_with_the_brow_key():
    """Lashes are parts of their own that the built blink keys carry down with the upper lid; the painted
    brows sit on skin that TR_brow_raise lifts."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    objects = heads.create_reference_head(bpy.context)
    shapekeys.build_shape_keys(objects["head"])
    reference = load_reference_head()
    for side, other in (("left", "right"), ("right", "left")):
        lashes = objects[f"{side}_eyelashes"]
        blink = _key_motion(lashes, f"TR_blink_{side}")
        rest = np.array([vertex.co for vertex in lashes.data.vertices]) + np.array(objects["head"].location)
        upper = rest[:, 2] > reference.landmarks[f"eye_inner_{side}"][2] + 0.002
        assert np.median(blink[upper, 2]) < -0.004  # the upper lashes come down with the lid
        assert np.abs(_key_motion(objects[f"{other}_eyelashes"], f"TR_blink_{side}")).max() < 1e-6
    skin = reference.parts["skin"]
    on_brows = reference.eyebrow_cover(skin) > 0.5
    assert on_brows.sum() >= 10
    assert np.median(_key_motion(objects["head"], "TR_brow_raise")[on_brows, 2]) > 0.001


def test_the_neck_is_closed():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    reference = load_reference_head()
    head = heads.create_reference_head(bpy.context)["head"]
    cap = head.data.polygons[-1]
    assert cap.loop_total == len(reference.neck_loop) and not cap.use_smooth
    # Every edge of the skin is shared by two faces: with the cap, the skin is closed.
    edge_faces = {}
    for polygon in head.data.polygons:
        for key in polygon.edge_keys:
            edge_faces[key] = edge_faces.get(key, 0) + 1
    assert [key for key, count in edge_faces.items() if count != 2] == []


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
