"""Non-rigid registration of the reference head onto a target head: landmark-guided ICP.

The landmarks place the reference (a similarity fit and a thin-plate warp); between them the two
surfaces still lie apart by millimetres, so a target vertex would sample the reference where it is not
the same piece of face (the skin above the lid for the lid's margin). Each iteration pairs target
vertices with their closest points on the placed reference, each lip and lid only with the reference's
surface that is not its opposite part, drops pairs too far apart (the target's mouth bag behind the
reference's shallower one), and bends the whole reference by a smoothing thin-plate spline through the
pairs and the landmarks, stiff at first and looser after. The landmarks stay where they were placed.
"""

from __future__ import annotations

import numpy as np

from .closest import closest_points
from .parts import PART_LABELS

# Smoothing of the spline through the pairs, in face sizes, one value per iteration: stiff, then looser.
STIFFNESS = (1.0, 0.3, 0.1, 0.04)
# Pairs further apart than this share of the face size are not the same surface (a deeper mouth bag,
# an ear); the threshold tightens with the stiffness as the surfaces come together.
PAIR_REACH = (0.06, 0.04, 0.03, 0.025)
# Target vertices paired per iteration (evenly spread over the face): enough for a smooth warp, few
# enough that each spline solve stays a fraction of a second.
PAIRED_VERTICES = 1200
# The face region paired: the landmarks' box, widened by this share of its size on each side.
FACE_MARGIN = 0.25
# Landmarks barely yield: their smoothing as a share of the pairs'.
LANDMARK_STIFFNESS = 1e-3


def similarity_fit(source: np.ndarray, target: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """Scale, rotation and translation that best map source points onto target points (Umeyama 1991)."""
    source = np.asarray(source, np.float64)
    target = np.asarray(target, np.float64)
    source_mean, target_mean = source.mean(0), target.mean(0)
    source_centred, target_centred = source - source_mean, target - target_mean
    covariance = target_centred.T @ source_centred / len(source)
    u, singular, vt = np.linalg.svd(covariance)
    sign = np.ones(3)
    if np.linalg.det(u) * np.linalg.det(vt) < 0:
        sign[2] = -1.0  # a reflection is not a head turned around
    rotation = u @ np.diag(sign) @ vt
    variance = (source_centred**2).sum() / len(source)
    scale = float((singular * sign).sum() / variance) if variance > 0 else 1.0
    translation = target_mean - scale * rotation @ source_mean
    return scale, rotation, translation


def rigid_fit(before: np.ndarray, after: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotation and translation that best move `before` onto `after` (no scaling: teeth do not grow)."""
    before_mean, after_mean = before.mean(0), after.mean(0)
    covariance = (after - after_mean).T @ (before - before_mean)
    u, _, vt = np.linalg.svd(covariance)
    sign = np.ones(3)
    if np.linalg.det(u) * np.linalg.det(vt) < 0:
        sign[2] = -1.0
    rotation = u @ np.diag(sign) @ vt
    return rotation, after_mean - rotation @ before_mean


class ThinPlateWarp:
    """A smooth 3D warp that moves each source landmark exactly onto its target (kernel |r|, affine part)."""

    def __init__(self, source: np.ndarray, target: np.ndarray, smoothing=0.0) -> None:
        self.source = np.asarray(source, np.float64)
        count = len(self.source)
        kernel = np.linalg.norm(self.source[:, None] - self.source[None], axis=2)
        # smoothing > 0 (one value, or one per point): pass near the points, not through them. The kernel
        # |r| is conditionally negative definite, so the smoothing is subtracted from its diagonal.
        kernel[np.diag_indices(count)] -= np.broadcast_to(np.asarray(smoothing, np.float64), (count,))
        affine = np.hstack((np.ones((count, 1)), self.source))
        system = np.zeros((count + 4, count + 4))
        system[:count, :count] = kernel
        system[:count, count:] = affine
        system[count:, :count] = affine.T
        right = np.zeros((count + 4, 3))
        right[:count] = target
        try:
            solution = np.linalg.solve(system, right)
        except np.linalg.LinAlgError:  # points that coincide: the least-squares warp
            solution = np.linalg.lstsq(system, right, rcond=None)[0]
        self.weights, self.affine = solution[:count], solution[count:]

    def __call__(self, points: np.ndarray) -> np.ndarray:
        out = self.affine[0] + points @ self.affine[1:]
        for start in range(0, len(points), 8192):
            chunk = points[start : start + 8192]
            kernel = np.linalg.norm(chunk[:, None] - self.source[None], axis=2)
            out[start : start + 8192] += kernel @ self.weights
        return out


def register_onto_target(
    placed: np.ndarray,
    surface: tuple[np.ndarray, np.ndarray],
    reference_skin: np.ndarray,
    reference_labels: np.ndarray,
    target_vertices: np.ndarray,
    target_skin: np.ndarray,
    target_labels: np.ndarray,
    upright_target: np.ndarray,
    upright_landmarks: np.ndarray,
    landmark_points: tuple[np.ndarray, np.ndarray],
    face_size: float,
) -> np.ndarray:
    """The placed reference's vertices bent onto the target's skin.

    surface: (triangles, triangles around each vertex) of the reference. reference_labels and
    target_labels: indices into PART_LABELS per vertex, -1 where a label is not sure (those pair with
    any surface). upright_target, upright_landmarks: the target's vertices and landmarks in the
    reference's frame (for the face's box).
    landmark_points: (on the placed reference, on the target), pinned as the warp bends.
    """
    triangles, around = surface
    sources, targets = (np.asarray(points, np.float64) for points in landmark_points)
    paired = _paired_vertices(target_skin, upright_target, upright_landmarks)
    placed = np.asarray(placed, np.float64).copy()
    on_skin = np.zeros(len(placed), bool)
    on_skin[reference_skin] = True
    for stiffness, reach in zip(STIFFNESS, PAIR_REACH, strict=True):
        found_on, found_at = [], []
        for index in range(len(PART_LABELS)):
            group = paired[target_labels[paired] == index] if index else paired[target_labels[paired] <= 0]
            if len(group) == 0:
                continue
            allowed = (on_skin & (reference_labels == index))[triangles].all(1)
            if not allowed.any():
                continue
            triangle, weights, distance = closest_points(
                target_vertices[group], placed, triangles, allowed, around
            )
            near = distance < reach * face_size
            corners = placed[triangles[triangle[near]]]
            found_on.append((corners * weights[near][:, :, None]).sum(1))
            found_at.append(target_vertices[group[near]])
        if not found_on:
            break
        on_reference = np.concatenate(found_on + [sources])
        on_target = np.concatenate(found_at + [targets])
        smoothing = np.full(len(on_reference), stiffness * face_size)
        smoothing[-len(sources) :] *= LANDMARK_STIFFNESS
        warp = ThinPlateWarp(on_reference, on_target, smoothing)
        placed = warp(placed)
        sources = warp(sources)
    return placed


def _paired_vertices(skin: np.ndarray, upright: np.ndarray, landmarks: np.ndarray) -> np.ndarray:
    """Target skin vertices in the face's box, thinned evenly to about PAIRED_VERTICES."""
    low, high = landmarks.min(0), landmarks.max(0)
    margin = FACE_MARGIN * (high - low)
    inside = np.all((upright[skin] >= low - margin) & (upright[skin] <= high + margin), axis=1)
    chosen = skin[inside]
    step = max(1, len(chosen) // PAIRED_VERTICES)
    return chosen[::step]
