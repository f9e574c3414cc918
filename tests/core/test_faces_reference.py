"""The reference head from its generated data file: metres, Blender axes, parts, units, landmarks, look."""

import importlib.metadata

import numpy as np
import pytest

from turkish_lipsync.core.base.errors import DataError
from turkish_lipsync.core.faces import reference, reference_build
from turkish_lipsync.core.faces.arkit_names import ARKIT_UNITS
from turkish_lipsync.core.faces.landmarks import find_landmarks
from turkish_lipsync.core.faces.measure import edge_stretch
from turkish_lipsync.core.faces.parts import PART_LABELS, find_face_parts, opening_gap
from turkish_lipsync.core.faces.reference import load_reference_head
from turkish_lipsync.core.faces.topology import edge_graph, triangulate


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


def test_blinks_close_the_lids_without_tearing_the_fold():
    """faceunits01's blinks grew the upper lid's fold edges 4.7 times (p99.9 4.1); the reference smooths the
    fold's motion, so a blink keeps under the ceiling of 4 and the lids close as far as before."""
    head = load_reference_head()
    vertices = np.asarray(head.vertices, np.float64)
    edges, _ = edge_graph(len(vertices), triangulate(head.polygons), vertices)
    landmarks = find_landmarks(head.vertices, head.polygons)
    skin = np.asarray(head.parts["skin"])
    face = find_face_parts(vertices, triangulate(head.polygons), skin, landmarks)
    for side in ("left", "right"):
        blink = np.asarray(head.units[f"eyeBlink{side.title()}"], np.float64)
        assert edge_stretch(vertices, edges, blink) < 4.0  # measured 3.35 (4.13 unsmoothed)
        lids = [
            np.flatnonzero(face.seen & (face.label == PART_LABELS.index(f"{lid}_lid_{side}")))
            for lid in ("upper", "lower")
        ]
        middle = (landmarks[f"eye_inner_{side}"][0] + landmarks[f"eye_outer_{side}"][0]) / 2
        assert opening_gap(vertices, np.zeros_like(vertices), *lids, middle) > 0.006  # 7.8 mm open
        assert opening_gap(vertices, blink, *lids, middle) < -0.003  # closed, lids overlapping 3.3 mm


def test_the_head_is_cut_along_one_closed_neck_loop():
    """The only open edges of the skin are the neck loop's: an even rim, no ragged faces."""
    head = load_reference_head()
    skin = set(head.parts["skin"].tolist())
    quads = head.polygons[np.isin(head.polygons, list(skin)).all(axis=1)]
    edges = np.sort(np.stack([quads, np.roll(quads, -1, axis=1)], axis=2).reshape(-1, 2), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    open_edges = {tuple(edge) for edge in unique[counts == 1].tolist()}
    loop = head.neck_loop.tolist()
    assert open_edges == {tuple(sorted(pair)) for pair in zip(loop, loop[1:] + loop[:1], strict=True)}
    rim = head.vertices[head.neck_loop]
    assert rim[:, 2].max() < head.landmarks["chin"][2] - 0.01  # below the chin all round


def test_painted_hair_covers_the_scalp_and_spares_the_face():
    head = load_reference_head()
    skin = head.parts["skin"]
    crown = skin[head.vertices[skin, 2].argmax()]
    assert head.hair[crown] == 1.0
    for landmark in ("nose_tip", "brow_left", "eye_outer_right", "chin", "upper_lip"):
        assert head.hair[head.landmark_vertices[landmark]] == 0.0, landmark
    assert head.hair[np.setdiff1d(np.arange(len(head.vertices)), skin)].max() == 0.0


def _copy_head_data(target_folder, fingerprint=None):
    """The head data this process read, copied (optionally with another fingerprint) into a folder."""
    head = load_reference_head()
    target_folder.mkdir(parents=True)
    with np.load(head.source) as stored:
        arrays = {name: stored[name] for name in stored.files}
    if fingerprint is not None:
        arrays["fingerprint"] = np.array(fingerprint)
    return reference_build.write_head_data(target_folder / reference.HEAD_DATA_NAME, arrays)


def test_head_data_comes_from_the_extension_then_the_build_folder(tmp_path, monkeypatch):
    bundled = _copy_head_data(tmp_path / "head_data")
    built = _copy_head_data(tmp_path / "build" / "head_data")
    monkeypatch.setattr(reference, "BUNDLED_HEAD_DATA", bundled.parent)
    monkeypatch.setattr(reference, "BUILT_HEAD_DATA", built.parent)
    settings = reference_build.read_settings()
    arrays, source = reference._head_arrays(settings)
    assert source == bundled and len(arrays["vertices"]) == len(load_reference_head().vertices)
    bundled.unlink()
    assert reference._head_arrays(settings)[1] == built


def test_stale_head_data_is_skipped_in_a_checkout_and_refused_in_the_extension(tmp_path, monkeypatch):
    settings = reference_build.read_settings()
    built = _copy_head_data(tmp_path / "build" / "head_data", fingerprint="stale")
    cache = tmp_path / "cache" / "turkish_lipsync"
    cached = _copy_head_data(cache)
    fingerprint, version = reference_build.settings_fingerprint(settings), importlib.metadata.version("anny")
    cached = cached.rename(cache / f"reference_head_{fingerprint}_{version}.npz")
    monkeypatch.setattr(reference, "BUNDLED_HEAD_DATA", tmp_path / "head_data")
    monkeypatch.setattr(reference, "BUILT_HEAD_DATA", built.parent)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    assert reference._head_arrays(settings)[1] == cached  # the stale build file is passed over
    _copy_head_data(tmp_path / "head_data", fingerprint="stale")
    with pytest.raises(DataError, match="reinstall the extension"):
        reference._head_arrays(settings)
