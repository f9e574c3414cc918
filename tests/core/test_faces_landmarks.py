"""Landmarks found from geometry alone, on the reference head, a whole body and a low-poly face mask."""

from pathlib import Path

import numpy as np
import pytest

from lab.kit.heads_on_disk import HEADS, read_obj
from turkish_lipsync.core.base.errors import HeadError
from turkish_lipsync.core.faces.hidden import hidden_face_share
from turkish_lipsync.core.faces.landmark_fallbacks import landmarks_from_motion
from turkish_lipsync.core.faces.landmarks import (
    FACINGS,
    LANDMARK_NAMES,
    LID_LANDMARK_NAMES,
    face_frame,
    find_head_region,
    find_landmarks,
)
from turkish_lipsync.core.faces.reference import load_reference_head
from turkish_lipsync.core.faces.topology import connected_pieces, triangulate, triangulate_loops, unique_pairs

# Millimetres the found landmarks may lie from the reference's picked vertices (measured: the midline
# within 3 mm, the corners of mouth and eyes and the brows within 8 mm, their depth being the larger part).
MIDLINE_TOLERANCE_MM = 4.0
CORNER_TOLERANCE_MM = 10.0
MIDLINE = ("nose_tip", "upper_lip", "lower_lip", "upper_lip_inner", "lower_lip_inner", "chin")


def obj_or_skip(relative: str) -> Path:
    path = HEADS / relative
    if not path.exists():
        pytest.skip(f"{path} not present")
    return path


def assert_close_to_reference(found: dict, expected: dict, millimetres_per_unit: float) -> None:
    assert set(found) == set(LANDMARK_NAMES + LID_LANDMARK_NAMES)  # its eyeballs show: the lid margins too
    for name, point in expected.items():
        error = np.linalg.norm(found[name] - point) * millimetres_per_unit
        tolerance = MIDLINE_TOLERANCE_MM if name in MIDLINE else CORNER_TOLERANCE_MM
        assert error < tolerance, f"{name} is {error:.1f} mm from the reference's"


def test_reference_head_landmarks_match_its_known_vertices():
    head = load_reference_head()
    found = find_landmarks(head.vertices, head.polygons)
    assert_close_to_reference(found, head.landmarks, 1000.0)
    # Left is the character's left, +X; the face reads top to bottom.
    assert found["eye_outer_left"][0] > found["eye_inner_left"][0] > 0 > found["eye_inner_right"][0]
    assert found["mouth_corner_left"][0] > 0 > found["mouth_corner_right"][0]
    assert found["brow_left"][2] > found["eye_inner_left"][2] > found["nose_tip"][2]
    assert found["nose_tip"][2] > found["upper_lip"][2] > found["lower_lip"][2] > found["chin"][2]


def test_landmarks_follow_the_head_at_any_scale_and_place():
    head = load_reference_head()
    offset = np.array([12.0, -3.0, 150.0])
    in_centimetres = head.vertices * 100.0 + offset
    found = find_landmarks(in_centimetres, head.polygons)
    reference = find_landmarks(head.vertices, head.polygons)
    for name in LANDMARK_NAMES:
        np.testing.assert_allclose(found[name], reference[name] * 100.0 + offset, atol=0.05)  # 0.5 mm


def test_whole_body_in_decimetres_finds_the_head_on_top():
    vertices, polygons = read_obj(obj_or_skip("makehuman/base.obj"))
    region = find_head_region(vertices, polygons)
    body_height = np.ptp(vertices[:, 2])
    region_height = np.ptp(vertices[region, 2])
    assert 0.1 * body_height < region_height < 0.2 * body_height  # a head is about an eighth of a body
    assert vertices[region, 2].max() == vertices[:, 2].max()
    found = find_landmarks(vertices, polygons)
    # The body is the reference's own source mesh, in decimetres.
    in_metres = {name: point * 0.1 for name, point in found.items()}
    assert_close_to_reference(in_metres, load_reference_head().landmarks, 1000.0)


def test_head_alone_is_its_own_head_region():
    head = load_reference_head()
    region = find_head_region(head.vertices, head.polygons)
    assert len(region) == len(head.vertices)


