"""Heads with visemes of their own: Vitruvian's Azure visemes and Godette's VRM vowels build the TR keys."""

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lab.kit.heads_on_disk import HEADS  # noqa: E402
from turkish_lipsync import blender  # noqa: E402
from turkish_lipsync.blender import heads, mesh, shapekeys  # noqa: E402
from turkish_lipsync.core.base.errors import HeadError  # noqa: E402
from turkish_lipsync.core.base.model import emotion_key_name, viseme_key_name  # noqa: E402
from turkish_lipsync.core.faces.reference import load_reference_head  # noqa: E402

VITRUVIAN = HEADS / "vitruvian" / "vitruvian_head_facs.glb"
GODETTE = HEADS / "godette" / "Godette_vrm_v4_named.glb"
BILABIALS = ("bpa", "bpe", "bpo", "ma", "me", "mo")
OPEN_VOWELS = ("a", "e", "o")


def _import(path, name):
    """The head as the batch script finds it among the file's objects (Godette's face beside its body)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    head = heads.find_head(heads.import_head(path))
    assert head.name == name
    return head


def _own_keys(head):
    """Every key of the head's own, as (value, coordinates), to check that a build leaves them alone."""
    blocks = head.data.shape_keys.key_blocks
    count = len(head.data.vertices)
    return {
        block.name: (block.value, mesh.read_coordinates(block.points, count))
        for block in blocks
        if not block.name.startswith("TR_")
    }


def _shape(head, key_name):
    """World coordinates of the head with one key at full weight (the key's own coordinates)."""
    block = head.data.shape_keys.key_blocks[key_name]
    return mesh.to_world(head, mesh.read_coordinates(block.points, len(head.data.vertices)))


class MidlineLips:
    """The midline gap between the lips: lowest upper-lip vertex minus highest lower-lip vertex (metres).

    The lips are told apart by the head's own open mouth, which drops the lower lip; only vertices near the
    front of the face's profile at their height count (within a 40th of the head's height), not the teeth.
    """

    def __init__(self, head, open_key, forward):
        rest = mesh.world_rest_coordinates(head)
        height = float(np.ptp(rest[:, 2]))
        drop = -(_shape(head, open_key) - rest)[:, 2]
        midline = np.where(np.abs(rest[:, 0] - np.median(rest[:, 0])) < 1e-3 * height)[0]
        depth = rest[midline] @ np.asarray(forward, dtype=np.float32)
        heights = rest[midline, 2]
        level = np.abs(heights[:, None] - heights[None]) < 0.01 * height
        profile = np.where(level, depth[None], -np.inf).max(axis=1)  # the face's front at each height
        front = midline[depth > profile - 0.025 * height]
        lower = front[drop[front] > 0.5 * drop.max()]
        top_of_lower = rest[lower, 2].max()
        near = front[np.abs(rest[front, 2] - top_of_lower) < 0.03 * height]
        self.lower = near[drop[near] > 0.5 * drop.max()]
        self.upper = near[drop[near] < 0.1 * drop.max()]
        assert len(self.lower) and len(self.upper)

    def gap(self, shape):
        return float(shape[self.upper, 2].min() - shape[self.lower, 2].max())


@pytest.fixture(scope="module")
def vitruvian():
    if not VITRUVIAN.is_file():
        pytest.skip("shared heads not found")
    head = _import(VITRUVIAN, "Vitruvian_head")
    before = _own_keys(head)
    report = shapekeys.build_shape_keys(head)
    return head, report, before


@pytest.fixture(scope="module")
def godette():
    if not GODETTE.is_file():
        pytest.skip("shared heads not found")
    head = _import(GODETTE, "Face")
    before = _own_keys(head)
    report = shapekeys.build_shape_keys(head)
    return head, report, before


def test_vitruvian_builds_from_its_azure_visemes_and_emotions(vitruvian):
    head, report, _ = vitruvian
    assert report.source == "convention" and report.convention.startswith("Azure")
    sources = report.key_sources
    assert sources[viseme_key_name("a")] == "own keys: aa_02 1"
    assert sources[viseme_key_name("bpa")] == "own keys: p_b_m_21 1"
    assert "w_uw_07" in sources[viseme_key_name("u")]
    assert sources[emotion_key_name("happy")] == "own keys: Happy 1"
    assert sources[emotion_key_name("angry")] == "own keys: Angry 1"
    assert sources[emotion_key_name("afraid")] == "own keys: Scared 1"
    assert sources["TR_blink_left"] == "own keys: Eyes_Closed_Left 1"
    # No Surprised key: raised brows, wide eyes and a dropped jaw of its own; nothing needs a transfer.
    assert sources[emotion_key_name("surprised")].startswith("own keys: Eyebrows_Raised_Left 1, ")
    assert sources["TR_brow_raise"] == "own keys: Eyebrows_Raised_Left 0.6, Eyebrows_Raised_Right 0.6"
    assert not [key for key, source in sources.items() if "transfer" in source]
    assert dict(head.data[shapekeys.KEY_SOURCES_PROPERTY]) == dict(sources)  # what the panel lists
    own = _shape(head, "aa_02") - mesh.world_rest_coordinates(head)
    built = _shape(head, viseme_key_name("a")) - mesh.world_rest_coordinates(head)
    np.testing.assert_allclose(built, own, atol=1e-6)


