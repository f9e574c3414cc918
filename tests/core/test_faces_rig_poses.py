"""Face-rig poses without Blender: how weights blend into bone motion, the mappings that come with the
extension, and a character's own set-up as it is stored."""

import numpy as np
import pytest

from turkish_lipsync.core.base.errors import DataError, HeadError
from turkish_lipsync.core.base.model import Track, WeightTracks
from turkish_lipsync.core.faces.recipes import load_recipes
from turkish_lipsync.core.faces.rig_mappings import (
    OwnRig,
    own_rig_from_json,
    own_rig_to_json,
    read_rig_template,
    rig_template,
    rig_templates,
)
from turkish_lipsync.core.faces.rig_poses import (
    BoneMove,
    FrameMove,
    Pose,
    RigMapping,
    bone_motion,
    pose_targets,
    quaternions,
    resolve_moves,
    rotation_vectors,
)


def _tracks(**weights) -> WeightTracks:
    """Tracks of one frame each at the given weights, and a rest frame before."""
    return WeightTracks(
        fps=25,
        frame_count=2,
        interpolation="LINEAR",
        tracks=tuple(Track(name, np.array([0.0, 1.0]), np.array([0.0, w])) for name, w in weights.items()),
    )


def _slerp_from_identity(q: np.ndarray, t: float) -> np.ndarray:
    angle = 2 * np.arccos(q[0])
    axis = q[1:] / np.sin(angle / 2)
    return np.concatenate([[np.cos(t * angle / 2)], np.sin(t * angle / 2) * axis])


def test_rotation_vectors_and_quaternions_are_each_others_inverse():
    vectors = np.random.default_rng(3).normal(size=(50, 3))
    vectors *= (np.pi * 0.9 / np.linalg.norm(vectors, axis=1))[:, None] * np.random.default_rng(4).random(
        (50, 1)
    )
    np.testing.assert_allclose(rotation_vectors(quaternions(vectors)), vectors, atol=1e-9)
    np.testing.assert_allclose(quaternions(np.zeros((1, 3))), [[1, 0, 0, 0]])


def test_one_pose_at_a_weight_is_the_slerp_from_rest_and_locations_add():
    turn = np.array([0.5, 0.2, -0.1])
    mapping = RigMapping(
        "m",
        "M",
        {
            "jawOpen": Pose({"jaw": BoneMove(location=(0.0, 0.01, 0.0), rotation=tuple(turn))}),
            "mouthClose": Pose({"jaw": BoneMove(location=(0.0, 0.0, 0.02))}),
        },
    )
    motion = bone_motion(_tracks(TR_viseme_neutral=0.0), mapping)
    assert not motion.locations and not motion.rotations  # no track moves a posed unit
    # A track drives the rig through its recipe's units: TR_viseme_a opens the jaw by its jawOpen share.
    share = load_recipes().key_recipes()["TR_viseme_a"]["jawOpen"]
    motion = bone_motion(_tracks(TR_viseme_a=1.0), mapping)
    full = quaternions(turn[None])[0]
    np.testing.assert_allclose(motion.rotations["jaw"][1], _slerp_from_identity(full, share), atol=1e-12)
    np.testing.assert_allclose(motion.locations["jaw"][1], [0.0, 0.01 * share, 0.0])
    assert motion.driven == {"TR_viseme_a"}
    # Two tracks add, as their shape keys would.
    both = bone_motion(_tracks(TR_viseme_a=0.5, TR_viseme_bpa=0.5), mapping)
    bpa = load_recipes().key_recipes()["TR_viseme_bpa"]
    expected_z = 0.02 * 0.5 * bpa["mouthClose"]
    assert both.locations["jaw"][1][2] == pytest.approx(expected_z)


def test_a_pose_of_a_viseme_replaces_what_its_units_make_and_an_emotions_mouth_is_released():
    mapping = RigMapping(
        "m",
        "M",
        {
            "jawOpen": Pose({"jaw": BoneMove(rotation=(0.4, 0.0, 0.0))}),
            "TR_viseme_a": Pose({"jaw": BoneMove(rotation=(0.1, 0.0, 0.0))}),
            "TR_emotion_happy": Pose(
                {"jaw": BoneMove(rotation=(0.2, 0, 0)), "brow": BoneMove(location=(0, 1, 0))}
            ),
        },
    )
    motion = bone_motion(_tracks(TR_viseme_a=1.0), mapping)
    assert rotation_vectors(motion.rotations["jaw"][1:])[0] == pytest.approx((0.1, 0.0, 0.0))
    # The release takes back the emotion's mouth bones (those a viseme or mouth unit moves), not its brows.
    motion = bone_motion(_tracks(TR_emotion_happy=1.0, TR_emotion_happy_mouth_release=1.0), mapping)
    assert rotation_vectors(motion.rotations["jaw"][1:])[0] == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)
    assert motion.locations["brow"][1] == pytest.approx((0.0, 1.0, 0.0))


