"""Figures that tell a good face shape from a broken one, computed from the arrays alone.

A transferred key can look plausible in numbers and still pull a curtain of stretched faces across the
mouth, so every key is judged by how much it stretches the mesh's edges, how far the lips and lids part
at the middle, how symmetric it is, and (where an artist made the same shape) how closely its
displacement field points the artist's way.
"""

from __future__ import annotations

import numpy as np

from .landmarks import face_frame, triangulate
from .parts import PART_LABELS, find_face_parts, opening_gap
from .transfer import find_parts


def mesh_edges(polygons) -> np.ndarray:
    """(E, 2) unique vertex pairs of the triangles' edges."""
    triangles = triangulate(polygons)
    edges = np.concatenate((triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]))
    return np.unique(np.sort(edges, axis=1), axis=0)


def edge_stretch(vertices: np.ndarray, edges: np.ndarray, deltas: np.ndarray, percentile: float = 99.9):
    """The given percentile of deformed / rest edge length over the edges the key moves at all."""
    rest = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1)
    moved = vertices + deltas
    deformed = np.linalg.norm(moved[edges[:, 0]] - moved[edges[:, 1]], axis=1)
    touched = (np.abs(deltas[edges[:, 0]]).sum(1) + np.abs(deltas[edges[:, 1]]).sum(1) > 0) & (rest > 0)
    if not touched.any():
        return 1.0
    return float(np.percentile(deformed[touched] / rest[touched], percentile))


def displacement_cosine(first: np.ndarray, second: np.ndarray) -> float:
    """Cosine between two displacement fields on the same vertices (1: the same direction everywhere)."""
    first = np.asarray(first, np.float64).ravel()
    second = np.asarray(second, np.float64).ravel()
    norm = np.linalg.norm(first) * np.linalg.norm(second)
    return float(first @ second / norm) if norm > 0 else 0.0


def symmetry(vertices: np.ndarray, deltas: np.ndarray, middle_x: float) -> float:
    """1 minus the relative difference between the key and its mirror image across x = middle_x.

    A key meant to be symmetric (jawOpen, a viseme) scores near 1; a one-sided key (a blink) near 0.
    """
    moved = np.flatnonzero(np.linalg.norm(deltas, axis=1) > 1e-3 * np.abs(deltas).max(initial=0.0))
    if len(moved) == 0:
        return 1.0
    mirrored = vertices[moved].copy()
    mirrored[:, 0] = 2 * middle_x - mirrored[:, 0]
    partner = nearest_points(mirrored, vertices)
    mirror_deltas = deltas[partner] * np.array([-1.0, 1.0, 1.0])
    difference = np.linalg.norm(deltas[moved] - mirror_deltas, axis=1).sum()
    total = np.linalg.norm(deltas[moved], axis=1).sum() + np.linalg.norm(mirror_deltas, axis=1).sum()
    return float(1.0 - difference / total) if total > 0 else 1.0


def nearest_points(points: np.ndarray, candidates: np.ndarray) -> np.ndarray:
    """Index of the nearest candidate for each point (chunked brute force; BLAS does the work)."""
    nearest = np.empty(len(points), np.int64)
    squared = (candidates**2).sum(1)
    for start in range(0, len(points), 1024):
        chunk = points[start : start + 1024]
        nearest[start : start + 1024] = np.argmin(squared[None, :] - 2.0 * chunk @ candidates.T, axis=1)
    return nearest


class FaceMeasure:
    """Figures of a head's keys in the face's own frame (looking toward -Y, Z up), whatever its turn.

    Lips and lids are the parts' vertices the front view sees (not the mouth bag or the socket's lining).
    """

    def __init__(self, vertices: np.ndarray, polygons, landmarks) -> None:
        self.landmarks = landmarks  # as given, in the mesh's own frame
        origin, self.axes = face_frame(landmarks)
        self.vertices = (np.asarray(vertices, np.float64) - origin) @ self.axes
        upright = {
            name: (np.asarray(point, np.float64) - origin) @ self.axes for name, point in landmarks.items()
        }
        triangles = triangulate(polygons)
        self.edges = mesh_edges(triangles)
        in_part = np.zeros(len(self.vertices), bool)
        for indices in find_parts(self.vertices, triangles, upright).values():
            in_part[indices] = True  # teeth, eyeballs and lashes are not skin
        parts = find_face_parts(self.vertices, triangles, np.flatnonzero(~in_part), upright)
        self.middle_x = parts.middle_x
        self.lips = [
            np.flatnonzero(parts.seen & (parts.label == PART_LABELS.index(n)))
            for n in ("upper_lip", "lower_lip")
        ]
        self.lids = {}
        for side in ("left", "right"):
            inner, outer = upright[f"eye_inner_{side}"], upright[f"eye_outer_{side}"]
            self.lids[side] = (
                [
                    np.flatnonzero(parts.seen & (parts.label == PART_LABELS.index(f"{n}_lid_{side}")))
                    for n in ("upper", "lower")
                ],
                0.5 * (inner[0] + outer[0]),
            )

    def upright(self, deltas: np.ndarray) -> np.ndarray:
        return np.asarray(deltas, np.float64) @ self.axes

    def lip_aperture(self, deltas: np.ndarray) -> float:
        """Lowest point of the upper lip minus highest of the lower lip at the midline (negative: pressed)."""
        return opening_gap(self.vertices, self.upright(deltas), *self.lips, self.middle_x)

    def lid_gap(self, deltas: np.ndarray, side: str = "left") -> float:
        (upper, lower), x = self.lids[side]
        return opening_gap(self.vertices, self.upright(deltas), upper, lower, x)

    def stretch(self, deltas: np.ndarray) -> float:
        return edge_stretch(self.vertices, self.edges, self.upright(deltas))

    def symmetry(self, deltas: np.ndarray) -> float:
        return symmetry(self.vertices, self.upright(deltas), self.middle_x)
