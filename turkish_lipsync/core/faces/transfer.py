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

import numpy as np

from .carry import TransferJob, carry_by_closest_point, carry_rigidly
from .closest import triangles_around
from .eyes import sphere_fit
from .head_parts import RIDER_KINDS, HeadParts, find_parts
from .jaw import carry_mouth_pieces, follow_the_jaw
from .landmarks import find_landmarks
from .lids import (
    LID_ROUGH,
    LidFrame,
    behind_the_lids,
    close_blinks_as_the_reference_does,
    ease_the_skin_above_the_lids,
    fade_behind_the_lids,
    smooth_lids,
)
from .parts import OPPOSITE_PART, PART_LABELS, FaceParts, find_face_parts
from .registration import place_reference
from .riders import carry_riders, keep_under_the_skin
from .topology import edge_graph, triangulate

# A lash or eye shell this close to the reference's own lashes (eye widths) takes their motion; from
# OWN_LASHES[1] on it rides its own lids (a head's lashes are rarely where the reference's are).
OWN_LASHES = (0.02, 0.06)


# An eye's shell is held this far (eye widths) under the moved skin that covers it.
SHELL_GAP = 0.01


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
    target_parts: HeadParts | None = None,
    warp: str = "auto",
    reference_landmarks: Mapping[str, np.ndarray] | None = None,
) -> dict[str, np.ndarray]:
    """Deltas (M, 3) on the target's vertices for each of the reference's units.

    reference: a ReferenceHead (vertices, polygons, parts, units). target_parts: the head's skin and
    pieces (find_parts, which is asked when they are not given). warp: "similarity", "landmarks" or
    "auto" (the warp when the similarity fit leaves the landmarks more than a few percent of the face
    apart). reference_landmarks default to find_landmarks on the reference, the convention the target's
    landmarks follow.
    """
    target_vertices = np.asarray(target_vertices, np.float64)
    target_triangles = triangulate(target_polygons)
    if reference_landmarks is None:
        reference_landmarks = reference_landmarks_of(reference)
    placement = place_reference(reference.vertices, reference_landmarks, target_landmarks, warp)
    if target_parts is None:
        target_parts = find_parts(target_vertices, target_triangles, target_landmarks)
    reference_triangles = triangulate(reference.polygons)
    job = TransferJob(
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
    _, anchorable = _carry_the_skin(job, result, target_parts.skin)
    _carry_the_parts(job, result, target_parts)
    _carry_the_riders(job, result, target_parts, anchorable)
    _take_the_reference_lashes(job, result, target_parts)
    return result


def _carry_the_skin(job: TransferJob, result, skin) -> tuple[LidFrame, np.ndarray]:
    """Each lip and lid samples only its own kind on the reference, the rest of the skin the whole
    reference skin; the inside of the mouth follows the teeth of its jaw; then the lid passes. Returns
    the faces as the lid passes read them, and the skin vertices a piece may ride (not the socket's
    still lining behind the lids, not the inside of the mouth)."""
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
        apart[targets], corners, weights = carry_by_closest_point(job, result, targets, sources, height)
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
    follow_the_jaw(job, result, skin, target_face, beyond, upright_vertices)
    eye_width = job.eye_width()
    target_edges, _ = edge_graph(len(job.vertices), job.triangles, job.vertices)
    smooth_lids(result, target_face, target_edges, np.clip(apart / (LID_ROUGH * eye_width), 0, 1))
    close_blinks_as_the_reference_does(result, frame, placement, sampled)
    ease_the_skin_above_the_lids(result, frame, target_edges, apart / eye_width)
    return frame, skin[~behind_the_lids(frame)[skin] & (target_face.inside_mouth[skin] < 0.5)]


def _carry_the_parts(job: TransferJob, result, parts: HeadParts) -> None:
    """Eyes and teeth move as solids, the tongue bends as the reference's does, and pieces reaching both
    jaws go with each jaw vertex by vertex."""
    reference = job.reference
    reference_vertices = np.asarray(reference.vertices, np.float64)
    solids = {f"{side}_eye": parts.indices("eyeball", "cornea", side=side) for side in ("left", "right")}
    solids.update(upper_teeth=parts.indices("upper_teeth"), lower_teeth=parts.indices("lower_teeth"))
    for name, targets in solids.items():
        if len(targets) and name in reference.parts:
            indices = reference.parts[name]
            part_units = {unit: delta[indices] for unit, delta in job.units.items()}
            carry_rigidly(job, result, targets, reference_vertices[indices], part_units)
    tongue = parts.indices("tongue")
    if len(tongue) and "tongue" in reference.parts:
        carry_by_closest_point(job, result, tongue, reference.parts["tongue"], None)
    carry_mouth_pieces(job, result, [piece.indices for piece in parts.pieces if piece.kind == "mouth"])


def _carry_the_riders(job: TransferJob, result, parts: HeadParts, anchorable: np.ndarray) -> None:
    """Lashes, shells and cards ride the skin they touch (an eye's turning about its eyeball); an eye's
    shells stay under the lids."""
    riders = [piece for piece in parts.pieces if piece.kind in RIDER_KINDS]
    centres = _eye_centres(job, parts)
    eye_width = job.eye_width()
    carry_riders(
        result,
        job.vertices,
        job.triangles,
        [piece.indices for piece in riders],
        anchorable,
        eye_width,
        [centres.get(piece.side) for piece in riders],
        [piece.kind == "lashes" for piece in riders],
    )
    for side, centre in centres.items():
        near = anchorable[np.linalg.norm(job.vertices[anchorable] - centre, axis=1) < 1.5 * eye_width]
        shells = parts.indices("eye_shell", side=side)
        keep_under_the_skin(result, job.vertices, shells, near, centre, SHELL_GAP * eye_width)


def _eye_centres(job: TransferJob, parts: HeadParts) -> dict[str, np.ndarray]:
    """The centre of each eyeball, which the eye's lashes and shells turn about: the head's own; else the
    centre of the sphere its biggest shell lies on (an occlusion shell hugs the eyeball); else the
    reference's eyeball where the registration placed it (a head whose eyes are not in its mesh)."""
    centres = {}
    for side in ("left", "right"):
        ball = parts.eye_balls.get(side)
        shells = [piece.indices for piece in parts.pieces if piece.kind == "eye_shell" and piece.side == side]
        if ball is not None:
            centres[side] = job.vertices[ball].mean(0)
        elif shells:
            centres[side] = sphere_fit(job.vertices[max(shells, key=len)])[0]
        elif f"{side}_eye" in job.reference.parts:
            centres[side] = job.placement.placed[job.reference.parts[f"{side}_eye"]].mean(0)
    return centres


def _take_the_reference_lashes(job: TransferJob, result, parts: HeadParts) -> None:
    """Lashes and eye shells lying where the reference's own lashes lie take those lashes' motion (the
    reference onto itself keeps its units); further off they ride their own lids."""
    eye_width = job.eye_width()
    for side in ("left", "right"):
        name = f"{side}_eyelashes"
        targets = parts.indices("lashes", "eye_shell", side=side)
        if len(targets) == 0 or name not in job.reference.parts:
            continue
        sampled = {unit: np.zeros_like(job.vertices) for unit in job.units}
        distance, _, _ = carry_by_closest_point(job, sampled, targets, job.reference.parts[name], None)
        near, far = OWN_LASHES
        weight = np.clip((far * eye_width - distance) / ((far - near) * eye_width), 0.0, 1.0)[:, None]
        for unit, deltas in result.items():
            deltas[targets] = (1 - weight) * deltas[targets] + weight * sampled[unit][targets]


@functools.lru_cache(maxsize=4)
def _reference_face_parts(reference, landmark_items) -> FaceParts:
    landmarks = {name: np.asarray(point) for name, point in landmark_items}
    return find_face_parts(
        np.asarray(reference.vertices, np.float64),
        triangulate(reference.polygons),
        np.asarray(reference.parts.get("skin", np.arange(len(reference.vertices)))),
        landmarks,
    )
