"""Pieces that ride the skin they touch: lashes on the lid margin, eye shells and tear lines on the lids,
brows as cards, a beard, hair.

A piece touches the skin along its base (its vertices nearest the skin: a lash card's root row, a
shell's rim); every vertex of the piece takes the base vertex nearest it along the piece's own edges, so
a lash card is carried column by column, each lash rigidly. That base vertex's nearest skin vertex is
its anchor: the vertex moves as the skin around the anchor does (the anchor's motion, and the turn of
the skin within two edges of it, fitted as a rotation), so a lash tip swings with a closing lid instead
of staying open through it. An eye's lashes and shells turn instead about the eyeball's centre, as the
lid they grow from slides over the eyeball (the way rigs carry lashes): on the reference head, whose
artist made its lashes' motion, both ways agree with it at cosine 0.99 under its blink; on Vitruvian's
artist blink, whose lid margin slides down more than its skin turns, the fitted turn left the lash tips
a third of the way open.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .closest import closest_points, nearest_vertices
from .topology import edge_graph, nearest_seed, smooth_over_edges, unique_pairs

# A piece's base: its vertices within this many eye widths of its nearest approach to the skin.
BASE_TOLERANCE = 0.015
# A vertex of a piece that is not rooted (not a lash) rides the skin itself where it lies this close.
TOUCH = 0.06
# Sweeps of neighbour averaging over a riding sheet's own edges.
SHEET_SWEEPS = 10
# A vertex this far along its piece from the skin it rides (eye widths) rides it fully, twice as far not
# at all: a lash or a shell is carried whole, a garment hanging far from the face is not.
ALONG_NEAR = 0.5
ALONG_FAR = 1.0
# A piece whose base lies this far from the skin (eye widths) rides it fully; twice as far, not at all
# (a hat brim, a helmet floating over the head).
RIDE_NEAR = 0.1
RIDE_FAR = 0.2


def carry_riders(
    result: dict[str, np.ndarray],
    vertices: np.ndarray,
    triangles: np.ndarray,
    pieces: list[np.ndarray],
    anchorable: np.ndarray,
    eye_width: float,
    pivots: list[np.ndarray | None] | None = None,
    rooted: list[bool] | None = None,
) -> None:
    """Write each rider piece's motion into result (unit -> (N, 3) deltas that already hold the skin's).

    anchorable: the skin vertices a piece may ride (the skin, less the socket's still lining). pivots:
    per piece, the centre of the eyeball it turns about (an eye's lashes and shells), or None (it turns
    as the skin around its anchor does). rooted: per piece, whether it grows from its base only (lashes:
    the whole lash follows its root, even where it lies along the lid); the other pieces' vertices that
    touch the skin (within TOUCH eye widths) ride it where they touch (a shell's rim under each lid, a
    brow card lying on the brow).
    """
    pivots = pivots or [None] * len(pieces)
    rooted = rooted or [False] * len(pieces)
    pivots = [pivot for piece, pivot in zip(pieces, pivots, strict=True) if len(piece)]
    rooted = np.array([root for piece, root in zip(pieces, rooted, strict=True) if len(piece)], bool)
    pieces = [np.asarray(piece, np.int64) for piece in pieces if len(piece)]
    if not pieces or len(anchorable) == 0:
        return
    riding = _riding(vertices, triangles, pieces, anchorable, eye_width, pivots, rooted)
    if riding is None:
        return
    for deltas in result.values():
        if np.any(deltas[riding.around]):
            riding.carry(vertices, deltas)


@dataclass(frozen=True, eq=False)
class _Riding:
    """The rider vertices that ride the skin, and where: each rides its base's closest point of the skin
    (corners and weights), turning as the skin within two edges of its anchor does, or about a pivot."""

    riders: np.ndarray
    fade: np.ndarray  # how fully each rides (1 near the skin, fading with distance)
    corners: np.ndarray  # (R, 3) the skin triangle's corners under each rider's base
    weights: np.ndarray  # (R, 3) barycentric weights of the base's closest point
    anchor_points: np.ndarray
    offset: np.ndarray  # each rider from its anchor point
    centres: np.ndarray  # per rider: the eyeball's centre it turns about (NaN: it turns with the skin)
    neighbourhood: np.ndarray  # (anchor number, skin vertex) pairs within two edges of each anchor
    anchor_count: int
    which: np.ndarray  # per rider: its anchor's number
    around: np.ndarray  # the skin vertices whose motion moves a rider
    sheets: np.ndarray  # the riders that ride where they touch (shells, tear lines, brow cards)
    sheet_edges: np.ndarray  # their own edges (indices into sheets)

    def carry(self, vertices: np.ndarray, deltas: np.ndarray) -> None:
        """Write the riders' motion under one key into its deltas."""
        motion = (deltas[self.corners] * self.weights[:, :, None]).sum(1)
        turns = _turns(vertices, deltas, self.neighbourhood, self.anchor_count)[self.which]
        pivoting = np.isfinite(self.centres[:, 0])
        if pivoting.any():
            before = self.anchor_points[pivoting] - self.centres[pivoting]
            turns[pivoting] = _turns_between(before, before + motion[pivoting])
        turned = np.einsum("nij,nj->ni", turns - np.eye(3), self.offset)
        deltas[self.riders] = self.fade[:, None] * (motion + turned)
        if len(self.sheets):
            # Sheets are smoothed over their own edges: neighbours riding different places (a shell's
            # rim under the lid, the next row on the lining) would tear them.
            movable = np.ones(len(self.sheets), bool)
            deltas[self.sheets] = smooth_over_edges(
                deltas[self.sheets], self.sheet_edges, movable, SHEET_SWEEPS
            )


def _riding(vertices, triangles, pieces, anchorable, eye_width, pivots, rooted) -> _Riding | None:
    """Which rider vertices ride the skin, how fully and where; None where none does."""
    riders = np.concatenate(pieces)
    piece_of = np.repeat(np.arange(len(pieces)), [len(piece) for piece in pieces])
    reach = RIDE_FAR * eye_width
    corners, weights, distance = _closest_skin(vertices, triangles, anchorable, vertices[riders], reach)
    closest = np.full(len(pieces), np.inf)
    np.minimum.at(closest, piece_of, distance)
    base = np.isfinite(distance) & (distance <= closest[piece_of] + BASE_TOLERANCE * eye_width)
    base |= ~rooted[piece_of] & (distance <= TOUCH * eye_width)
    fade = np.clip((reach - closest) / ((RIDE_FAR - RIDE_NEAR) * eye_width), 0.0, 1.0)[piece_of]
    along, owner = _nearest_base(vertices, triangles, riders, base)
    fade = fade * np.clip((ALONG_FAR * eye_width - along) / ((ALONG_FAR - ALONG_NEAR) * eye_width), 0, 1)
    keep = (owner >= 0) & (fade > 0)
    if not keep.any():
        return None
    riders, owner, fade, piece_of = riders[keep], owner[keep], fade[keep], piece_of[keep]
    corners, weights = corners[owner], weights[owner]  # each vertex rides its base's point of the skin
    anchors = corners[np.arange(len(corners)), np.argmax(weights, axis=1)]
    distinct, which = np.unique(anchors, return_inverse=True)
    neighbourhood = _two_rings(vertices, triangles, anchorable, distinct)
    anchor_points = (vertices[corners] * weights[:, :, None]).sum(1)
    sheets = riders[~rooted[piece_of]]
    return _Riding(
        riders=riders,
        fade=fade,
        corners=corners,
        weights=weights,
        anchor_points=anchor_points,
        offset=vertices[riders] - anchor_points,
        centres=np.array([np.full(3, np.nan) if pivot is None else pivot for pivot in pivots])[piece_of],
        neighbourhood=neighbourhood,
        anchor_count=len(distinct),
        which=which,
        around=np.unique(np.concatenate((neighbourhood[:, 1], corners.ravel()))),
        sheets=sheets,
        sheet_edges=_own_edges(vertices, triangles, sheets)[0],
    )


def _own_edges(
    vertices: np.ndarray, triangles: np.ndarray, piece: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The edges of the triangles among a piece's vertices (as indices into the piece), and their lengths."""
    local = np.full(len(vertices), -1, np.int64)
    local[piece] = np.arange(len(piece))
    own = triangles[(local[triangles] >= 0).all(1)]
    edges, lengths = edge_graph(len(vertices), own, vertices)
    return local[edges], lengths


def _closest_skin(vertices, triangles, anchorable, points, reach):
    """(corners (P, 3), barycentric weights (P, 3), distance) of each point's closest point on the skin
    (the triangles of anchorable vertices), for points within reach of a skin vertex; inf beyond."""
    corners = np.zeros((len(points), 3), np.int64)
    weights = np.zeros((len(points), 3))
    distance = np.full(len(points), np.inf)
    _, near = nearest_vertices(points, vertices[anchorable], reach)
    within = np.isfinite(near)
    if not within.any():
        return corners, weights, distance
    on_skin = np.zeros(len(vertices), bool)
    on_skin[anchorable] = True
    skin = triangles[on_skin[triangles].all(1)]
    low, high = points[within].min(0) - 2 * reach, points[within].max(0) + 2 * reach
    nearby = skin[np.all((vertices[skin] >= low) & (vertices[skin] <= high), axis=(1, 2))]
    if len(nearby) == 0:
        return corners, weights, distance
    used, local = np.unique(nearby, return_inverse=True)
    local = local.reshape(-1, 3)
    triangle, found, gap = closest_points(points[within], vertices[used], local)
    corners[within] = used[local[triangle]]
    weights[within], distance[within] = found, gap
    return corners, weights, distance


def _nearest_base(vertices, triangles, riders, base) -> np.ndarray:
    """For each rider vertex, the distance along the pieces' own edges to the base vertex nearest it, and
    that vertex (an index into riders; -1 where no edge joins it to a base)."""
    edges, lengths = _own_edges(vertices, triangles, riders)
    return nearest_seed(len(riders), edges, lengths, np.flatnonzero(base), np.ones(len(riders), bool))


def _two_rings(vertices, triangles, anchorable, anchors) -> np.ndarray:
    """(P, 2) pairs (anchor number, skin vertex) of the skin within two edges of each anchor."""
    on_skin = np.zeros(len(vertices), bool)
    on_skin[anchorable] = True
    edges, _ = edge_graph(len(vertices), triangles[on_skin[triangles].all(1)], vertices)
    both = np.concatenate((edges, edges[:, ::-1]))
    both = both[np.argsort(both[:, 0], kind="stable")]
    first = np.searchsorted(both[:, 0], np.arange(len(vertices) + 1))
    pairs = np.stack((np.arange(len(anchors)), anchors), 1)
    for _ in range(2):
        counts = first[pairs[:, 1] + 1] - first[pairs[:, 1]]
        offsets = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
        reached = both[np.repeat(first[pairs[:, 1]], counts) + offsets, 1]
        pairs = unique_pairs(np.concatenate((pairs, np.stack((np.repeat(pairs[:, 0], counts), reached), 1))))
    return pairs


def _turns(vertices, deltas, pairs, count) -> np.ndarray:
    """(count, 3, 3) the rotation best fitting each neighbourhood's motion (Kabsch); the identity where
    a neighbourhood is too thin to say (fewer than three points off one line) or does not move."""
    group = pairs[:, 0]
    rest = vertices[pairs[:, 1]]
    moved = rest + deltas[pairs[:, 1]]
    size = np.bincount(group, minlength=count).astype(np.float64)[:, None]
    rest_centre = np.stack([np.bincount(group, rest[:, axis], count) for axis in range(3)], 1) / size
    moved_centre = np.stack([np.bincount(group, moved[:, axis], count) for axis in range(3)], 1) / size
    rest_local, moved_local = rest - rest_centre[group], moved - moved_centre[group]
    covariance = np.zeros((count, 3, 3))
    spread = np.zeros((count, 3, 3))
    np.add.at(covariance, group, moved_local[:, :, None] * rest_local[:, None, :])
    np.add.at(spread, group, rest_local[:, :, None] * rest_local[:, None, :])
    u, _, vt = np.linalg.svd(covariance)
    sign = np.sign(np.linalg.det(u @ vt))
    u[:, :, 2] *= np.where(sign == 0, 1.0, sign)[:, None]
    turns = u @ vt
    extent = np.linalg.svd(spread, compute_uv=False)
    thin = extent[:, 1] <= 1e-6 * np.maximum(extent[:, 0], 1e-300)
    still = np.bincount(group, np.any(deltas[pairs[:, 1]] != 0, axis=1), count) == 0
    turns[thin | still] = np.eye(3)  # exactly: a rider on skin that does not move stays where it is
    return turns


def _turns_between(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """(n, 3, 3) the smallest rotations turning each direction of first onto second (Rodrigues)."""
    a = first / np.maximum(np.linalg.norm(first, axis=1, keepdims=True), 1e-300)
    b = second / np.maximum(np.linalg.norm(second, axis=1, keepdims=True), 1e-300)
    axis = np.cross(a, b)
    sine = np.linalg.norm(axis, axis=1)
    cosine = np.clip((a * b).sum(1), -1.0, 1.0)
    axis = axis / np.maximum(sine, 1e-300)[:, None]
    cross = np.zeros((len(a), 3, 3))
    cross[:, 0, 1], cross[:, 0, 2], cross[:, 1, 2] = -axis[:, 2], axis[:, 1], -axis[:, 0]
    cross -= cross.transpose(0, 2, 1)
    turns = np.eye(3) + sine[:, None, None] * cross + (1 - cosine)[:, None, None] * cross @ cross
    turns[sine < 1e-12] = np.eye(3)
    return turns


def keep_under_the_skin(
    result: dict[str, np.ndarray],
    vertices: np.ndarray,
    shell: np.ndarray,
    skin: np.ndarray,
    centre,
    gap: float,
) -> None:
    """Hold a shell over an eyeball (an occlusion shell, a tear line) behind the skin that covers it: a
    shell vertex that a key carries out past the moved skin in its direction from the eyeball's centre
    is drawn back to `gap` under it. Riding its nearer lid, a shell's middle otherwise came out in front
    of the closed lid (seen in the close-ups)."""
    if len(shell) == 0 or len(skin) == 0:
        return
    for deltas in result.values():
        if not np.any(deltas[shell]):
            continue
        moved_shell = vertices[shell] + deltas[shell] - centre
        moved_skin = vertices[skin] + deltas[skin] - centre
        shell_reach = np.linalg.norm(moved_shell, axis=1)
        skin_reach = np.linalg.norm(moved_skin, axis=1)
        directions = moved_shell / np.maximum(shell_reach, 1e-300)[:, None]
        nearest, _ = nearest_vertices(directions, moved_skin / np.maximum(skin_reach, 1e-300)[:, None], 0.1)
        covered = nearest >= 0
        limit = np.where(covered, skin_reach[np.maximum(nearest, 0)] - gap, np.inf)
        out = covered & (shell_reach > limit)
        if out.any():
            pulled = directions[out] * limit[out, None] + centre
            deltas[shell[out]] = pulled - vertices[shell[out]]
