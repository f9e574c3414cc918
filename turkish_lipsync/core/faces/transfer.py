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

from ..base.errors import HeadError
from .closest import closest_points, triangles_around
from .landmarks import connected_pieces, face_frame, find_landmarks, largest_piece, triangulate
from .parts import (
    OPPOSITE_PART,
    PART_LABELS,
    FaceParts,
    edge_graph,
    find_face_parts,
    opening_gap,
    smooth_over_edges,
)
from .registration import LandmarkWarp, rigid_fit, similarity_fit

# Reference part names (reference.parts) and the target part each one drives.
RIGID_PARTS: tuple[str, ...] = ("upper_teeth", "lower_teeth", "left_eye", "right_eye")
SOFT_PARTS: tuple[str, ...] = ("tongue", "left_eyelashes", "right_eyelashes")

# Beyond these distances (fractions of the reference head's height, after registration) a target vertex
# is not near the reference skin any more (a torso, a hat): its deltas fade to nothing.
FALLOFF_NEAR = 0.05
FALLOFF_FAR = 0.15

# Lid vertices this far behind the eye's corners (in eye widths) are the socket's lining: they fade out.
LID_FADE_NEAR = 0.1
LID_FADE_FAR = 0.3

# Above the upper lid's margin a blink's travel falls off over this length (eye widths).
LID_UNFOLD_LENGTH = 0.2

# Sweeps of neighbour averaging that smooth a lid's deltas where the reference lies apart.
SMOOTHING_SWEEPS = 12
# A lid vertex this far from the reference surface (in eye widths) takes fully smoothed deltas.
LID_ROUGH = 0.1
# A blink's motion of the skin above the upper lid's margin, within this many eye widths of the eye's
# centre, is smoothed over the target's edges (sweeps): where the reference's lid ends the sampled motion
# steps from full travel to none, which creases a closed lid across; smoothed, the skin slopes from the
# margin to the brow. In full where that skin lies (median) BLINK_EASE_APART eye widths from the
# reference surface it samples, fading to nothing where the two coincide. Vitruvian (1.2 mm apart): the
# crease and its folds gone in close renders, cosine to the artist's blink 0.733 -> 0.744.
BLINK_EASE_REACH = 1.2
BLINK_EASE_SWEEPS = 30
BLINK_EASE_APART = 0.03

# A similarity fit that leaves landmarks this far off (fraction of the face size) calls for the warp.
WARP_RESIDUAL = 0.02


