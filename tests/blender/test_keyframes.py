"""Weight tracks become F-curves on the shape keys, in bulk, replacing only ours."""

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from turkish_lipsync.blender import compat, keyframes, owned_keys  # noqa: E402
from turkish_lipsync.core.base.model import Track, WeightTracks  # noqa: E402


def _mesh_with_keys(name: str, key_names: tuple[str, ...], users: tuple[str, ...] = ()) -> bpy.types.Object:
    """A mesh with shape keys: ours (key_names starting with TR_, marked as a build marks them) and the
    user's (the rest, and users: keys of the user's own that carry our names)."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [(0, 1, 2)])
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    obj.shape_key_add(name="Basis")
    for key_name in (*users, *key_names):
        block = obj.shape_key_add(name=key_name)
        block.data[0].co = (0.0, 0.0, 1.0)
    ours = [key_name for key_name in key_names if key_name.startswith("TR_")]
    owned_keys.mark_owned(obj, {key_name: obj.data.shape_keys.key_blocks[key_name].name for key_name in ours})
    return obj


def _tracks(fps: float = 25.0, interpolation: str = "LINEAR") -> WeightTracks:
    return WeightTracks(
        fps=fps,
        frame_count=12,
        interpolation=interpolation,
        tracks=(
            Track("TR_viseme_a", np.array([0.0, 2.5, 5.0, 7.25]), np.array([0.0, 1.0, 0.2, 0.0])),
            Track("TR_viseme_u", np.array([0.0, 4.0, 11.0]), np.array([0.0, 0.9, 0.0])),
            Track("TR_emotion_happy", np.array([0.0, 11.0]), np.array([0.3, 0.6])),
        ),
    )


@pytest.fixture(autouse=True)
def empty_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    yield


def _curves(obj) -> dict[str, object]:
    action = obj.data.shape_keys.animation_data.action
    return {fc.data_path: fc for fc in compat.all_action_fcurves(action)}


def test_tracks_are_keyed_at_their_frames_with_their_values():
    head = _mesh_with_keys("Head", ("TR_viseme_a", "TR_viseme_u", "TR_emotion_happy"))
    written = keyframes.write_weight_tracks([head], _tracks(), start_frame=10, action_name="TR_şu köşe")

    assert [(w.object_name, w.action_name, w.curve_count, w.key_count) for w in written] == [
        ("Head", "TR_şu köşe", 3, 9)
    ]
    curves = _curves(head)
    curve = curves['key_blocks["TR_viseme_a"].value']
    coordinates = np.array([tuple(point.co) for point in curve.keyframe_points])
    np.testing.assert_allclose(coordinates[:, 0], [10.0, 12.5, 15.0, 17.25], atol=1e-5)
    np.testing.assert_allclose(coordinates[:, 1], [0.0, 1.0, 0.2, 0.0], atol=1e-6)
    assert {point.interpolation for point in curve.keyframe_points} == {"LINEAR"}
    assert curve.group is not None and curve.group.name == "TR visemes"
    assert curves['key_blocks["TR_emotion_happy"].value'].group.name == "TR emotions"

    # The evaluated weights follow the tracks between keys.
    bpy.context.scene.frame_set(13)
    expected = np.interp(3.0, [0.0, 2.5, 5.0, 7.25], [0.0, 1.0, 0.2, 0.0])
    assert head.data.shape_keys.key_blocks["TR_viseme_a"].value == pytest.approx(expected, abs=1e-5)


def test_fractional_frame_rate_keys_land_between_whole_frames():
    head = _mesh_with_keys("Head", ("TR_viseme_a",))
    scene = bpy.context.scene
    scene.render.fps, scene.render.fps_base = 30, 1.001
    fps = scene.render.fps / scene.render.fps_base
    seconds = np.array([0.0, 0.1, 0.2])
    tracks = WeightTracks(fps, 7, "LINEAR", (Track("TR_viseme_a", seconds * fps, np.array([0.0, 1.0, 0.0])),))
    keyframes.write_weight_tracks([head], tracks, start_frame=1, action_name="TR_a")
    frames = [point.co[0] for point in _curves(head)['key_blocks["TR_viseme_a"].value'].keyframe_points]
    np.testing.assert_allclose(frames, 1 + seconds * 29.97002997, atol=1e-4)


def test_constant_and_bezier_interpolation_are_set_on_every_key():
    head = _mesh_with_keys("Head", ("TR_viseme_a", "TR_viseme_u"))
    for interpolation in ("CONSTANT", "BEZIER"):
        keyframes.write_weight_tracks([head], _tracks(interpolation=interpolation), 1, "TR_a")
        for curve in _curves(head).values():
            assert {point.interpolation for point in curve.keyframe_points} == {interpolation}


def test_regenerating_replaces_our_curves_and_keeps_the_users():
    head = _mesh_with_keys("Head", ("TR_viseme_a", "TR_viseme_u", "Smile"))
    key = head.data.shape_keys
    key.key_blocks["Smile"].value = 0.4
    key.key_blocks["Smile"].keyframe_insert("value", frame=7)
    user_action_name = key.animation_data.action.name

    keyframes.write_weight_tracks([head], _tracks(), 1, "TR_first")
    keyframes.write_weight_tracks([head], _tracks(), 30, "TR_second")

    # The user's action is kept and holds ours next to the user's curve, each curve once.
    assert key.animation_data.action.name == user_action_name
    paths = [fc.data_path for fc in compat.all_action_fcurves(key.animation_data.action)]
    assert sorted(paths) == sorted(
        ['key_blocks["Smile"].value', 'key_blocks["TR_viseme_a"].value', 'key_blocks["TR_viseme_u"].value']
    )
    curves = _curves(head)
    assert [tuple(p.co) for p in curves['key_blocks["Smile"].value'].keyframe_points] == [
        pytest.approx((7.0, 0.4))
    ]
    assert curves['key_blocks["TR_viseme_a"].value'].keyframe_points[0].co[0] == pytest.approx(30.0)


def test_each_utterance_gets_its_own_action_and_the_same_one_is_reused():
    head = _mesh_with_keys("Head", ("TR_viseme_a",))
    keyframes.write_weight_tracks([head], _tracks(), 1, "TR_merhaba")
    first = head.data.shape_keys.animation_data.action.name
    keyframes.write_weight_tracks([head], _tracks(), 1, "TR_benim adım")
    second = head.data.shape_keys.animation_data.action.name
    keyframes.write_weight_tracks([head], _tracks(), 1, "TR_benim adım")
    assert (first, second) == ("TR_merhaba", "TR_benim adım")
    assert head.data.shape_keys.animation_data.action.name == "TR_benim adım"
    assert len([a for a in bpy.data.actions if a.name.startswith("TR_benim")]) == 1
    assert len(_curves(head)) == 1


def test_teeth_follow_with_the_tracks_their_keys_have():
    head = _mesh_with_keys("Head", ("TR_viseme_a", "TR_viseme_u", "TR_emotion_happy"))
    teeth = _mesh_with_keys("Teeth", ("TR_viseme_a",))
    plain = _mesh_with_keys("Plain", ())
    written = keyframes.write_weight_tracks([head, teeth, plain], _tracks(), 1, "TR_a")
    assert [(w.object_name, w.action_name, w.curve_count) for w in written] == [
        ("Head", "TR_a", 3),
        ("Teeth", "TR_a.Teeth", 1),
    ]
    assert list(_curves(teeth)) == ['key_blocks["TR_viseme_a"].value']
    assert plain.data.shape_keys.animation_data is None


def test_remove_weight_tracks_leaves_other_curves():
    head = _mesh_with_keys("Head", ("TR_viseme_a", "Smile"))
    head.data.shape_keys.key_blocks["Smile"].keyframe_insert("value", frame=1)
    keyframes.write_weight_tracks([head], _tracks(), 1, "TR_a")
    assert keyframes.remove_weight_tracks([head]) == 1
    assert list(_curves(head)) == ['key_blocks["Smile"].value']


def test_a_users_own_key_named_like_ours_is_never_keyed():
    """A user's sculpt called TR_viseme_a is theirs: no curve of ours drives it, nothing resets it; with
    our own a beside it (built as TR_viseme_a.001), the track keys ours."""
    alone = _mesh_with_keys("Sculpted", (), users=("TR_viseme_a", "TR_viseme_u"))
    alone.data.shape_keys.key_blocks["TR_viseme_a"].value = 0.7
    assert keyframes.write_weight_tracks([alone], _tracks(), 1, "TR_test") == ()
    assert alone.data.shape_keys.animation_data is None
    assert alone.data.shape_keys.key_blocks["TR_viseme_a"].value == pytest.approx(0.7)
    beside = _mesh_with_keys("Beside", ("TR_viseme_u",), users=("TR_viseme_a",))
    ours = beside.shape_key_add(name="TR_viseme_a.001")
    owned_keys.mark_owned(beside, {"TR_viseme_a": ours.name, "TR_viseme_u": "TR_viseme_u"})
    keyframes.write_weight_tracks([beside], _tracks(), 1, "TR_test")
    assert set(_curves(beside)) == {'key_blocks["TR_viseme_a.001"].value', 'key_blocks["TR_viseme_u"].value'}


def test_a_part_gets_no_curve_for_a_key_that_leaves_it_still():
    head = _mesh_with_keys("Head", ("TR_viseme_a", "TR_viseme_u", "TR_emotion_happy"))
    teeth = _mesh_with_keys("Teeth", ("TR_viseme_a", "TR_viseme_u"))
    teeth.data.shape_keys.key_blocks["TR_viseme_u"].data[0].co = (0.0, 0.0, 0.0)  # u leaves the teeth
    written = keyframes.write_weight_tracks([head, teeth], _tracks(), 1, "TR_a")
    assert [(w.object_name, w.curve_count) for w in written] == [("Head", 3), ("Teeth", 1)]
    assert list(_curves(teeth)) == ['key_blocks["TR_viseme_a"].value']
