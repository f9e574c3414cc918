"""Placing the reference head on a target: similarity and rigid fits, and a landmark warp.

The landmarks place the reference (a similarity fit, and a warp where the proportions differ); the rigid
fit turns teeth and eyes as solids. The warp is local: a thin-plate spline (kernel |r|, whose pull grows
with distance) let the brows' 7 mm of disagreement between Vitruvian and the reference bend its mouth
(pucker and smile against its artists' keys 0.63 and 0.62; local 0.71 and 0.73), and on the reference
bent into 24 other faces (lab/measure/transfer.py) the local warp gives mean cosine 0.970 against
the thin-plate's 0.970, the worst face 0.938 against 0.924. An affine fit under the local pulls (for a
face wider all over) lost on both (Vitruvian 0.67 and 0.67, the bent faces 0.968 and 0.935).
A non-rigid ICP on top (pairs of closest points, a smoothing spline through them) brought the surfaces
together on Vitruvian (median gap 2.15 -> 0.43 mm) but did not bring the transferred keys nearer its
artists' (31 units compared, each within +-0.05) and took 4 s more; it is not used.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..base.errors import HeadError

# How far the landmarks' pull reaches, as a share of their spread (about the face's diagonal):
# REACH_PER_OFFSET times the median distance (same share) the similarity fit leaves them from their
# targets, within REACH_RANGE. Most landmarks near their fit mean local differences (Vitruvian, median
# 1.1 %: 0.15, best there and on the bent faces; 0.25 and 0.4 fell back toward the spline); most of them
# far off mean a face of other proportions all over (Godette's stylised eyes, 6.7 %: 0.27; at 0.15 its
# transferred blink stretched its lids 4.0, now 1.7). Bent faces: mean 0.970, worst 0.938.
REACH_PER_OFFSET = 4.0
REACH_RANGE = (0.15, 0.6)
# A similarity fit that leaves landmarks this far off (fraction of the face size) calls for the warp.
WARP_RESIDUAL = 0.02


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


class LandmarkWarp:
    """A smooth 3D warp that moves each source landmark exactly onto its target, its pull fading with
    distance (Gaussian, reach as REACH_PER_OFFSET says): a landmark that two heads place a little
    differently (a brow, a nose tip) bends its own region, not the mouth across the face."""

    def __init__(self, source: np.ndarray, target: np.ndarray) -> None:
        self.source = np.asarray(source, np.float64)
        spread = float(np.linalg.norm(np.ptp(self.source, axis=0)))
        offset = float(np.median(np.linalg.norm(np.asarray(target) - self.source, axis=1))) / spread
        self.reach = spread * float(np.clip(REACH_PER_OFFSET * offset, *REACH_RANGE))
        kernel = self._kernel(self.source)
        # Distinct landmarks make the kernel positive definite; the ridge only guards near-duplicates.
        kernel[np.diag_indices(len(kernel))] += 1e-9
        self.weights = np.linalg.solve(kernel, np.asarray(target, np.float64) - self.source)

    def _kernel(self, points: np.ndarray) -> np.ndarray:
        distance = np.linalg.norm(points[:, None] - self.source[None], axis=2)
        return np.exp(-((distance / self.reach) ** 2))

    def __call__(self, points: np.ndarray) -> np.ndarray:
        points = np.asarray(points, np.float64)
        out = points.copy()
        for start in range(0, len(points), 8192):
            out[start : start + 8192] += self._kernel(points[start : start + 8192]) @ self.weights
        return out


@dataclass(frozen=True)
class Placement:
    """Where the reference lies on a target: the similarity fit of their landmarks (target = scale *
    rotation @ reference + translation), and the reference's vertices placed on the target (that fit,
    then the landmark warp where the proportions differ). Deltas follow the similarity only."""

    scale: float
    rotation: np.ndarray
    translation: np.ndarray
    placed: np.ndarray  # (N, 3) the reference's vertices on the target
    face_size: float  # the spread of the target's landmarks (its diagonal)

    def to_reference(self, points) -> np.ndarray:
        """Target points in the reference's frame (face toward -Y, Z up, the reference's size)."""
        return ((np.asarray(points, np.float64) - self.translation) @ self.rotation) / self.scale

    def deltas_to_target(self, deltas) -> np.ndarray:
        """Displacements in the reference's frame as the target's (turned and scaled)."""
        return self.scale * np.asarray(deltas, np.float64) @ self.rotation.T

    def deltas_to_reference(self, deltas) -> np.ndarray:
        return np.asarray(deltas, np.float64) @ self.rotation / self.scale


def place_reference(
    reference_vertices: np.ndarray,
    reference_landmarks: Mapping[str, np.ndarray],
    target_landmarks: Mapping[str, np.ndarray],
    warp: str = "auto",
) -> Placement:
    """Lay the reference on the target by their shared landmarks. warp: "similarity", "landmarks" or
    "auto" (the warp when the similarity fit leaves the landmarks more than WARP_RESIDUAL apart)."""
    if warp not in ("auto", "similarity", "landmarks"):
        raise ValueError(f"warp must be 'auto', 'similarity' or 'landmarks', not {warp!r}")
    names = [name for name in reference_landmarks if name in target_landmarks]
    if len(names) < 4:
        raise HeadError(
            f"Only {len(names)} face landmarks match the reference ({', '.join(names) or 'none'}); "
            "at least 4 are needed to place the reference head. Place the landmark markers and rebuild."
        )
    source_points = np.array([reference_landmarks[name] for name in names], np.float64)
    target_points = np.array([target_landmarks[name] for name in names], np.float64)
    if np.linalg.matrix_rank(target_points - target_points.mean(0), tol=1e-9 * np.ptp(target_points)) < 3:
        raise HeadError("The face landmarks lie on one line or plane; move the landmark markers apart.")
    scale, rotation, translation = similarity_fit(source_points, target_points)
    placed_landmarks = scale * source_points @ rotation.T + translation
    face_size = float(np.linalg.norm(np.ptp(target_points, axis=0)))
    residual = float(np.sqrt(((placed_landmarks - target_points) ** 2).sum(1).mean()))
    placed = scale * np.asarray(reference_vertices, np.float64) @ rotation.T + translation
    if warp == "landmarks" or (warp == "auto" and residual > WARP_RESIDUAL * face_size):
        # Landmarks that coincide on the reference (the inner lips of a closed mouth) would make the
        # warp singular: keep the first of each group.
        distinct = [0]
        for index in range(1, len(names)):
            gaps = np.linalg.norm(placed_landmarks[distinct] - placed_landmarks[index], axis=1)
            if gaps.min() > 1e-3 * face_size:
                distinct.append(index)
        placed = LandmarkWarp(placed_landmarks[distinct], target_points[distinct])(placed)
    return Placement(scale, rotation, translation, placed, face_size)