def test_vitruvian_bilabials_close_and_open_vowels_open(vitruvian):
    head, _, _ = vitruvian
    lips = MidlineLips(head, "Mouth_Large_Opened", forward=(0, -1, 0))
    for viseme in BILABIALS:
        assert lips.gap(_shape(head, viseme_key_name(viseme))) < 0.001, viseme
    for viseme in OPEN_VOWELS:
        assert lips.gap(_shape(head, viseme_key_name(viseme))) > 0.003, viseme
    assert lips.gap(_shape(head, viseme_key_name("a"))) > 0.01
    assert lips.gap(_shape(head, viseme_key_name("a"))) > 0.4 * lips.gap(_shape(head, "Mouth_Large_Opened"))


def test_own_emotion_is_released_only_around_the_mouth(vitruvian):
    head, _, _ = vitruvian
    rest = mesh.world_rest_coordinates(head)
    happy = _shape(head, emotion_key_name("happy")) - rest
    release = _shape(head, emotion_key_name("happy") + "_mouth_release") - rest
    opening = np.linalg.norm(_shape(head, viseme_key_name("a")) - rest, axis=1)
    mouth_moved = opening > 0.5 * opening.max()
    moved = np.linalg.norm(happy, axis=1) > 1e-4
    assert (moved & ~mouth_moved).any()
    together = happy + release
    # Where the visemes move the face, the release cancels the smile; around the eyes and brows it stays.
    assert np.abs(together[mouth_moved]).max() < 1e-5
    upper_face = moved & (rest[:, 2] > rest[mouth_moved, 2].max() + 0.04)
    assert upper_face.sum() > 100
    np.testing.assert_allclose(together[upper_face], happy[upper_face], atol=1e-6)


def test_a_build_leaves_the_heads_own_keys_alone_and_rebuilds_in_place(vitruvian):
    head, report, before = vitruvian
    after = _own_keys(head)
    assert set(after) == set(before)
    for name, (value, coordinates) in before.items():
        assert after[name][0] == value
        np.testing.assert_array_equal(after[name][1], coordinates)
    count = len(head.data.shape_keys.key_blocks)
    again = shapekeys.build_shape_keys(head)
    assert len(head.data.shape_keys.key_blocks) == count
    assert again.key_sources == report.key_sources


def test_godette_builds_from_its_vrm_vowels_and_blinks(godette):
    head, report, _ = godette
    assert report.source == "convention" and report.convention == "VRM vowels"
    sources = report.key_sources
    assert sources[viseme_key_name("a")] == "own keys: ah 1"
    assert sources[viseme_key_name("u")] == "own keys: uu 1"
    assert sources["TR_blink_left"] == "own keys: blink_left 1"
    assert sources["TR_blink_right"] == "own keys: blink_right 1"
    # VRM has no lip closure: b, p, m rest (closed) with the lip press from a transfer where one can be
    # made on this stylised head facing +Y; where none can, the report and a warning say so.
    if any("no other basis" in warning for warning in report.warnings):
        assert sources[viseme_key_name("bpa")] == "rest shape (lip press missing: no other basis)"
    else:
        assert sources[viseme_key_name("bpa")] == "transfer (lip press)"


def test_godette_bilabials_close_and_open_vowels_open(godette):
    head, _, _ = godette
    lips = MidlineLips(head, "ah", forward=(0, 1, 0))
    assert lips.gap(mesh.world_rest_coordinates(head)) < 0.001  # VRM heads rest with closed lips
    for viseme in BILABIALS:
        assert lips.gap(_shape(head, viseme_key_name(viseme))) < 0.001, viseme
    for viseme in ("a", "o"):  # Godette's own ee is a wide, flat mouth that keeps the midline shut
        assert lips.gap(_shape(head, viseme_key_name(viseme))) > 0.01, viseme


def _godette_mapping(folder):
    mapping = folder / "godette.toml"
    mapping.write_text(
        '[visemes.a]\nshapes = { oh = 0.5, ah = 0.5 }\n[expressions]\nhappy = "angled_eyebrows"\n',
        encoding="utf-8",
    )
    return mapping


def test_a_users_mapping_file_names_the_keys(tmp_path):
    if not GODETTE.is_file():
        pytest.skip("shared heads not found")
    head = _import(GODETTE, "Face")
    mapping = _godette_mapping(tmp_path)
    report = shapekeys.build_shape_keys(head, mapping_file=mapping)
    assert report.convention == "own mapping godette.toml"
    assert report.key_sources[viseme_key_name("a")] == "own keys: oh 0.5, ah 0.5"
    assert report.key_sources[emotion_key_name("happy")] == "own keys: angled_eyebrows 1"
    rest = mesh.world_rest_coordinates(head)
    expected = 0.5 * (_shape(head, "oh") - rest) + 0.5 * (_shape(head, "ah") - rest)
    np.testing.assert_allclose(_shape(head, viseme_key_name("a")) - rest, expected, atol=1e-6)
    missing = tmp_path / "other.toml"
    missing.write_text('[visemes.a]\nshapes = { "Jaw Open" = 1.0 }\n', encoding="utf-8")
    with pytest.raises(HeadError, match="None of the keys"):
        shapekeys.build_shape_keys(head, mapping_file=missing)
    assert report.key_sources == dict(head.data[shapekeys.KEY_SOURCES_PROPERTY])  # the failed build kept them


