"""Landmarks where a head's shape shows no face: read off what its own keys move, or laid out in a box as a
start for markers the user then moves."""

from __future__ import annotations

import numpy as np

from ..base.errors import HeadError
from .landmarks import check_proportions
from .topology import triangulate


def landmarks_from_motion(
    vertices: np.ndarray,
    polygons,
    mouth_open: np.ndarray,
    blink_left: np.ndarray | None = None,
    blink_right: np.ndarray | None = None,
) -> dict[str, np.ndarray]:
    """Landmarks read off what a head's own keys move, for faces whose shape shows no mouth or eyes
    (a mouth painted on the texture that only a key opens, stylised eyes).

    mouth_open: deltas of a key that opens the mouth; blink_*: of the blinks (the eyes are placed by the
    face's usual proportions without them). The face looks where the mouth lies from the head's centre.
    """
    vertices = np.asarray(vertices, np.float64)
    triangles = triangulate(polygons)
    mouth = _moved(mouth_open)
    if len(mouth) < 2:
        raise HeadError("The mouth-opening key moves nothing; place the landmark markers instead.")
    centre = vertices[np.unique(triangles)].mean(0)
    mouth_centre = vertices[mouth].mean(0)
    forward = np.array([mouth_centre[0] - centre[0], mouth_centre[1] - centre[1], 0.0])
    if np.linalg.norm(forward) == 0:
        raise HeadError("The mouth lies at the head's centre; place the landmark markers instead.")
    forward /= np.linalg.norm(forward)
    # A turn about Z taking forward to -Y; upright = points @ turn.T.
    turn = np.array([[-forward[1], forward[0], 0.0], [-forward[0], -forward[1], 0.0], [0.0, 0.0, 1.0]])
    upright = vertices @ turn.T
    points = _mouth_from_motion(upright, mouth, mouth_open @ turn.T)
    width = float(np.linalg.norm(points["mouth_corner_left"] - points["mouth_corner_right"]))
    for side, blink in (("left", blink_left), ("right", blink_right)):
        points.update(_eye_from_motion(upright, side, blink, points, width))
    points["nose_tip"] = _front_point(
        upright, points, 0.5 * (points["eye_inner_left"][2] + points["upper_lip"][2])
    )
    # The chin: the lowest point on the midline below the mouth, in front of the head's middle.
    below = np.abs(upright[:, 0] - points["upper_lip"][0]) < 0.15 * width
    below &= (upright[:, 1] < points["upper_lip"][1] + 1.5 * width) & (upright[:, 2] < points["lower_lip"][2])
    if not below.any():
        raise HeadError("No chin found below the mouth the key opens; place the landmark markers instead.")
    points["chin"] = upright[below][np.argmin(upright[below, 2])]
    check_proportions(points, widths=False)  # stylised faces: big eyes over a small mouth
    return {name: point @ turn for name, point in points.items()}


def _moved(deltas: np.ndarray | None) -> np.ndarray:
    if deltas is None:
        return np.empty(0, np.int64)
    size = np.linalg.norm(np.asarray(deltas, np.float64), axis=1)
    return np.flatnonzero(size > 0.2 * size.max()) if size.max() > 0 else np.empty(0, np.int64)


def _mouth_from_motion(upright: np.ndarray, mouth: np.ndarray, deltas: np.ndarray) -> dict[str, np.ndarray]:
    """Corners at the sides of what the key moves; the lips above and below the middle of the line."""
    moved = upright[mouth]
    left, right = moved[np.argmax(moved[:, 0])], moved[np.argmin(moved[:, 0])]
    middle_x = 0.5 * (left[0] + right[0])
    width = float(left[0] - right[0])
    seam = 0.5 * (left[2] + right[2])
    front = upright[np.abs(upright[:, 2] - seam) < 0.2 * width]
    front = front[np.abs(front[:, 0] - middle_x) < 0.2 * width]
    front_y = float(front[:, 1].min()) if len(front) else float(moved[:, 1].min())
    lowered = deltas[mouth, 2] < 0
    lip = 0.15 * width
    upper_z = max(seam + lip, float(moved[~lowered, 2].max()) if (~lowered).any() else seam + lip)
    lower_z = min(seam - lip, float(moved[lowered, 2].min()) if lowered.any() else seam - lip)
    return {
        "upper_lip": np.array([middle_x, front_y, upper_z]),
        "lower_lip": np.array([middle_x, front_y, lower_z]),
        "upper_lip_inner": np.array([middle_x, front_y, seam]),
        "lower_lip_inner": np.array([middle_x, front_y, seam]),
        "mouth_corner_left": left,
        "mouth_corner_right": right,
    }


def _eye_from_motion(upright, side, blink, mouth_points, mouth_width) -> dict[str, np.ndarray]:
    """An eye's corners at the sides of what its blink moves, or where faces put eyes without one."""
    direction = 1 if side == "left" else -1
    middle_x = mouth_points["upper_lip"][0]
    moved = _moved(None if blink is None else blink @ np.eye(3))
    if len(moved) >= 2:
        points = upright[moved]
        inner = points[np.argmin(np.abs(points[:, 0] - middle_x))]
        outer = points[np.argmax(np.abs(points[:, 0] - middle_x))]
        height = float(np.median(points[:, 2]))
        inner, outer = inner.copy(), outer.copy()
        inner[2] = outer[2] = height
    else:
        height = mouth_points["upper_lip"][2] + 1.3 * mouth_width
        inner = _front_point(upright, mouth_points, height, middle_x + direction * 0.35 * mouth_width)
        outer = _front_point(upright, mouth_points, height, middle_x + direction * 1.2 * mouth_width)
    eye_width = float(abs(outer[0] - inner[0]))
    brow = _front_point(upright, mouth_points, inner[2] + 0.6 * eye_width, 0.5 * (inner[0] + outer[0]))
    return {f"eye_inner_{side}": inner, f"eye_outer_{side}": outer, f"brow_{side}": brow}


def _front_point(upright, mouth_points, height, x=None) -> np.ndarray:
    """The most forward vertex near (x, height): the face's surface there."""
    x = mouth_points["upper_lip"][0] if x is None else x
    width = float(np.linalg.norm(mouth_points["mouth_corner_left"] - mouth_points["mouth_corner_right"]))
    near = np.hypot(upright[:, 0] - x, upright[:, 2] - height) < 0.25 * width
    if not near.any():
        near = (
            np.hypot(upright[:, 0] - x, upright[:, 2] - height)
            <= np.hypot(upright[:, 0] - x, upright[:, 2] - height).min()
        )
    candidates = upright[near]
    return candidates[np.argmin(candidates[:, 1])].copy()


def landmark_layout_in_box(
    reference_landmarks: dict[str, np.ndarray],
    reference_skin: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
) -> dict[str, np.ndarray]:
    """The reference's landmarks scaled into a box, on its -Y face: a start for markers a user then moves.

    Used where no face can be found on a head, so the markers workflow has something to move.
    """
    low, high = reference_skin.min(axis=0), reference_skin.max(axis=0)
    lower, upper = np.asarray(lower, np.float64), np.asarray(upper, np.float64)
    scale = float(np.min((upper - lower)[[0, 2]] / np.maximum((high - low)[[0, 2]], 1e-12)))
    centre = (lower + upper) / 2
    reference_centre = (low + high) / 2
    layout = {}
    for name, point in reference_landmarks.items():
        placed = centre + (np.asarray(point, np.float64) - reference_centre) * scale
        placed[1] = lower[1] + (point[1] - low[1]) * scale  # the face's depth from the box's front
        layout[name] = placed
    return layout
