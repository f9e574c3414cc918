"""Test faces made from the reference head: subdivided finer and bent into other faces (the truth is the
reference's own units subdivided and bent alike).
"""

from __future__ import annotations

import numpy as np

from turkish_lipsync.core.faces.landmarks import axis_rotation


def reshape_face(points: np.ndarray, landmarks, bends: dict[str, float]) -> np.ndarray:
    """points (on the reference, metres) bent into another face; landmarks: the reference's."""
    points = np.asarray(points, np.float64)
    mouth_z = 0.5 * (landmarks["upper_lip"][2] + landmarks["lower_lip"][2])
    eye = 0.5 * (landmarks["eye_inner_left"] + landmarks["eye_outer_left"])
    nose_tip, chin, brow_z = landmarks["nose_tip"], landmarks["chin"], landmarks["brow_left"][2]
    x, y, z = points.T
    out = points.copy()
    out[:, 0] *= 1 + bends.get("jaw", 0.0) * np.clip((mouth_z + 0.02 - z) / 0.06, 0, 1)
    out[:, 2] -= bends.get("chin", 0.0) * np.clip((mouth_z - z) / 0.04, 0, 1)
    nose = np.linalg.norm(points - nose_tip, axis=1)
    out[:, 1] -= bends.get("nose", 0.0) * np.exp(-((nose / 0.02) ** 2))
    for lip in ("upper_lip", "lower_lip"):  # each lip fuller on its own: the crease between them stays
        centre = [0.0, landmarks[lip][1], landmarks[lip][2]]
        lips = np.linalg.norm((points - centre) * [1.0, 1.0, 3.0], axis=1)
        out[:, 1] -= bends.get("lips", 0.0) * np.exp(-((lips / 0.02) ** 2))
    around_eye = ((np.abs(x) - abs(eye[0])) ** 2 + (z - eye[2]) ** 2) / 0.025**2
    out[:, 0] += bends.get("eyes", 0.0) * np.sign(x) * np.exp(-around_eye)
    out[:, 1] += bends.get("forehead", 0.0) * np.clip((z - eye[2] - 0.03) / 0.05, 0, 1)
    middle = np.exp(-((x / 0.05) ** 2)) * np.clip((z - chin[2]) / 0.1, 0, 1)
    out[:, 1] -= bends.get("midface", 0.0) * middle * np.clip((brow_z + 0.02 - z) / 0.03, 0, 1)
    out[:, 2] = nose_tip[2] + (out[:, 2] - nose_tip[2]) * bends.get("tall", 1.0)
    turn = tilt(bends)
    return ((out - nose_tip) @ turn.T + nose_tip) * bends.get("size", 1.0)


def subdivide_quads(vertices: np.ndarray, quads: np.ndarray, cuts: int) -> tuple[np.ndarray, np.ndarray]:
    """Each quad split bilinearly into cuts x cuts quads; points on shared edges are merged."""
    steps = np.linspace(0.0, 1.0, cuts + 1)
    u, v = np.meshgrid(steps, steps, indexing="ij")
    a, b, c, d = (vertices[quads[:, i]][:, None, None, :] for i in range(4))
    u, v = u[None, :, :, None], v[None, :, :, None]
    grid = (1 - u) * (1 - v) * a + u * (1 - v) * b + u * v * c + (1 - u) * v * d  # (F, n+1, n+1, 3)
    points = grid.reshape(-1, 3)
    _, first, index = np.unique(np.round(points, 9), axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first)  # keep the original vertex order stable for readability
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    new_vertices = points[first[order]]
    index = rank[index.ravel()].reshape(len(quads), cuts + 1, cuts + 1)
    i, j = np.meshgrid(np.arange(cuts), np.arange(cuts), indexing="ij")
    new_quads = np.stack(
        (index[:, i, j], index[:, i + 1, j], index[:, i + 1, j + 1], index[:, i, j + 1]), axis=-1
    ).reshape(-1, 4)
    return new_vertices, new_quads


def tilt(bends: dict[str, float]) -> np.ndarray:
    """The rotation of the bends' roll, nod and turn (degrees; none when absent)."""
    turn = np.eye(3)
    for axis, name in ((1, "roll"), (0, "nod"), (2, "turn")):
        turn = axis_rotation(axis, bends.get(name, 0.0)) @ turn
    return turn
