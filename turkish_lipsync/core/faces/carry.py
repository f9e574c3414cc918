"""How the transfer carries the reference's deltas onto a target: the closest point of the placed
reference surface, or a part's rigid motion; and the inputs every pass of one transfer shares."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from .closest import closest_points
from .registration import Placement, rigid_fit

# Beyond these distances (fractions of the reference head's height, after registration) a target vertex
# is not near the reference skin any more (a torso, a hat): its deltas fade to nothing.
FALLOFF_NEAR = 0.05
FALLOFF_FAR = 0.15


@dataclass(frozen=True)
class TransferJob:
    """One transfer's inputs: the reference, where it lies on the target, and the target."""

    reference: object  # the ReferenceHead
    reference_landmarks: Mapping[str, np.ndarray]
    placement: Placement
    surface: tuple[np.ndarray, np.ndarray]  # the reference's triangles and triangles_around them
    units: dict[str, np.ndarray]  # the reference's units, float64
    vertices: np.ndarray  # the target's
    triangles: np.ndarray
    landmarks: Mapping[str, np.ndarray]

    @property
    def turn(self) -> np.ndarray:
        """Deltas follow the global rotation and scale only."""
        return self.placement.scale * self.placement.rotation

    def eye_width(self) -> float:
        return float(
            np.mean(
                [
                    np.linalg.norm(self.landmarks[f"eye_outer_{side}"] - self.landmarks[f"eye_inner_{side}"])
                    for side in ("left", "right")
                ]
            )
        )

    def mouth_width(self) -> float:
        return float(
            np.linalg.norm(self.landmarks["mouth_corner_left"] - self.landmarks["mouth_corner_right"])
        )


def carry_by_closest_point(job: TransferJob, result, targets, reference_indices, height):
    """Deltas at the closest point of the placed reference (among reference_indices), interpolated over
    its triangle, turned and scaled; fading beyond FALLOFF_* of height from it (None: never).

    Returns the distances and the sampled triangles' corners with their barycentric weights (None, None
    when nothing was sampled).
    """
    triangles, around = job.surface
    placed = job.placement.placed
    keep = np.zeros(len(placed), bool)
    keep[reference_indices] = True
    allowed = keep[triangles].all(1)
    if not allowed.any() or len(targets) == 0:
        return np.zeros(len(targets)), None, None
    triangle, weights, distance = closest_points(job.vertices[targets], placed, triangles, allowed, around)
    corners = triangles[triangle]
    if height is None:
        fade = np.ones(len(targets))
    else:
        fade = np.clip((FALLOFF_FAR * height - distance) / ((FALLOFF_FAR - FALLOFF_NEAR) * height), 0, 1)
    faded = weights * fade[:, None]
    for name, delta in job.units.items():
        local = (delta[corners] * faded[:, :, None]).sum(1)
        result[name][targets] = local @ job.turn.T
    return distance, corners, weights


def carry_rigidly(job: TransferJob, result, targets, reference_points, part_units) -> None:
    """Each unit's motion of a reference part as a rotation about the part's centre plus a shift.

    The rotation turns the target part about its own centre (in the reference frame), so a part the
    landmarks placed a little off still turns in place instead of swinging around the reference's.
    """
    target_in_reference = job.placement.to_reference(job.vertices[targets])
    target_centre = target_in_reference.mean(0)
    reference_centre = reference_points.mean(0)
    for name, delta in part_units.items():
        if not np.any(delta):
            continue
        turn, shift = rigid_fit(reference_points, reference_points + delta)
        centre_motion = turn @ reference_centre + shift - reference_centre
        moved = (target_in_reference - target_centre) @ turn.T + target_centre + centre_motion
        result[name][targets] = job.placement.deltas_to_target(moved - target_in_reference)