def test_moves_in_the_characters_frame_are_resolved_into_each_bones_axes():
    # A bone whose own y points forward and z down (a jaw bone along the chin, as Blender's bones run).
    axes = np.column_stack([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])  # columns in left, up, fwd
    moves = {"jawOpen": {"jaw": FrameMove(turn_degrees=(20.0, 0.0, 0.0), move=(0.0, 0.0, 0.5))}}
    pose = resolve_moves(moves, {"jaw": axes}, lambda _pair: 0.05, "test")["jawOpen"].bones["jaw"]
    assert pose.rotation == pytest.approx((np.radians(20), 0.0, 0.0))
    assert pose.location == pytest.approx((0.0, 0.025, 0.0))  # forward is along the bone, its y


def test_the_mappings_that_come_with_the_extension_load_and_mirror():
    names = {template.name for template in rig_templates()}
    assert names == {"jaw_bone", "rigify_face"}
    rigify = rig_template("rigify_face")
    assert set(rigify.poses) <= set(pose_targets())
    smile_left, smile_right = rigify.poses["mouthSmileLeft"], rigify.poses["mouthSmileRight"]
    assert set(smile_right) == {"lips.R"}
    assert smile_right["lips.R"].move == (-smile_left["lips.L"].move[0], *smile_left["lips.L"].move[1:])
    blink = rigify.poses["eyeBlinkRight"]["lid.T.R.002"]
    assert blink.length == ("lid.T.R.002", "lid.B.R.002")
    jaw = rig_template("jaw_bone")
    assert jaw.poses["jawLeft"]["jaw"].turn_degrees == (0.0, 4.0, 0.0)
    assert jaw.poses["jawRight"]["jaw"].turn_degrees == (0.0, -4.0, 0.0)
    with pytest.raises(HeadError, match="no face-rig mapping named 'nope'"):
        rig_template("nope")


@pytest.mark.parametrize(
    "text, problem",
    [
        (
            '[rig]\ntitle = "T"\n[poses.jawOpened]\njaw = { turn = [1, 0, 0] }\n',
            "jawOpened: not an ARKit unit",
        ),
        ('[rig]\ntitle = "T"\n[poses.jawOpen]\njaw = { turn = [1, 0] }\n', "turn must be three numbers"),
        ('[rig]\ntitle = "T"\n[poses.jawOpen]\njaw = { move = [0, 1, 0] }\n', "must give the length"),
        ('[rig]\ntitle = "T"\n[poses.jawOpen]\njaw = { spin = [1, 0, 0] }\n', "give turn, move, scale"),
        ('[rig]\ntitle = "T"\n[poses.jawOpen]\njaw = { turn = [900, 0, 0] }\n', "beyond"),
        ("[poses.jawOpen]\njaw = { turn = [1, 0, 0] }\n", "needs a \\[rig\\] table"),
    ],
)
def test_a_broken_mapping_file_names_itself_and_what_is_wrong(tmp_path, text, problem):
    path = tmp_path / "mine.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(DataError, match=problem) as error:
        read_rig_template(path)
    assert str(path) in str(error.value)


def test_a_characters_own_set_up_survives_being_stored_and_a_damaged_one_says_so():
    own = OwnRig(
        "jaw_bone",
        {"jaw": "Kiefer"},
        {"TR_viseme_a": Pose({"Kiefer": BoneMove(rotation=(0.3, 0, 0), properties={"lock": 0.5})}, "posed")},
    )
    assert own_rig_from_json(own_rig_to_json(own), "here") == own
    with pytest.raises(HeadError, match="kept in the armature 'Rig'.*damaged"):
        own_rig_from_json(
            '{"poses": {"jawOpen": {"bones": {"jaw": {"location": [1]}}}}}', "the armature 'Rig'"
        )
