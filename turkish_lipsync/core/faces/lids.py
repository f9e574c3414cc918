"""The lids under a transfer: a blink closes as a sheet, as far as the reference's does, unrolling from
under the crease without creasing the skin above; the socket's lining stays still.

Each pass works on the deltas the closest-point transfer sampled, read in the reference's frame (face
toward -Y, Z up) whatever the target's turn.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from .parts import PART_LABELS, FaceParts, opening_gap
from .registration import Placement
from .topology import smooth_over_edges

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


@dataclass(frozen=True)
class LidFrame:
    """The target's and the reference's faces as the lid passes read them: in the reference's frame."""

    face: FaceParts  # the target's lips and lids
    vertices: np.ndarray  # the target's vertices in the reference's frame
    landmarks: Mapping[str, np.ndarray]  # the target's landmarks in the reference's frame
    reference: object  # the ReferenceHead
    reference_face: FaceParts
    reference_landmarks: Mapping[str, np.ndarray]


def fade_behind_the_lids(result, frame: LidFrame, apart) -> None:
    """The lining of an eye socket, deeper than the eye's corners and away from the reference surface,
    stays still: sampling the reference's nearest lid there would fold the lid over the eyeball."""
    face, upright_vertices, upright_landmarks = frame.face, frame.vertices, frame.landmarks
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


def behind_the_lids(frame: LidFrame) -> np.ndarray:
    """Per vertex: the lids' skin deeper than LID_FADE_NEAR eye widths behind the eye's corners (the
    socket's lining, which stays still), not a place for lashes or shells to ride."""
    inside = np.zeros(len(frame.vertices), bool)
    for side in ("left", "right"):
        inner, outer = frame.landmarks[f"eye_inner_{side}"], frame.landmarks[f"eye_outer_{side}"]
        eye_width = float(np.linalg.norm(outer - inner))
        lids = np.isin(
            frame.face.label, [PART_LABELS.index(f"upper_lid_{side}"), PART_LABELS.index(f"lower_lid_{side}")]
        )
        inside |= lids & (frame.vertices[:, 1] - 0.5 * (inner[1] + outer[1]) > LID_FADE_NEAR * eye_width)
    return inside


def close_blinks_as_the_reference_does(result, frame: LidFrame, placement: Placement, sampled) -> None:
    """Scale each blink's lid motion so the target's lids travel the same share of their opening as the
    reference's do: an eye narrower than the reference's closes without one lid passing through the
    other, a wider one closes all the way. The openings are measured at the middle of each eye."""
    face, upright_vertices, upright_landmarks = frame.face, frame.vertices, frame.landmarks
    reference, reference_face, reference_landmarks = (
        frame.reference,
        frame.reference_face,
        frame.reference_landmarks,
    )
    reference_vertices = np.asarray(reference.vertices, np.float64)
    for side in ("left", "right"):
        unit = f"eyeBlink{side.capitalize()}"
        if unit not in result:
            continue
        _unfold_the_upper_lid(result[unit], frame, sampled, side)
        shares = []
        for vertices, parts, landmarks, deltas in (
            (upright_vertices, face, upright_landmarks, placement.deltas_to_reference(result[unit])),
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


def ease_the_skin_above_the_lids(result, frame: LidFrame, edges, apart) -> None:
    """Smooth each blink's motion of the skin above its upper lid's margin (BLINK_EASE_*): the margin,
    the lower lid and the lid's corners keep their motion, so the lids close as far as before. apart:
    each vertex's distance from the reference surface it sampled, in eye widths; the smoothing counts
    in full where that region lies BLINK_EASE_APART apart (median), not at all where the surfaces
    coincide (the reference onto itself keeps its own blink)."""
    face, upright_vertices, upright_landmarks = frame.face, frame.vertices, frame.landmarks
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


def _unfold_the_upper_lid(deltas, frame: LidFrame, sampled, side):
    """A closing upper lid unrolls from under its crease: the margin travels the whole way, the skin above
    it less the higher it sits. Where the registration lets a vertex high above the target's margin sample
    the reference's lid nearer its margin (a deep crease, a fold hanging over the eye), the vertex takes
    the travel of its own height in the eye's frame: the reference's motion, falling off over
    LID_UNFOLD_LENGTH for each eye width it sits higher than its sample. On the reference itself nothing
    changes. Vitruvian: cosine to the artist's blink 0.63 -> 0.71, stretch 3.7 -> 3.4."""
    upright_vertices, upright_landmarks, reference_landmarks = (
        frame.vertices,
        frame.landmarks,
        frame.reference_landmarks,
    )
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


def smooth_lids(result, face: FaceParts, edges, unreliable) -> None:
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