# ---------------------------------------------------------------- parts of the target


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
    if warp not in ("auto", "similarity", "landmarks"):
        raise ValueError(f"warp must be 'auto', 'similarity' or 'landmarks', not {warp!r}")
    target_vertices = np.asarray(target_vertices, np.float64)
    target_triangles = triangulate(target_polygons)
    if reference_landmarks is None:
        reference_landmarks = reference_landmarks_of(reference)
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
    use_warp = warp == "landmarks" or (warp == "auto" and residual > WARP_RESIDUAL * face_size)

    reference_vertices = np.asarray(reference.vertices, np.float64)
    placed = scale * reference_vertices @ rotation.T + translation
    if use_warp:
        # Landmarks that coincide on the reference (the inner lips of a closed mouth) would make the
        # warp singular: keep the first of each group.
        distinct = [0]
        for index in range(1, len(names)):
            gaps = np.linalg.norm(placed_landmarks[distinct] - placed_landmarks[index], axis=1)
            if gaps.min() > 1e-3 * face_size:
                distinct.append(index)
        placed = LandmarkWarp(placed_landmarks[distinct], target_points[distinct])(placed)
    turn = scale * rotation  # deltas follow the global rotation and scale only

    reference_triangles = triangulate(reference.polygons)
    surface = (reference_triangles, triangles_around(len(placed), reference_triangles))
    reference_parts = {name: np.asarray(indices) for name, indices in reference.parts.items()}
    if target_parts is None:
        target_parts = find_parts(target_vertices, target_triangles, target_landmarks)
    target_parts = _split_eyes(dict(target_parts), target_vertices, target_landmarks)

    units = {name: np.asarray(delta, np.float64) for name, delta in reference.units.items()}
    result = {name: np.zeros_like(target_vertices) for name in units}
    in_part = np.zeros(len(target_vertices), bool)
    for name, indices in target_parts.items():
        if len(indices) and name in reference_parts:
            in_part[indices] = True

    # Skin (and everything that is not a known part): each lip and lid samples only its own kind on
    # the reference, the rest of the skin the whole reference skin; the inside of the mouth follows
    # the teeth of its jaw.
    skin = np.flatnonzero(~in_part)
    reference_skin = reference_parts.get("skin", np.arange(len(reference_vertices)))
    height = scale * float(np.ptp(reference_vertices[reference_skin, 2]))

    # Parts are read in the reference's frame (face toward -Y, Z up), whatever the target's turn.
    def upright(points):
        return ((np.asarray(points, np.float64) - translation) @ rotation) / scale

    upright_vertices = upright(target_vertices)
    upright_landmarks = {name: upright(point) for name, point in target_landmarks.items()}
    target_face = find_face_parts(upright_vertices, target_triangles, skin, upright_landmarks)
    reference_face = _reference_face_parts(
        reference, tuple((name, tuple(map(float, point))) for name, point in reference_landmarks.items())
    )
    apart = np.zeros(len(target_vertices))  # each vertex's distance from the reference surface it samples
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
        apart[targets], corners, weights = _carry_by_closest_point(
            result, targets, target_vertices, placed, surface, sources, units, turn, height
        )
        if corners is not None:
            sampled[targets] = (reference_vertices[corners] * weights[:, :, None]).sum(1)
    _fade_behind_the_lids(result, target_face, upright_vertices, upright_landmarks, apart / scale)
    mouth_width = float(
        np.linalg.norm(target_landmarks["mouth_corner_left"] - target_landmarks["mouth_corner_right"])
    )
    # Where the reference's own mouth lies on the target's, its own motion is right; the jaw takes over
    # where the target's mouth goes deeper than the reference's.
    beyond = np.clip((apart - 0.02 * mouth_width) / (0.06 * mouth_width), 0.0, 1.0)
    _follow_the_jaw(
        result, skin, target_face, beyond, target_vertices, reference, units, scale, rotation, translation
    )
    eye_width = np.mean(
        [
            np.linalg.norm(target_landmarks[f"eye_outer_{side}"] - target_landmarks[f"eye_inner_{side}"])
            for side in ("left", "right")
        ]
    )
    target_edges, _ = edge_graph(len(target_vertices), target_triangles, target_vertices)
    _smooth_lids(result, target_face, target_edges, np.clip(apart / (LID_ROUGH * eye_width), 0, 1))
    _close_blinks_as_the_reference_does(
        result,
        target_face,
        upright_vertices,
        upright_landmarks,
        reference,
        reference_face,
        reference_landmarks,
        rotation,
        scale,
        sampled,
    )
    _ease_the_skin_above_the_lids(
        result, target_face, target_edges, upright_vertices, upright_landmarks, apart / eye_width
    )
    # The tongue bends (tongueOut): closest point on the reference tongue.
    for name in SOFT_PARTS:
        if name in target_parts and name in reference_parts and len(target_parts[name]):
            _carry_by_closest_point(
                result,
                np.asarray(target_parts[name]),
                target_vertices,
                placed,
                surface,
                reference_parts[name],
                units,
                turn,
                None,
            )
    # Teeth and eyes move as solids.
    for name in RIGID_PARTS:
        if name in target_parts and name in reference_parts and len(target_parts[name]):
            _carry_rigidly(
                result,
                np.asarray(target_parts[name]),
                target_vertices,
                reference_vertices[reference_parts[name]],
                {unit: delta[reference_parts[name]] for unit, delta in units.items()},
                scale,
                rotation,
                translation,
            )
    return result


@functools.lru_cache(maxsize=4)
def _reference_face_parts(reference, landmark_items) -> FaceParts:
    landmarks = {name: np.asarray(point) for name, point in landmark_items}
    return find_face_parts(
        np.asarray(reference.vertices, np.float64),
        triangulate(reference.polygons),
        np.asarray(reference.parts.get("skin", np.arange(len(reference.vertices)))),
        landmarks,
    )


