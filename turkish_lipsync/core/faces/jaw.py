"""The inside of the mouth under a transfer: the upper teeth and gums stay with the skull, the lower teeth,
gums and tongue go with the jaw.

Each unit's motion of the reference's upper and lower teeth is fitted as a rigid motion. The skin's own
mouth bag blends the two by how deep inside the mouth it lies; a piece that reaches both jaws (gums and
tongue in one island, both rows of teeth joined) is divided vertex by vertex: grown over its own edges
from its front above the bite and its front below it, what the lower front reaches first goes with the
jaw (the tongue joins the lower gums at the floor of the mouth, the upper gums only round the back), and
its tongue, nearer the reference's tongue than its teeth, bends as the reference's tongue does.
"""

from __future__ import annotations

import functools

import numpy as np

from .carry import TransferJob, carry_by_closest_point
from .closest import nearest_vertices
from .registration import rigid_fit
from .topology import edge_graph, geodesic_distance, smooth_over_edges

# A mixed piece's seeds: its vertices within this many mouth widths behind the lips' front, and as far
# as a tenth of this above or below the bite.
SEED_FRONT = 0.35
SEED_HEIGHT = 0.08
# Sweeps of neighbour averaging that blend the two jaws (and the tongue) where they meet in one piece.
BLEND_SWEEPS = 8


def rigid_jaw_motion(job: TransferJob, in_reference: np.ndarray, lower: np.ndarray, unit: str) -> np.ndarray:
    """The target's deltas of points (in the reference's frame) moved by the reference's upper teeth's
    rigid motion (lower 0) or the lower teeth's (lower 1), blended by `lower`."""
    reference = job.reference
    reference_vertices = np.asarray(reference.vertices, np.float64)
    rigid = np.zeros_like(in_reference)
    for teeth, share in (("upper_teeth", 1 - lower), ("lower_teeth", lower)):
        points = reference_vertices[reference.parts[teeth]]
        part_delta = job.units[unit][reference.parts[teeth]]
        if np.any(part_delta):
            turn, shift = rigid_fit(points, points + part_delta)
            rigid += share[:, None] * (in_reference @ turn.T + shift - in_reference)
    return job.placement.deltas_to_target(rigid)


def follow_the_jaw(job: TransferJob, result, skin, face, beyond, in_reference) -> None:
    """Blend the inside of the mouth (bag, gums, teeth and tongue joined to the skin) toward the rigid
    motion of the reference's teeth, the lower teeth's below the lips and the upper teeth's above."""
    if not _has_teeth(job.reference):
        return
    targets = skin[face.inside_mouth[skin] > 0]
    if len(targets) == 0:
        return
    weight = (face.inside_mouth[targets] * beyond[targets])[:, None]
    lower = face.lower_jaw[targets]
    for name in job.units:
        rigid = rigid_jaw_motion(job, in_reference[targets], lower, name)
        result[name][targets] = (1 - weight) * result[name][targets] + weight * rigid


def carry_mouth_pieces(job: TransferJob, result, pieces: list[np.ndarray]) -> dict[str, np.ndarray]:
    """Each piece reaching both jaws moved vertex by vertex; returns, for the report, the vertices of
    all such pieces that went with the lower jaw, stayed with the upper, and bent as the tongue."""
    shares = {"lower": [], "upper": [], "tongue": []}
    if not _has_teeth(job.reference):
        return {}
    for piece in pieces:
        lower, tongue = _jaw_shares(job, piece)
        in_reference = job.placement.to_reference(job.vertices[piece])
        bent = {name: np.zeros_like(job.vertices) for name in job.units}
        if tongue.any() and "tongue" in job.reference.parts:
            carry_by_closest_point(job, bent, piece, job.reference.parts["tongue"], None)
        for name in job.units:
            rigid = rigid_jaw_motion(job, in_reference, lower, name)
            result[name][piece] = (1 - tongue[:, None]) * rigid + tongue[:, None] * bent[name][piece]
        shares["lower"].append(piece[(lower >= 0.5) & (tongue < 0.5)])
        shares["upper"].append(piece[lower < 0.5])
        shares["tongue"].append(piece[tongue >= 0.5])
    return {name: np.concatenate(found) for name, found in shares.items() if found}