def test_convention_source_on_a_head_without_visemes_says_what_to_do():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    objects = heads.create_reference_head(bpy.context)
    with pytest.raises(HeadError, match="mapping file"):
        shapekeys.build_shape_keys(objects["head"], source="convention")


def test_the_build_operator_takes_the_mapping_file_of_the_panel(tmp_path):
    if not GODETTE.is_file():
        pytest.skip("shared heads not found")
    blender.register()
    try:
        head = _import(GODETTE, "Face")
        settings = bpy.context.scene.turkish_lipsync
        settings.head = head
        settings.key_source = "convention"
        settings.mapping_file = str(_godette_mapping(tmp_path))
        assert bpy.ops.turkish_lipsync.build_shape_keys() == {"FINISHED"}
        assert head.data[shapekeys.KEY_SOURCES_PROPERTY][viseme_key_name("a")] == "own keys: oh 0.5, ah 0.5"
    finally:
        blender.unregister()


def test_the_build_operator_asks_for_a_head_with_visemes():
    blender.register()
    try:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        bpy.context.scene.turkish_lipsync.key_source = "convention"
        with pytest.raises(RuntimeError, match="visemes of its own"):
            bpy.ops.turkish_lipsync.build_shape_keys()
    finally:
        blender.unregister()


OCULUS_FROM_TR = {
    "sil": "neutral", "PP": "bpa", "FF": "fvae", "TH": "dte", "DD": "dta", "kk": "gkya", "CH": "cjae",
    "SS": "sza", "nn": "na", "RR": "ra", "aa": "a", "E": "e", "ih": "Ii", "oh": "o", "ou": "u",
}  # fmt: skip


def test_oculus_visemes_win_over_the_heads_other_basis_which_fills_the_rest():
    """The reference head given Ready Player Me's viseme_* keys: they make the visemes, its units the rest."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    head = heads.create_reference_head(bpy.context)["head"]
    shapekeys.build_shape_keys(head)
    blocks = head.data.shape_keys.key_blocks
    count = len(head.data.vertices)
    for oculus, viseme in OCULUS_FROM_TR.items():
        shape = mesh.read_coordinates(blocks[viseme_key_name(viseme)].points, count)
        head.shape_key_add(name=f"viseme_{oculus}", from_mix=False).data.foreach_set("co", shape.ravel())
    blink = mesh.read_coordinates(blocks["TR_blink_left"].points, count)
    report = shapekeys.build_shape_keys(head)
    assert report.source == "convention" and report.convention == "Oculus / Meta visemes"
    assert report.key_sources[viseme_key_name("u")] == "own keys: viseme_ou 1"
    assert report.key_sources["TR_blink_left"] == "reference"  # Oculus has no blinks: the head's units
    np.testing.assert_allclose(mesh.read_coordinates(blocks["TR_blink_left"].points, count), blink, atol=1e-6)
    rest = mesh.rest_coordinates(head)
    rounded = mesh.read_coordinates(blocks["viseme_ou"].points, count) - rest
    built = mesh.read_coordinates(blocks[viseme_key_name("u")].points, count) - rest
    np.testing.assert_allclose(built, rounded, atol=1e-6)


def test_what_vrm_lacks_comes_from_the_heads_other_basis_for_that_part_only():
    """VRM vowels on the reference head: b, p, m are the rest shape plus the reference's own lip press."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    head = heads.create_reference_head(bpy.context)["head"]
    shapekeys.build_shape_keys(head)
    blocks = head.data.shape_keys.key_blocks
    count = len(head.data.vertices)
    for vrm, viseme in {"A": "a", "I": "Ii", "U": "u", "E": "e", "O": "o"}.items():
        shape = mesh.read_coordinates(blocks[viseme_key_name(viseme)].points, count)
        head.shape_key_add(name=f"Fcl_MTH_{vrm}", from_mix=False).data.foreach_set("co", shape.ravel())
    report = shapekeys.build_shape_keys(head)
    assert report.convention == "VRM vowels"
    assert report.key_sources[viseme_key_name("bpa")] == "reference (lip press)"
    assert report.key_sources[viseme_key_name("fvae")] == (
        "own keys: Fcl_MTH_I 0.2 + reference (lower lip to the upper teeth)"
    )
    units = shapekeys.reference_units(head, load_reference_head())
    press = 0.4 * (units["mouthPressLeft"] + units["mouthPressRight"])
    built = mesh.read_coordinates(blocks[viseme_key_name("bpa")].points, count) - mesh.rest_coordinates(head)
    np.testing.assert_allclose(built, press, atol=1e-6)