def _fade_behind_the_lids(result, face, upright_vertices, upright_landmarks, apart) -> None:
    """The lining of an eye socket, deeper than the eye's corners and away from the reference surface,
    stays still: sampling the reference's nearest lid there would fold the lid over the eyeball."""
    for side in ("left", "right"):
        inner, outer = upright_landmarks[f"eye_inner_{side}"], upright_landmarks[f"eye_outer_{side}"]
        eye_width = float(np.linalg.norm(outer - inner))
        lids = np.isin(
            face.label, [PART_LABELS.index(f"upper_lid_{side}"), PART_LABELS.index(f"lower_lid_{side}")]
        )
        lids = np.flatnonzero(lids)
        behind = upright_vertices[lids, 1] - 0.5 * (inner[1] + outer[1])
        keep = np.clip(
            1.0 - (behind - LID_FADE_NEAR * eye_width) / ((LID_FADE_FAR - LID_FADE_NEAR) * eye_width), 0, 1
        )
        keep = np.maximum(keep, apart[lids] < LID_FADE_NEAR * eye_width)
        for deltas in result.values():
            deltas[lids] *= keep[:, None]


def _close_blinks_as_the_reference_does(
    result,
    face,
    upright_vertices,
    upright_landmarks,
    reference,
    reference_face,
    reference_landmarks,
    rotation,
    scale,
    sampled,
) -> None:
    """Scale each blink's lid motion so the target's lids travel the same share of their opening as the
    reference's do: an eye narrower than the reference's closes without one lid passing through the
    other, a wider one closes all the way. The openings are measured at the middle of each eye."""
    reference_vertices = np.asarray(reference.vertices, np.float64)
    for side in ("left", "right"):
        unit = f"eyeBlink{side.capitalize()}"
        if unit not in result:
            continue
        _unfold_the_upper_lid(
            result[unit], upright_vertices, upright_landmarks, sampled, reference_landmarks, side
        )
        shares = []
        for vertices, parts, landmarks, deltas in (
            (upright_vertices, face, upright_landmarks, result[unit] @ rotation / scale),
            (
                reference_vertices,
                reference_face,
                reference_landmarks,
                np.asarray(reference.units[unit], np.float64),
            ),
        ):
            lids = [
                np.flatnonzero(parts.seen & (parts.label == PART_LABELS.index(f"{lid}_lid_{side}")))
                for lid in ("upper", "lower")
            ]
            middle = 0.5 * (landmarks[f"eye_inner_{side}"][0] + landmarks[f"eye_outer_{side}"][0])
            rest = opening_gap(vertices, np.zeros_like(vertices), *lids, middle)
            closed = opening_gap(vertices, deltas, *lids, middle)
            shares.append((rest - closed) / rest if rest > 0 else np.nan)
        if not np.all(np.isfinite(shares)) or shares[0] <= 0:
            continue
        lids = np.flatnonzero(
            np.isin(face.label, [PART_LABELS.index(f"{lid}_lid_{side}") for lid in ("upper", "lower")])
        )
        result[unit][lids] *= float(np.clip(shares[1] / shares[0], 0.5, 1.5))


def _ease_the_skin_above_the_lids(result, face, edges, upright_vertices, upright_landmarks, apart) -> None:
    """Smooth each blink's motion of the skin above its upper lid's margin (BLINK_EASE_*): the margin,
    the lower lid and the lid's corners keep their motion, so the lids close as far as before. apart:
    each vertex's distance from the reference surface it sampled, in eye widths; the smoothing counts
    in full where that region lies BLINK_EASE_APART apart (median), not at all where the surfaces
    coincide (the reference onto itself keeps its own blink)."""
    for side, other in (("left", "right"), ("right", "left")):
        unit = f"eyeBlink{side.capitalize()}"
        names = (f"eye_inner_{side}", f"eye_outer_{side}", f"upper_lid_{side}")
        if unit not in result or not all(name in upright_landmarks for name in names):
            continue  # landmarks from a head's own keys mark the corners only: the margin is unknown
        inner, outer, margin = (np.asarray(upright_landmarks[name], np.float64) for name in names)
        centre, eye_width = (inner + outer) / 2, float(np.linalg.norm(outer - inner))
        distance = np.linalg.norm(upright_vertices - centre, axis=1)
        other_centre = (upright_landmarks[f"eye_inner_{other}"] + upright_landmarks[f"eye_outer_{other}"]) / 2
        movable = (
            (face.label >= 0)
            & (face.label != PART_LABELS.index(f"lower_lid_{side}"))
            & (upright_vertices[:, 2] > margin[2])
            & (distance < BLINK_EASE_REACH * eye_width)
            & (distance < np.linalg.norm(upright_vertices - other_centre, axis=1))
            & np.any(result[unit] != 0, axis=1)
        )
        if not movable.any():
            continue
        near = movable[edges[:, 0]] | movable[edges[:, 1]]  # the region and the ring that holds it
        smoothed = smooth_over_edges(result[unit], edges[near], movable, BLINK_EASE_SWEEPS)
        weight = min(float(np.median(apart[movable])) / BLINK_EASE_APART, 1.0)
        result[unit] = (1 - weight) * result[unit] + weight * smoothed


