"""The parts of a head beside its skin: teeth, tongue, eyes and lashes, found from the mesh's pieces."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .landmarks import face_frame
from .topology import connected_pieces, largest_piece, triangulate


def find_parts(vertices: np.ndarray, polygons, landmarks: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Teeth, tongue and eyes of a head, as vertex indices, from its separate pieces and where they sit.

    Material and object names differ from head to head; geometry does not: a piece inside the mouth
    that reaches forward to the lips is a row of teeth (upper above the lip line, lower below), one
    further back is the tongue; pieces behind each eye's corners are that eye (eyeball, iris, cornea).
    Parts a head lacks are left out. Read in the face's own frame, so a head looking elsewhere than -Y
    is judged the same.
    """
    origin, axes = face_frame(landmarks)
    vertices = (np.asarray(vertices, np.float64) - origin) @ axes
    landmarks = {name: (np.asarray(point, np.float64) - origin) @ axes for name, point in landmarks.items()}
    triangles = triangulate(polygons)
    labels = connected_pieces(len(vertices), triangles)
    skin = set(labels[largest_piece(len(vertices), triangles)].tolist())
    used = np.zeros(len(vertices), bool)
    used[triangles.ravel()] = True
    pieces = [
        np.flatnonzero((labels == label) & used) for label in np.unique(labels[used]) if label not in skin
    ]
    lm = {name: np.asarray(point, np.float64) for name, point in landmarks.items()}
    corner_left, corner_right = lm["mouth_corner_left"], lm["mouth_corner_right"]
    mouth_width = float(np.linalg.norm(corner_left - corner_right))
    lip_line = 0.5 * (lm["upper_lip_inner"][2] + lm["lower_lip_inner"][2])
    lips_front = min(lm["upper_lip"][1], lm["lower_lip"][1])
    mouth_centre_x = 0.5 * (corner_left[0] + corner_right[0])
    parts: dict[str, list[np.ndarray]] = {name: [] for name in ("upper_teeth", "lower_teeth", "tongue")}
    parts.update(left_eye=[], right_eye=[], left_eyelashes=[], right_eyelashes=[])
    eyes = {
        side: (
            0.5 * (lm[f"eye_inner_{side}"] + lm[f"eye_outer_{side}"]),
            float(np.linalg.norm(lm[f"eye_inner_{side}"] - lm[f"eye_outer_{side}"])),
        )
        for side in ("left", "right")
    }
    teeth, loose = [], []
    for piece in pieces:
        points = vertices[piece]
        centre = points.mean(0)
        for side, (eye_centre, eye_width) in eyes.items():
            offset = centre - eye_centre
            sideways = np.hypot(offset[0], offset[2])
            # An eyeball's centre lies well behind the corners; lashes and lids hang in front of it.
            if sideways < 0.6 * eye_width and (
                0.15 * eye_width < offset[1] < 1.2 * eye_width
                or (_is_ball(points, eye_width) and -0.3 * eye_width < offset[1] < 1.2 * eye_width)
            ):
                parts[f"{side}_eye"].append(piece)
                break
            if sideways < 0.8 * eye_width and -0.6 * eye_width < offset[1] <= 0.15 * eye_width:
                loose.append((side, piece))  # lashes, or a cornea in front of the eyeball
                break
        else:
            inside_mouth = (
                abs(centre[0] - mouth_centre_x) < 0.6 * mouth_width
                and abs(centre[2] - lip_line) < 0.6 * mouth_width
                and centre[1] > lips_front
                and centre[1] - lips_front < 1.5 * mouth_width
            )
            if not inside_mouth:
                continue
            if points[:, 1].min() - lips_front < 0.3 * mouth_width:
                teeth.append(piece)
            else:
                parts["tongue"].append(piece)
    for side, piece in loose:
        # A cornea lies on its eyeball; lashes stand out of it, along the lid.
        eyeball = np.concatenate(parts[f"{side}_eye"]) if parts[f"{side}_eye"] else np.empty(0, np.int64)
        if len(eyeball):
            centre = vertices[eyeball].mean(0)
            radius = np.linalg.norm(vertices[eyeball] - centre, axis=1).max()
            if np.linalg.norm(vertices[piece] - centre, axis=1).max() < 1.15 * radius:
                parts[f"{side}_eye"].append(piece)
                continue
        parts[f"{side}_eyelashes"].append(piece)
    if len(teeth) == 1 and 0.25 < (vertices[teeth[0], 2] >= lip_line).mean() < 0.75:
        above = vertices[teeth[0], 2] >= lip_line  # both rows in one piece: split it at the lip line
        parts["upper_teeth"].append(teeth[0][above])
        parts["lower_teeth"].append(teeth[0][~above])
    else:
        for piece in teeth:
            row = "upper_teeth" if vertices[piece, 2].mean() >= lip_line else "lower_teeth"
            parts[row].append(piece)
    return {name: np.sort(np.concatenate(found)) for name, found in parts.items() if found}


def _is_ball(points: np.ndarray, eye_width: float) -> bool:
    """A closed, round piece about an eye wide: an eyeball, wherever its centre sits."""
    radius = np.linalg.norm(points - points.mean(0), axis=1)
    return bool(radius.std() < 0.15 * radius.mean() and 0.25 * eye_width < radius.mean() < 0.8 * eye_width)


# ---------------------------------------------------------------- the transfer


def split_eyes(parts: dict, vertices: np.ndarray, landmarks: Mapping[str, np.ndarray]) -> dict:
    """Accept both eyes as one part ("eyes") and split them at the nose: left is +X."""
    eyes = parts.pop("eyes", None)
    if eyes is not None and len(eyes):
        eyes = np.asarray(eyes)
        middle = np.asarray(landmarks["nose_tip"])[0] if "nose_tip" in landmarks else vertices[eyes, 0].mean()
        left = vertices[eyes, 0] >= middle
        parts.setdefault("left_eye", eyes[left])
        parts.setdefault("right_eye", eyes[~left])
    return parts