def test_mediapipe_face_mask_landmarks_land_on_its_known_vertices():
    vertices, polygons = read_obj(obj_or_skip("mediapipe/canonical_face_model.obj"))
    found = find_landmarks(vertices, polygons)
    known = {
        "nose_tip": 4,
        "upper_lip_inner": 13,
        "lower_lip_inner": 14,
        "mouth_corner_right": 61,
        "mouth_corner_left": 291,
        "eye_inner_right": 133,
        "eye_outer_right": 33,
        "eye_inner_left": 362,
        "eye_outer_left": 263,
    }
    # Centimetres on a 17.6 cm mask; measured 0.02 (nose), 0.06 and 0.52 (inner lips: the mask closes the
    # mouth with a sloping strip whose lower edge the front view cannot see), 0.36 (mouth corners), 0.35
    # to 0.25 (eye corners: its eyes are closed and smooth, so they come from the face's proportions).
    tolerance = {"nose_tip": 0.2, "upper_lip_inner": 0.3, "lower_lip_inner": 0.7}
    for name, index in known.items():
        error = np.linalg.norm(found[name] - vertices[index])
        assert error < tolerance.get(name, 0.5), f"{name} is {error:.2f} cm from vertex {index}"
    assert found["eye_inner_left"][0] > 0 > found["eye_inner_right"][0]
    assert found["brow_left"][2] > found["eye_inner_left"][2] > found["nose_tip"][2] > found["chin"][2]