def _unfold_the_upper_lid(deltas, upright_vertices, upright_landmarks, sampled, reference_landmarks, side):
    """A closing upper lid unrolls from under its crease: the margin travels the whole way, the skin above
    it less the higher it sits. Where the registration lets a vertex high above the target's margin sample
    the reference's lid nearer its margin (a deep crease, a fold hanging over the eye), the vertex takes
    the travel of its own height in the eye's frame: the reference's motion, falling off over
    LID_UNFOLD_LENGTH for each eye width it sits higher than its sample. On the reference itself nothing
    changes. Vitruvian: cosine to the artist's blink 0.63 -> 0.71, stretch 3.7 -> 3.4."""
    names = (f"eye_inner_{side}", f"eye_outer_{side}", f"upper_lid_{side}")
    if not all(name in upright_landmarks and name in reference_landmarks for name in names):
        return  # landmarks from a head's own keys mark the corners only: the margin is unknown

    def height_above_margin(points, landmarks, rows):
        inner, outer, margin = (np.asarray(landmarks[name], np.float64) for name in names)
        return np.maximum(points[rows, 2] - margin[2], 0.0) / float(np.linalg.norm(outer - inner))

    inner, outer = upright_landmarks[names[0]], upright_landmarks[names[1]]
    # The lid and the skin around it that the lid labels may not reach (a fold hanging over the eye).
    near = np.flatnonzero(
        np.abs(upright_vertices[:, 0] - 0.5 * (inner[0] + outer[0])) < np.linalg.norm(outer - inner)
    )
    higher = height_above_margin(upright_vertices, upright_landmarks, near) - height_above_margin(
        sampled, reference_landmarks, near
    )
    deltas[near] *= np.exp(-np.maximum(higher, 0.0) / LID_UNFOLD_LENGTH)[:, None]


def _smooth_lids(result, face, edges, unreliable) -> None:
    """Smooth each lid's deltas along its own edges only (never across the lid line between the corners),
    where the reference surface lies apart from the target's and its samples are rough: a blink then
    closes the lid as a sheet instead of creasing it. Where the surfaces coincide (unreliable 0) the
    sampled deltas stand. (Smoothing the lips this way pulled their corners apart: measured.)"""
    is_lid = face.label >= PART_LABELS.index("upper_lid_left")
    labelled = np.flatnonzero(is_lid & (unreliable > 0))
    if len(labelled) == 0:
        return
    first, second = face.label[edges[:, 0]], face.label[edges[:, 1]]
    same = (first == second) & is_lid[edges[:, 0]]
    # Beside the eye's corners, where the lids meet (neither side sure), the two lids of an eye blend.
    eye_of = np.full(len(PART_LABELS), -1)
    for eye, side in enumerate(("left", "right")):
        eye_of[[PART_LABELS.index(f"upper_lid_{side}"), PART_LABELS.index(f"lower_lid_{side}")]] = eye
    same_eye = (eye_of[first] >= 0) & (eye_of[first] == eye_of[second])
    same |= same_eye & ~(face.sure[edges[:, 0]] & face.sure[edges[:, 1]])
    edges = edges[same]
    local = np.full(len(face.label), -1)
    region = np.unique(np.concatenate((labelled, edges.ravel())))
    local[region] = np.arange(len(region))
    names = [name for name in result if np.any(result[name][region])]  # most units leave the lids be
    if not names:
        return
    stacked = np.concatenate([result[name][region] for name in names], axis=1)
    smoothed = smooth_over_edges(stacked, local[edges], np.ones(len(region), bool), SMOOTHING_SWEEPS)
    weight = unreliable[region][:, None]
    blended = (1 - weight) * stacked + weight * smoothed
    for index, name in enumerate(names):
        result[name][region] = blended[:, 3 * index : 3 * index + 3]