def _jaw_shares(job: TransferJob, piece: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(lower, tongue) per vertex of a piece, 0..1: how far it goes with the lower jaw, and bends as the
    tongue does."""
    placement = job.placement
    upright = placement.to_reference(job.vertices[piece])
    marks = {name: placement.to_reference(point) for name, point in job.landmarks.items()}
    mouth_width = job.mouth_width() / placement.scale
    lips_front = min(marks["upper_lip"][1], marks["lower_lip"][1])
    bite = upright[:, 2] - _bite_height(job.reference)(upright[:, 1])
    front = upright[:, 1] - lips_front < SEED_FRONT * mouth_width
    local = np.full(len(job.vertices), -1, np.int64)
    local[piece] = np.arange(len(piece))
    own = job.triangles[(local[job.triangles] >= 0).all(1)]
    edges, lengths = edge_graph(len(job.vertices), own, job.vertices)
    edges = local[edges]
    everywhere = np.ones(len(piece), bool)
    upper_seeds = np.flatnonzero(front & (bite > SEED_HEIGHT * mouth_width))
    lower_seeds = np.flatnonzero(front & (bite < -SEED_HEIGHT * mouth_width))
    to_upper = geodesic_distance(len(piece), edges, lengths, upper_seeds, everywhere)
    to_lower = geodesic_distance(len(piece), edges, lengths, lower_seeds, everywhere)
    lower = np.where(np.isfinite(to_lower) | np.isfinite(to_upper), to_lower < to_upper, bite < 0)
    lower = smooth_over_edges(lower.astype(np.float64), edges, everywhere, BLEND_SWEEPS)
    tongue = np.zeros(len(piece))
    if "tongue" in job.reference.parts:
        behind = ~front & (lower > 0.5)
        nearer = _nearer_the_tongue(job, piece[behind])
        tongue[np.flatnonzero(behind)[nearer]] = 1.0
        tongue = smooth_over_edges(tongue, edges, everywhere, BLEND_SWEEPS)
    return lower, tongue


def _nearer_the_tongue(job: TransferJob, targets: np.ndarray) -> np.ndarray:
    """Which of the targets lie nearer the placed reference's tongue than its lower teeth."""
    placed = job.placement.placed
    points = job.vertices[targets]
    tongue, teeth = (
        nearest_vertices(points, placed[job.reference.parts[part]])[1] for part in ("tongue", "lower_teeth")
    )
    return tongue < teeth


@functools.lru_cache(maxsize=4)
def _bite_height(reference):
    """z of the bite (between the upper teeth's lowest points and the lower teeth's highest) as a line
    over depth, in the reference's frame: the plane that tells the upper jaw from the lower."""
    vertices = np.asarray(reference.vertices, np.float64)
    upper, lower = vertices[reference.parts["upper_teeth"]], vertices[reference.parts["lower_teeth"]]
    edges = np.linspace(
        max(upper[:, 1].min(), lower[:, 1].min()), min(upper[:, 1].max(), lower[:, 1].max()), 6
    )
    depths, heights = [], []
    for start, stop in zip(edges[:-1], edges[1:], strict=True):
        above = upper[(upper[:, 1] >= start) & (upper[:, 1] <= stop), 2]
        below = lower[(lower[:, 1] >= start) & (lower[:, 1] <= stop), 2]
        if len(above) and len(below):
            depths.append(0.5 * (start + stop))
            heights.append(0.5 * (above.min() + below.max()))
    slope, intercept = np.polyfit(depths, heights, 1) if len(depths) >= 2 else (0.0, np.mean(heights))

    def height(depth):
        return intercept + slope * np.asarray(depth, np.float64)

    return height


def _has_teeth(reference) -> bool:
    return "upper_teeth" in reference.parts and "lower_teeth" in reference.parts