def icosphere(subdivisions: int) -> tuple[np.ndarray, np.ndarray]:
    """A unit sphere: a closed surface with no face on it."""
    t = (1 + 5**0.5) / 2
    vertices = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t]]
    vertices += [[0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    faces = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2]]
    faces += [[10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5]]
    faces += [[2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    points = [np.array(v, float) / np.linalg.norm(v) for v in vertices]
    for _ in range(subdivisions):
        middle: dict[tuple[int, int], int] = {}
        refined = []
        for a, b, c in faces:
            corners = []
            for first, second in ((a, b), (b, c), (c, a)):
                key = (min(first, second), max(first, second))
                if key not in middle:
                    point = points[first] + points[second]
                    points.append(point / np.linalg.norm(point))
                    middle[key] = len(points) - 1
                corners.append(middle[key])
            ab, bc, ca = corners
            refined += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        faces = refined
    return np.array(points), np.array(faces)


def test_a_ball_is_refused_as_a_head_with_a_reason():
    vertices, faces = icosphere(3)
    with pytest.raises(HeadError, match="mouth|eye"):
        find_landmarks(vertices * 0.1, faces)


def test_a_bigger_piece_without_a_face_does_not_hide_the_head():
    """A hair cap or helmet with more vertices than the skin: the face is still found on the skin."""
    head = load_reference_head()
    ball, ball_faces = icosphere(5)
    assert len(ball) > len(head.parts["skin"])
    vertices = np.concatenate((head.vertices, ball * 0.12 + [0.0, 0.05, 0.8]))
    polygons = [list(quad) for quad in head.polygons] + [
        list(face + len(head.vertices)) for face in ball_faces
    ]
    found = find_landmarks(vertices, polygons)
    alone = find_landmarks(head.vertices, head.polygons)
    for name in LANDMARK_NAMES:
        np.testing.assert_allclose(found[name], alone[name], atol=1e-9)


def test_a_mesh_without_faces_is_refused():
    with pytest.raises(HeadError, match="no faces"):
        find_landmarks(np.random.default_rng(0).random((50, 3)), [])


def test_polygons_of_any_size_become_triangles_and_pieces():
    quads_and_pentagon = [[0, 1, 2, 3], [4, 5, 6, 7, 8]]
    triangles = triangulate(quads_and_pentagon)
    assert triangles.tolist() == [[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7], [4, 7, 8]]
    loops = triangulate_loops(np.arange(9), np.array([0, 4]), np.array([4, 5]))
    assert np.array_equal(loops, triangles)
    labels = connected_pieces(10, triangles)
    assert len(set(labels[:4])) == 1 and len(set(labels[4:9])) == 1 and labels[0] != labels[4]
    assert labels[9] not in labels[:9]  # a loose vertex is a piece of its own


@pytest.mark.parametrize("facing", [name for name, _ in FACINGS])
def test_a_head_looking_elsewhere_is_turned_and_found(facing):
    """Looking toward +Y (a VRM 0.x avatar), sideways, or lying on its back or face."""
    head = load_reference_head()
    turn = dict(FACINGS)[facing]
    upright = find_landmarks(head.vertices, head.polygons)
    found = find_landmarks(head.vertices @ turn, head.polygons)  # the inverse turn: looks toward `facing`
    for name in LANDMARK_NAMES:
        np.testing.assert_allclose(found[name] @ turn.T, upright[name], atol=1e-9)
    # The face's own frame undoes the turn: it maps the turned landmarks back upright.
    _, axes = face_frame(found)
    _, expected_axes = face_frame(upright)
    np.testing.assert_allclose(turn @ axes, expected_axes, atol=1e-9)


def test_landmarks_from_what_the_heads_own_keys_move():
    """A head whose mouth shows only when a key opens it: the mouth and eyes are where its keys move."""
    head = load_reference_head()
    turn = dict(FACINGS)["+Y"]
    vertices = head.vertices @ turn
    found = landmarks_from_motion(
        vertices,
        head.polygons,
        head.units["jawOpen"] @ turn,
        head.units["eyeBlinkLeft"] @ turn,
        head.units["eyeBlinkRight"] @ turn,
    )
    upright = {name: point @ turn.T for name, point in found.items()}
    expected = find_landmarks(head.vertices, head.polygons)
    # A rough placing, for faces whose shape tells nothing: the character's left stays its left (+X
    # upright), the order from brows to chin holds, the eyes land within 16 mm of the shape's (measured
    # 10 to 14: a blink moves the lids beyond the corners). A jaw moves the cheeks too, so the mouth's
    # corners come out wide (measured 3 cm): painted mouths open with keys that move the lips alone.
    assert upright["mouth_corner_left"][0] > 0 > upright["mouth_corner_right"][0]
    assert upright["eye_outer_left"][0] > upright["eye_inner_left"][0] > 0
    for name in ("eye_inner_left", "eye_outer_left", "eye_inner_right", "eye_outer_right"):
        assert np.linalg.norm(upright[name] - expected[name]) < 0.016, name
    heights = [upright[name][2] for name in ("brow_left", "eye_inner_left", "nose_tip", "upper_lip", "chin")]
    assert np.all(np.diff(heights) < 0)


def test_a_key_that_moves_nothing_gives_no_landmarks():
    head = load_reference_head()
    with pytest.raises(HeadError, match="moves nothing"):
        landmarks_from_motion(head.vertices, head.polygons, np.zeros_like(head.vertices))


def test_a_sheet_over_the_face_hides_it_and_eyes_and_lashes_do_not():
    """hidden_face_share: the reference with its eyes, teeth and lashes in one mesh shows its face; a
    sheet of the same mesh hung a little in front of it hides nearly all of it."""
    reference = load_reference_head()
    vertices = np.asarray(reference.vertices, np.float64)
    polygons = np.asarray(reference.polygons)
    landmarks = find_landmarks(vertices, polygons)
    assert hidden_face_share(vertices, polygons, landmarks) < 0.1
    skin = vertices[reference.parts["skin"]]
    front = skin[:, 1].min() - 0.01  # a centimetre in front of the nose tip
    low, high = skin[:, [0, 2]].min(0), skin[:, [0, 2]].max(0)
    sheet = np.array(
        [
            [low[0], front, low[1]],
            [high[0], front, low[1]],
            [high[0], front, high[1]],
            [low[0], front, high[1]],
        ]
    )
    covered = np.concatenate((vertices, sheet))
    quads = np.concatenate((polygons, [np.arange(4) + len(vertices)]))
    assert hidden_face_share(covered, quads, landmarks) > 0.95


def test_unique_pairs_are_numpys_unique_rows():
    rows = np.random.default_rng(7).integers(0, 40, (500, 2))
    np.testing.assert_array_equal(unique_pairs(rows), np.unique(rows, axis=0))
    assert unique_pairs(np.zeros((0, 2), np.int64)).shape == (0, 2)


def test_a_heap_of_random_triangles_is_refused_quickly_in_bounded_memory():
    """3,000 vertices in 4,000 random triangles once made a depth map reach 13.2 GB: its triangles' boxes
    cover the front view hundreds of times over, which no head's surface does (measured: refused at a
    peak of 19 MB)."""
    import tracemalloc

    random = np.random.default_rng(0)
    vertices = random.random((3000, 3))
    triangles = random.integers(0, 3000, (4000, 3))
    tracemalloc.start()
    try:
        with pytest.raises(HeadError, match="times over: that is no head's surface"):
            find_landmarks(vertices, triangles)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 300e6