def _follow_the_jaw(
    result, skin, face, beyond, target_vertices, reference, units, scale, rotation, translation
):
    """Blend the inside of the mouth (bag, gums, teeth and tongue joined to the skin) toward the rigid
    motion of the reference's teeth, the lower teeth's below the lips and the upper teeth's above."""
    if "upper_teeth" not in reference.parts or "lower_teeth" not in reference.parts:
        return
    targets = skin[face.inside_mouth[skin] > 0]
    if len(targets) == 0:
        return
    weight = (face.inside_mouth[targets] * beyond[targets])[:, None]
    lower = face.lower_jaw[targets][:, None]
    in_reference = ((target_vertices[targets] - translation) @ rotation) / scale
    reference_vertices = np.asarray(reference.vertices, np.float64)
    for name, delta in units.items():
        rigid = np.zeros_like(in_reference)
        for teeth, share in (("upper_teeth", 1 - lower), ("lower_teeth", lower)):
            points = reference_vertices[reference.parts[teeth]]
            part_delta = delta[reference.parts[teeth]]
            if np.any(part_delta):
                turn, shift = rigid_fit(points, points + part_delta)
                rigid += share * (in_reference @ turn.T + shift - in_reference)
        result[name][targets] = (1 - weight) * result[name][targets] + weight * scale * rigid @ rotation.T


def _split_eyes(parts: dict, vertices: np.ndarray, landmarks: Mapping[str, np.ndarray]) -> dict:
    """Accept both eyes as one part ("eyes") and split them at the nose: left is +X."""
    eyes = parts.pop("eyes", None)
    if eyes is not None and len(eyes):
        eyes = np.asarray(eyes)
        middle = np.asarray(landmarks["nose_tip"])[0] if "nose_tip" in landmarks else vertices[eyes, 0].mean()
        left = vertices[eyes, 0] >= middle
        parts.setdefault("left_eye", eyes[left])
        parts.setdefault("right_eye", eyes[~left])
    return parts


def _carry_by_closest_point(
    result, targets, target_vertices, placed, surface, reference_indices, units, turn, height
):
    """Deltas at the closest reference point, interpolated over its triangle, turned and scaled.

    surface: (triangles, triangles_around of them) of the placed reference. Returns the distances and
    the sampled triangles' corners with their barycentric weights (None, None when nothing was sampled).
    """
    triangles, around = surface
    keep = np.zeros(len(placed), bool)
    keep[reference_indices] = True
    allowed = keep[triangles].all(1)
    if not allowed.any() or len(targets) == 0:
        return np.zeros(len(targets)), None, None
    triangle, weights, distance = closest_points(target_vertices[targets], placed, triangles, allowed, around)
    corners = triangles[triangle]
    if height is None:
        fade = np.ones(len(targets))
    else:
        fade = np.clip((FALLOFF_FAR * height - distance) / ((FALLOFF_FAR - FALLOFF_NEAR) * height), 0, 1)
    faded = weights * fade[:, None]
    for name, delta in units.items():
        local = (delta[corners] * faded[:, :, None]).sum(1)
        result[name][targets] = local @ turn.T
    return distance, corners, weights


def _carry_rigidly(
    result, targets, target_vertices, reference_points, part_units, scale, rotation, translation
):
    """Each unit's motion of a reference part as a rotation about the part's centre plus a shift.

    The rotation turns the target part about its own centre (in the reference frame), so a part the
    landmarks placed a little off still turns in place instead of swinging around the reference's.
    """
    target_in_reference = ((target_vertices[targets] - translation) @ rotation) / scale
    target_centre = target_in_reference.mean(0)
    reference_centre = reference_points.mean(0)
    for name, delta in part_units.items():
        if not np.any(delta):
            continue
        turn, shift = rigid_fit(reference_points, reference_points + delta)
        centre_motion = turn @ reference_centre + shift - reference_centre
        moved = (target_in_reference - target_centre) @ turn.T + target_centre + centre_motion
        result[name][targets] = scale * (moved - target_in_reference) @ rotation.T
