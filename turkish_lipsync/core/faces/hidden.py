"""How much of a face other pieces of its mesh hide (hair and clothing helpers, a beard, lashes)."""

from __future__ import annotations

import numpy as np

from .depth import DepthMap
from .landmarks import face_frame
from .topology import connected_pieces, round_triangles, triangulate

# piece hides the skin where it stands this share of that height in front of it.
HIDDEN_FACE_ROWS = 120
HIDDEN_FACE_GAP = 0.01


def hidden_face_share(vertices: np.ndarray, polygons, landmarks) -> float:
    """The share of the face (between the outer eye corners, from the brows to the chin, seen from the
    front) that other pieces of the same mesh hide: pieces standing in front of the skin there, eyeballs
    aside. MakeHuman's raw base mesh keeps its hair and clothing helpers over the face; a beard or lashes
    hide a little of it."""
    names = ("nose_tip", "chin", "eye_outer_left", "eye_outer_right", "brow_left", "brow_right")
    framing = ("mouth_corner_left", "mouth_corner_right", "eye_inner_left", "eye_inner_right")  # face_frame
    if not all(name in landmarks for name in names + framing):
        return 0.0
    origin, axes = face_frame(landmarks)
    upright = (np.asarray(vertices, np.float64) - origin) @ axes
    marks = {name: (np.asarray(landmarks[name], np.float64) - origin) @ axes for name in names}
    triangles = triangulate(polygons)
    labels = connected_pieces(len(upright), triangles)
    skin_label = labels[np.argmin(np.linalg.norm(upright - marks["nose_tip"], axis=1))]
    on_skin = labels[triangles[:, 0]] == skin_label
    if on_skin.all():
        return 0.0
    height = float(np.mean([marks["brow_left"][2], marks["brow_right"][2]]) - marks["chin"][2])
    if height <= 0:
        return 0.0
    # Only what lies over the face, from the right eye's outer corner to the left's, chin to brows.
    low = np.array([marks["eye_outer_right"][0], marks["chin"][2]])
    high = np.array([marks["eye_outer_left"][0], marks["chin"][2] + height])
    corners = upright[triangles][:, :, [0, 2]]
    over = np.all(corners.max(1) >= low, axis=1) & np.all(corners.min(1) <= high, axis=1)
    others = triangles[over & ~on_skin]
    others = others[~round_triangles(upright, others)]
    if len(others) == 0 or not np.any(over & on_skin):
        return 0.0
    skin = DepthMap(upright, triangles[over & on_skin], height / HIDDEN_FACE_ROWS)
    cover = DepthMap(upright, others, skin.pixel, like=skin)
    rows = slice(max(skin.row_of(high[1]), 0), skin.row_of(low[1]) + 1)
    columns = slice(max(skin.column_of(low[0]), 0), skin.column_of(high[0]) + 1)
    front, hiding = skin.front[rows, columns], cover.front[rows, columns]
    face = np.isfinite(front)
    if not face.any():
        return 0.0
    hidden = face & np.isfinite(hiding) & (hiding > front + HIDDEN_FACE_GAP * height)
    return float(hidden.sum() / face.sum())
