"""Figures that tell a good face shape from a broken one, computed from the arrays alone.

A transferred key can look plausible in numbers and still pull a curtain of stretched faces across the
mouth, so every key is judged by how much it stretches the mesh's edges, how far the lips and lids part
at the middle, how symmetric it is, whether a blink creases the skin above the lid, and (where an artist
made the same shape) how closely its displacement field points the artist's way.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .closest import nearest_vertices
from .head_parts import find_parts
from .landmarks import face_frame
from .parts import PART_LABELS, find_face_parts, opening_gap
from .topology import edge_graph, triangulate

# Reach of the skin above an upper lid whose folds count as the lid's creases, in eye widths.
LID_CREASE_REACH = 1.2


def edge_stretch(vertices: np.ndarray, edges: np.ndarray, deltas: np.ndarray, percentile: float = 99.9):
    """The given percentile of deformed / rest edge length over the edges the key moves at all."""
    rest = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1)
    moved = vertices + deltas
    deformed = np.linalg.norm(moved[edges[:, 0]] - moved[edges[:, 1]], axis=1)
    touched = (np.abs(deltas[edges[:, 0]]).sum(1) + np.abs(deltas[edges[:, 1]]).sum(1) > 0) & (rest > 0)
    if not touched.any():
        return 1.0
    return float(np.percentile(deformed[touched] / rest[touched], percentile))


def edge_folds(
    triangles: np.ndarray, vertices: np.ndarray, deltas: np.ndarray, region: np.ndarray, degrees=60.0
):
    """How many edges inside region (a vertex mask) the key folds: the angle between the two triangles
    that share the edge grows by more than `degrees`. A key that creases the skin folds a row of them."""
    sides = np.sort(
        np.concatenate((triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]])), axis=1
    )
    owners = np.tile(np.arange(len(triangles)), 3)
    order = np.lexsort((sides[:, 1], sides[:, 0]))
    sides, owners = sides[order], owners[order]
    shared = np.all(sides[1:] == sides[:-1], axis=1)  # an edge of two triangles: consecutive once sorted
    first, second, ends = owners[:-1][shared], owners[1:][shared], sides[:-1][shared]
    keep = region[ends].all(1) & np.any(deltas[ends].reshape(len(ends), -1) != 0, axis=1)
    first, second = first[keep], second[keep]

    def angles(points):
        corners = points[triangles]
        normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
        return np.degrees(np.arccos(np.clip((normals[first] * normals[second]).sum(1), -1.0, 1.0)))

    return int(np.count_nonzero(angles(vertices + deltas) - angles(vertices) > degrees))


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
    partner, _ = nearest_vertices(mirrored, vertices)
    mirror_deltas = deltas[partner] * np.array([-1.0, 1.0, 1.0])
    difference = np.linalg.norm(deltas[moved] - mirror_deltas, axis=1).sum()
    total = np.linalg.norm(deltas[moved], axis=1).sum() + np.linalg.norm(mirror_deltas, axis=1).sum()
    return float(1.0 - difference / total) if total > 0 else 1.0


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
        self.triangles = triangulate(polygons)
        self.edges, _ = edge_graph(len(self.vertices), self.triangles, self.vertices)
        skin = find_parts(self.vertices, self.triangles, upright).skin  # not teeth, eyeballs or lashes
        parts = find_face_parts(self.vertices, self.triangles, skin, upright)
        self.middle_x = parts.middle_x
        self.lips = [
            np.flatnonzero(parts.seen & (parts.label == PART_LABELS.index(n)))
            for n in ("upper_lip", "lower_lip")
        ]
        self.lids = {}
        self.above_lids = {}  # the seen skin above each upper lid's margin, near the eye (LID_CREASE_REACH)
        for side in ("left", "right"):
            inner, outer = upright[f"eye_inner_{side}"], upright[f"eye_outer_{side}"]
            if f"upper_lid_{side}" in upright:
                reach = LID_CREASE_REACH * np.linalg.norm(outer - inner)
                self.above_lids[side] = (
                    parts.seen
                    & (parts.label >= 0)
                    & (self.vertices[:, 2] > upright[f"upper_lid_{side}"][2])
                    & (np.linalg.norm(self.vertices - (inner + outer) / 2, axis=1) < reach)
                )
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

    def lid_creases(self, deltas: np.ndarray, side: str = "left") -> float:
        """Edges of the skin above the upper lid that the key folds (edge_folds); NaN with no lid margin."""
        if side not in self.above_lids:
            return float("nan")
        return float(edge_folds(self.triangles, self.vertices, self.upright(deltas), self.above_lids[side]))

    def symmetry(self, deltas: np.ndarray) -> float:
        return symmetry(self.vertices, self.upright(deltas), self.middle_x)


def piece_motion(pieces: Mapping[str, np.ndarray], ours: np.ndarray, truth: np.ndarray | None = None) -> dict:
    """Per piece (name -> vertex indices): its share of a key's motion (of the summed squared
    displacements), and with a truth (an artist's key, or a known one) its share of that and the
    cosine of the two."""
    ours = np.asarray(ours, np.float64)
    total = max(float((ours**2).sum()), 1e-300)
    figures = {}
    for name, indices in pieces.items():
        row = {"ours": float((ours[indices] ** 2).sum()) / total}
        if truth is not None:
            row["share"] = float((truth[indices] ** 2).sum()) / max(float((truth**2).sum()), 1e-300)
            row["cosine"] = displacement_cosine(ours[indices], truth[indices])
        figures[name] = row
    return figures
