"""Visemes of other conventions: recognised by name on real heads' key lists, mapped onto every TR key."""

import json
import struct

import numpy as np
import pytest

from lab.kit.heads_on_disk import HEADS
from turkish_lipsync.core.base.errors import DataError
from turkish_lipsync.core.base.model import (
    EMOTIONS,
    emotion_key_name,
    emotion_release_key_name,
    viseme_key_name,
)
from turkish_lipsync.core.faces.conventions import (
    canonical_name,
    convention_key_deltas,
    load_conventions,
    match_convention,
    mouth_weights,
    plan_keys,
    read_user_mapping,
    recognise_convention,
    unmatched_names,
)
from turkish_lipsync.core.faces.recipes import VISEME_NAMES, empower, load_recipes

OCULUS = ("sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "ih", "oh", "ou")


def _glb_target_names(path):
    """The morph target names a glTF exporter stored in the file (meshes[].extras.targetNames)."""
    data = path.read_bytes()
    (length,) = struct.unpack("<I", data[12:16])
    document = json.loads(data[20 : 20 + length])
    return {mesh.get("name"): mesh.get("extras", {}).get("targetNames", []) for mesh in document["meshes"]}


def _by_name():
    return {convention.name: convention for convention in load_conventions()}


def test_every_table_loads_and_maps_only_known_visemes():
    conventions = _by_name()
    assert set(conventions) == {"azure", "oculus", "papagayo", "vrm"}
    for convention in conventions.values():
        assert set(convention.visemes) <= set(VISEME_NAMES)
        mapped = [v for v in convention.visemes.values() if v.shapes or v.units]
        assert len(mapped) == 36, convention.name  # every viseme but neutral says how it is made
        assert not convention.visemes["neutral"].shapes
    assert len(conventions["azure"].spellings) == 22
    assert len(conventions["oculus"].spellings) == 15
    assert len(conventions["vrm"].spellings) == 5


@pytest.mark.parametrize(
    ("spelling", "prefixes", "expected"),
    [
        ("aa_02", (), "aa"),
        ("p_b_m_21", (), "pbm"),
        ("vrc.v_aa", ("vrc_v", "v"), "aa"),
        ("viseme_PP", ("viseme",), "pp"),
        ("Fcl_MTH_A", ("fcl_mth",), "a"),
        ("blendShape1.viseme_aa", ("viseme",), "aa"),
        ("Mouth_A", ("mouth",), "a"),
        ("ah.001", (), "ah"),
        ("Face|mouth_MBP", ("mouth",), "mbp"),
    ],
)
def test_canonical_names(spelling, prefixes, expected):
    assert canonical_name(spelling, prefixes) == expected


@pytest.mark.parametrize(
    ("names", "expected"),
    [
        ([f"viseme_{name}" for name in OCULUS], "oculus"),
        ([f"vrc.v_{name.lower()}" for name in OCULUS], "oculus"),
        (["viseme_sil", "viseme_PP", "viseme_FF", "viseme_TH", "viseme_DD", "viseme_kk", "viseme_CH",
          "viseme_SS", "viseme_nn", "viseme_RR", "viseme_aa", "viseme_E", "viseme_I", "viseme_O", "viseme_U"],
         "oculus"),  # Ready Player Me
        (["Fcl_MTH_A", "Fcl_MTH_I", "Fcl_MTH_U", "Fcl_MTH_E", "Fcl_MTH_O"], "vrm"),  # VRoid
        (["aa", "ih", "ou", "ee", "oh"], "vrm"),  # VRM 1.0: shares four names with Oculus, yet VRM
        (["Mouth_A", "Mouth_I", "Mouth_U", "Mouth_E", "Mouth_O"], "vrm"),
        (["mouth_AI", "mouth_E", "mouth_O", "mouth_U", "mouth_etc", "mouth_MBP", "mouth_FV", "mouth_L",
          "mouth_WQ", "mouth_rest"], "papagayo"),
        (["jawOpen", "mouthClose", "Basis", "Smile"], None),
        (["aa", "E"], None),  # two shapes are below every convention's minimum
    ],
)  # fmt: skip
def test_recognition_by_name(names, expected):
    match = recognise_convention(names)
    assert (match.convention.name if match else None) == expected


@pytest.mark.skipif(not (HEADS / "vitruvian").is_dir(), reason="shared heads not found")
def test_vitruvian_is_azure_with_its_emotions_and_blinks():
    names = _glb_target_names(HEADS / "vitruvian" / "vitruvian_head_facs.glb")["Vitruvian_head"]
    match = recognise_convention(names)
    assert match.convention.name == "azure"
    assert len(match.shapes) == 21  # every Azure viseme but silence
    assert match.shapes["aa"] == "aa_02" and match.shapes["p_b_m"] == "p_b_m_21"
    assert match.expressions["happy"] == {"Happy": 1.0} and match.expressions["angry"] == {"Angry": 1.0}
    assert match.expressions["afraid"] == {"Scared": 1.0}
    assert match.expressions["blink_left"] == {"Eyes_Closed_Left": 1.0}
    # No Surprised key: the surprise is composed of the head's raised brows, wide eyes and dropped jaw.
    assert set(match.expressions["surprised"]) == {
        "Eyebrows_Raised_Left", "Eyebrows_Raised_Right", "Eyes_Opened_Max_Left", "Eyes_Opened_Max_Right",
        "aa_02",
    }  # fmt: skip
    assert match.expressions["brow_raise"] == {"Eyebrows_Raised_Left": 0.6, "Eyebrows_Raised_Right": 0.6}


@pytest.mark.skipif(not (HEADS / "godette").is_dir(), reason="shared heads not found")
def test_godette_is_vrm_with_its_blinks():
    names = _glb_target_names(HEADS / "godette" / "Godette_vrm_v4_named.glb")["FaceMesh"]
    match = recognise_convention(names)
    assert match.convention.name == "vrm"
    assert dict(match.shapes) == {"a": "ah", "i": "ih", "u": "uu", "e": "ee", "o": "oh"}
    assert dict(match.expressions) == {"blink_left": {"blink_left": 1.0}, "blink_right": {"blink_right": 1.0}}


def test_plan_says_where_each_key_comes_from():
    vrm = _by_name()["vrm"]
    match = match_convention(["ah", "ih", "uu", "ee", "oh", "blink_left", "blink_right"], vrm)
    recipes = load_recipes()
    plans = plan_keys(match, recipes)
    assert set(plans) == set(recipes.key_recipes())
    assert dict(plans[viseme_key_name("a")].shapes) == {"ah": 1.0}
    assert not plans[viseme_key_name("a")].units
    closure = plans[viseme_key_name("bpa")]  # VRM has no closure: the rest shape and a lip press
    assert not closure.shapes and closure.units == {"mouthPressLeft": 0.4, "mouthPressRight": 0.4}
    assert closure.describe("transfer") == "transfer (lip press)"
    bitten = plans[viseme_key_name("fvae")]  # own shape plus the part VRM lacks
    assert bitten.describe("transfer") == "own keys: ih 0.2 + transfer (lower lip to the upper teeth)"
    assert plans["TR_blink_left"].describe("transfer") == "own keys: blink_left 1"
    happy = plans[emotion_key_name("happy")]  # no emotions on this head: the ARKit recipe whole
    assert not happy.shapes and happy.units == recipes.key_recipes()[emotion_key_name("happy")]


def test_a_viseme_whose_shapes_the_head_lacks_takes_its_arkit_recipe():
    oculus = _by_name()["oculus"]
    names = [f"viseme_{name}" for name in OCULUS if name != "FF"]
    plans = plan_keys(match_convention(names, oculus), load_recipes())
    assert plans[viseme_key_name("fvae")].units == load_recipes().key_recipes()[viseme_key_name("fvae")]
    assert dict(plans[viseme_key_name("bpa")].shapes) == {"viseme_PP": 1.0}


def test_deltas_sum_own_shapes_and_release_own_emotions_where_the_mouth_moves():
    count = 6
    rng = np.random.default_rng(3)
    own = {name: np.zeros((count, 3), np.float32) for name in ("Happy", "aa_02", "ow_08", "p_b_m_21")}
    own["aa_02"][:3] = rng.normal(size=(3, 3))  # the mouth: vertices 0-2
    own["ow_08"][:3] = rng.normal(size=(3, 3))
    own["Happy"][:] = 0.01  # the whole face: mouth and eyes
    azure = _by_name()["azure"]
    match = match_convention(list(own), azure)
    plans = plan_keys(match, load_recipes())
    deltas = empower(convention_key_deltas(plans, own, {}, count), 3.0)
    np.testing.assert_allclose(deltas[viseme_key_name("o")], 0.9 * own["ow_08"])
    np.testing.assert_allclose(deltas[emotion_key_name("happy")], 3.0 * own["Happy"], rtol=1e-6)
    release = deltas[emotion_release_key_name("happy")]
    mouth = mouth_weights([own["aa_02"], own["ow_08"]], count)
    assert (mouth[:3] > 0).all() and (mouth[3:] == 0).all()
    np.testing.assert_allclose(release, -3.0 * own["Happy"] * mouth[:, None], rtol=1e-6)
    for emotion in EMOTIONS:  # every emotion key exists, own or not
        assert emotion_key_name(emotion) in deltas


def test_user_mapping_names_the_heads_keys_exactly(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(
        '[visemes.a]\nshapes = { "Mouth Open" = 0.8 }\n'
        '[visemes.bpa]\nshapes = { "Lips Shut" = 1.0 }\nunits = { mouthPress = 0.2 }\nfills = "press"\n'
        '[expressions]\nhappy = "Grin"\n',
        encoding="utf-8",
    )
    mapping = read_user_mapping(path)
    match = match_convention(["Mouth Open", "Lips Shut", "Grin", "mouth_open"], mapping)
    plans = plan_keys(match, load_recipes())
    assert dict(plans[viseme_key_name("a")].shapes) == {"Mouth Open": 0.8}
    assert plans[viseme_key_name("bpa")].describe("arkit") == "own keys: Lips Shut 1 + arkit (press)"
    assert dict(plans[emotion_key_name("happy")].shapes) == {"Grin": 1.0}
    assert plans[viseme_key_name("e")].units  # not mapped: the ARKit recipe
    assert unmatched_names(match) == ()


def test_a_mapping_naming_keys_the_head_lacks_says_which(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(
        '[visemes.a]\nshapes = { "Mouth Open" = 0.8 }\n[visemes.bpa]\nshapes = { "Lips Shutt" = 1.0 }\n'
        '[expressions]\nhappy = "Grin"\n',
        encoding="utf-8",
    )
    match = match_convention(["Mouth Open", "Lips Shut"], read_user_mapping(path))
    spelling, expressions = unmatched_names(match)
    assert "'Lips Shutt'" in spelling and "Mouth Open" not in spelling
    assert "happy" in expressions
    # the misspelt viseme falls back to its ARKit recipe, the others keep the head's keys
    plans = plan_keys(match, load_recipes())
    assert plans[viseme_key_name("bpa")].units and not plans[viseme_key_name("bpa")].shapes
    assert dict(plans[viseme_key_name("a")].shapes) == {"Mouth Open": 0.8}


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('[visemes.aa]\nshapes = { "X" = 1.0 }\n', "unknown TR visemes"),
        ('[visemes.a]\nshapes = { "X" = 5.0 }\n', "weights must lie"),
        ('[visemes.a]\nshapes = { "X" = 1.0 }\nunits = { jawOpen = 0.2 }\n', "fills"),
        ('[visemes.a]\nshapes = { "X" = 1.0 }\nunits = { jawOpenn = 0.2 }\nfills = "x"\n', "ARKit units"),
        ("[expressions]\njoy = 'X'\n", "may name only"),
        ("[expressions]\nhappy = ['X', 1]\n", "key names or tables"),
        ("[visemes.a\n", "TOML"),
    ],
)
def test_bad_user_mapping_is_refused_with_its_path(tmp_path, text, message):
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(DataError, match=message) as error:
        read_user_mapping(path)
    assert str(path) in str(error.value)


def test_missing_user_mapping_says_so(tmp_path):
    with pytest.raises(DataError, match="not found"):
        read_user_mapping(tmp_path / "none.toml")


def test_without_another_basis_the_report_says_what_is_missing():
    vrm = _by_name()["vrm"]
    plans = plan_keys(match_convention(["ah", "ih", "uu", "ee", "oh"], vrm), load_recipes())
    assert plans[viseme_key_name("bpa")].describe(None) == "rest shape (lip press missing: no other basis)"
    assert plans[emotion_key_name("sad")].describe(None) == "at rest: no other basis"
    assert plans[viseme_key_name("o")].describe(None) == "own keys: oh 1"


def test_a_combined_expression_needs_all_its_keys_and_is_released_as_a_whole(tmp_path):
    path = tmp_path / "combined.toml"
    path.write_text(
        "[visemes.a]\nshapes = { Open = 1.0 }\n"
        '[expressions]\nsurprised = { "Brows Up" = 1.0, Open = 0.3 }\n'
        'happy = ["Smile", { Grin = 1.0, Cheeks = 0.5 }]\n',
        encoding="utf-8",
    )
    mapping = read_user_mapping(path)
    match = match_convention(["Open", "Brows Up", "Grin"], mapping)
    assert match.expressions == {"surprised": {"Brows Up": 1.0, "Open": 0.3}}  # no Cheeks: no own happy
    plans = plan_keys(match, load_recipes())
    release = plans[emotion_release_key_name("surprised")]
    assert release.describe("transfer") == "mouth part of own keys: Brows Up 1, Open 0.3"
    count = 4
    own = {name: np.zeros((count, 3), np.float32) for name in ("Open", "Brows Up")}
    own["Open"][0] = (0.0, 0.0, -0.02)  # the jaw
    own["Brows Up"][3] = (0.0, 0.0, 0.005)  # a brow
    deltas = convention_key_deltas(plans, own, {}, count)
    surprised = deltas[emotion_key_name("surprised")]
    np.testing.assert_allclose(surprised, own["Brows Up"] + 0.3 * own["Open"])
    together = surprised + deltas[emotion_release_key_name("surprised")]
    np.testing.assert_allclose(together[0], 0, atol=1e-7)  # the jaw drop is released while speaking
    np.testing.assert_allclose(together[3], own["Brows Up"][3])  # the brows stay up
