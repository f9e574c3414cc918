"""Carry the reference head's 52 ARKit units over to a head that has none.

The landmarks register the reference onto the target (a similarity fit, and for heads whose proportions
differ a local warp that takes each landmark onto its own); each target skin vertex then takes the
deltas of the closest point on the reference surface, turned and scaled by the fitted similarity. Teeth
and eyes are rigid: each unit's motion of the reference's teeth and eyes is fitted as a rotation and
translation and applied to the target's, so the jaw carries the lower teeth without bending them, and
the eyes turn in place.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from .closest import closest_points, triangles_around
from .head_parts import find_parts, split_eyes
from .landmarks import find_landmarks
from .lids import (
    LID_ROUGH,
    LidFrame,
    close_blinks_as_the_reference_does,
    ease_the_skin_above_the_lids,
    fade_behind_the_lids,
    smooth_lids,
)
from .parts import OPPOSITE_PART, PART_LABELS, FaceParts, find_face_parts
from .registration import Placement, place_reference, rigid_fit
from .topology import edge_graph, triangulate

# Reference part names (reference.parts) and the target part each one drives.
RIGID_PARTS: tuple[str, ...] = ("upper_teeth", "lower_teeth", "left_eye", "right_eye")
SOFT_PARTS: tuple[str, ...] = ("tongue", "left_eyelashes", "right_eyelashes")


# Beyond these distances (fractions of the reference head's height, after registration) a target vertex
# is not near the reference skin any more (a torso, a hat): its deltas fade to nothing.
FALLOFF_NEAR = 0.05
FALLOFF_FAR = 0.15


@functools.lru_cache(maxsize=4)
def reference_landmarks_of(reference) -> dict[str, np.ndarray]:
    """The reference's landmarks found the same way as a target's, so both follow one convention."""
    return find_landmarks(reference.vertices, reference.polygons)


def transfer_units(
    reference,
    target_vertices: np.ndarray,
    target_polygons,
    target_landmarks: Mapping[str, np.ndarray],
    *,
    target_parts: Mapping[str, np.ndarray] | None = None,
    warp: str = "auto",
    reference_landmarks: Mapping[str, np.ndarray] | None = None,
) -> dict[str, np.ndarray]:
    """Deltas (M, 3) on the target's vertices for each of the reference's units.

    reference: a ReferenceHead (vertices, polygons, parts, units). target_parts: vertex indices of
    "upper_teeth", "lower_teeth", "tongue", "left_eye", "right_eye" (or "eyes", split by side), found
    with find_parts when not given. warp: "similarity", "landmarks" or "auto" (the warp when the
    similarity fit leaves the landmarks more than a few percent of the face apart). reference_landmarks
    default to find_landmarks on the reference, the convention the target's landmarks follow.
    """
    target_vertices = np.asarray(target_vertices, np.float64)
    target_triangles = triangulate(target_polygons)
    if reference_landmarks is None:
        reference_landmarks = reference_landmarks_of(reference)
    placement = place_reference(reference.vertices, reference_landmarks, target_landmarks, warp)
    if target_parts is None:
        target_parts = find_parts(target_vertices, target_triangles, target_landmarks)
    target_parts = split_eyes(dict(target_parts), target_vertices, target_landmarks)
    reference_triangles = triangulate(reference.polygons)
    job = _Transfer(
        reference=reference,
        reference_landmarks=reference_landmarks,
        placement=placement,
        surface=(reference_triangles, triangles_around(len(placement.placed), reference_triangles)),
        units={name: np.asarray(delta, np.float64) for name, delta in reference.units.items()},
        vertices=target_vertices,
        triangles=target_triangles,
        landmarks=target_landmarks,
    )
    result = {name: np.zeros_like(target_vertices) for name in job.units}
    in_part = np.zeros(len(target_vertices), bool)
    for name, indices in target_parts.items():
        if len(indices) and name in reference.parts:
            in_part[indices] = True
    _carry_the_skin(job, result, np.flatnonzero(~in_part))  # the skin, and whatever is no known part
    _carry_the_parts(job, result, target_parts)
    return result


@dataclass(frozen=True)
class _Transfer:
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


def _carry_the_skin(job: _Transfer, result, skin) -> None:
    """Each lip and lid samples only its own kind on the reference, the rest of the skin the whole
    reference skin; the inside of the mouth follows the teeth of its jaw; then the lid passes."""
    reference, placement = job.reference, job.placement
    reference_vertices = np.asarray(reference.vertices, np.float64)
    reference_skin = np.asarray(reference.parts.get("skin", np.arange(len(reference_vertices))))
    height = placement.scale * float(np.ptp(reference_vertices[reference_skin, 2]))
    # Parts are read in the reference's frame (face toward -Y, Z up), whatever the target's turn.
    upright_vertices = placement.to_reference(job.vertices)
    upright_landmarks = {name: placement.to_reference(point) for name, point in job.landmarks.items()}
    target_face = find_face_parts(upright_vertices, job.triangles, skin, upright_landmarks)
    reference_face = _reference_face_parts(
        reference, tuple((name, tuple(map(float, point))) for name, point in job.reference_landmarks.items())
    )
    apart = np.zeros(len(job.vertices))  # each vertex's distance from the reference surface it samples
    sampled = upright_vertices.copy()  # where on the reference at rest each vertex samples (itself if none)
    for index, label in enumerate(PART_LABELS):
        sure = target_face.sure[skin]
        targets = skin[(target_face.label[skin] == index) & sure] if index else skin[~sure]
        # A lip or lid samples the reference anywhere but on its opposite, so the parts need not match
        # in extent: only the surfaces that touch are kept apart.
        sources = reference_skin
        if index:
            opposite = reference_face.label[reference_skin] == PART_LABELS.index(OPPOSITE_PART[label])
            opposite &= reference_face.sure[reference_skin]
            sources = reference_skin[~opposite]
        apart[targets], corners, weights = _carry_by_closest_point(job, result, targets, sources, height)
        if corners is not None:
            sampled[targets] = (reference_vertices[corners] * weights[:, :, None]).sum(1)
    frame = LidFrame(
        target_face, upright_vertices, upright_landmarks, reference, reference_face, job.reference_landmarks
    )
    fade_behind_the_lids(result, frame, apart / placement.scale)
    # Where the reference's own mouth lies on the target's, its own motion is right; the jaw takes over
    # where the target's mouth goes deeper than the reference's.
    mouth_width = job.mouth_width()
    beyond = np.clip((apart - 0.02 * mouth_width) / (0.06 * mouth_width), 0.0, 1.0)
    _follow_the_jaw(job, result, skin, target_face, beyond, upright_vertices)
    eye_width = job.eye_width()
    target_edges, _ = edge_graph(len(job.vertices), job.triangles, job.vertices)
    smooth_lids(result, target_face, target_edges, np.clip(apart / (LID_ROUGH * eye_width), 0, 1))
    close_blinks_as_the_reference_does(result, frame, placement, sampled)
    ease_the_skin_above_the_lids(result, frame, target_edges, apart / eye_width)


def _carry_the_parts(job: _Transfer, result, target_parts) -> None:
    """The tongue and lashes bend (closest point on the reference's own); teeth and eyes move as solids."""
    reference = job.reference
    for name in SOFT_PARTS:
        if name in target_parts and name in reference.parts and len(target_parts[name]):
            _carry_by_closest_point(job, result, np.asarray(target_parts[name]), reference.parts[name], None)
    reference_vertices = np.asarray(reference.vertices, np.float64)
    for name in RIGID_PARTS:
        if name in target_parts and name in reference.parts and len(target_parts[name]):
            indices = reference.parts[name]
            part_units = {unit: delta[indices] for unit, delta in job.units.items()}
            _carry_rigidly(
                job, result, np.asarray(target_parts[name]), reference_vertices[indices], part_units
            )


@functools.lru_cache(maxsize=4)
def _reference_face_parts(reference, landmark_items) -> FaceParts:
    landmarks = {name: np.asarray(point) for name, point in landmark_items}
    return find_face_parts(
        np.asarray(reference.vertices, np.float64),
        triangulate(reference.polygons),
        np.asarray(reference.parts.get("skin", np.arange(len(reference.vertices)))),
        landmarks,
    )


def _follow_the_jaw(job: _Transfer, result, skin, face, beyond, in_reference) -> None:
    """Blend the inside of the mouth (bag, gums, teeth and tongue joined to the skin) toward the rigid
    motion of the reference's teeth, the lower teeth's below the lips and the upper teeth's above."""
    reference = job.reference
    if "upper_teeth" not in reference.parts or "lower_teeth" not in reference.parts:
        return
    targets = skin[face.inside_mouth[skin] > 0]
    if len(targets) == 0:
        return
    weight = (face.inside_mouth[targets] * beyond[targets])[:, None]
    lower = face.lower_jaw[targets][:, None]
    in_reference = in_reference[targets]
    reference_vertices = np.asarray(reference.vertices, np.float64)
    for name, delta in job.units.items():
        rigid = np.zeros_like(in_reference)
        for teeth, share in (("upper_teeth", 1 - lower), ("lower_teeth", lower)):
            points = reference_vertices[reference.parts[teeth]]
            part_delta = delta[reference.parts[teeth]]
            if np.any(part_delta):
                turn, shift = rigid_fit(points, points + part_delta)
                rigid += share * (in_reference @ turn.T + shift - in_reference)
        deltas = job.placement.deltas_to_target(rigid)
        result[name][targets] = (1 - weight) * result[name][targets] + weight * deltas


def _carry_by_closest_point(job: _Transfer, result, targets, reference_indices, height):
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


def _carry_rigidly(job: _Transfer, result, targets, reference_points, part_units) -> None:
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
