"""Mesh topology the face code shares: triangles from any polygons, edges, connected pieces, distances and
averaging along a mesh's edges. Plain numpy over whole arrays: no Python loop per vertex or edge."""

from __future__ import annotations

import numpy as np

from ..base.errors import HeadError

ROUND_EXTENT = 0.6
OPEN_RIM_SHARE = 0.2
MAX_SWEEPS = 400  # edge hops a geodesic distance may take: far more than across a mouth or an eye


def triangulate(polygons) -> np.ndarray:
    """(T, 3) vertex indices from triangles, quads, n-gons (fan split) or an (F, k) array."""
    if isinstance(polygons, np.ndarray) and polygons.ndim == 2:
        polygons = polygons.astype(np.int64, copy=False)
        if polygons.shape[1] == 3:
            return polygons
        corners = polygons.shape[1]
        fans = [polygons[:, [0, i, i + 1]] for i in range(1, corners - 1)]
        return np.concatenate(fans) if fans else np.empty((0, 3), np.int64)
    totals = np.fromiter((len(p) for p in polygons), dtype=np.int64, count=len(polygons))
    if totals.size == 0:
        return np.empty((0, 3), np.int64)
    loop_vertices = np.fromiter((i for p in polygons for i in p), dtype=np.int64, count=int(totals.sum()))
    starts = np.concatenate(([0], np.cumsum(totals)[:-1]))
    return triangulate_loops(loop_vertices, starts, totals)


def triangulate_loops(
    loop_vertices: np.ndarray, loop_starts: np.ndarray, loop_totals: np.ndarray
) -> np.ndarray:
    """Fan triangles from Blender-style polygon loops (the arrays `foreach_get` gives)."""
    loop_vertices = np.asarray(loop_vertices, np.int64)
    loop_starts = np.asarray(loop_starts, np.int64)
    loop_totals = np.asarray(loop_totals, np.int64)
    fan_counts = np.clip(loop_totals - 2, 0, None)
    polygon_of_fan = np.repeat(np.arange(loop_starts.size), fan_counts)
    fan_offsets = np.arange(polygon_of_fan.size) - np.repeat(np.cumsum(fan_counts) - fan_counts, fan_counts)
    first = loop_starts[polygon_of_fan]
    return np.stack(
        (
            loop_vertices[first],
            loop_vertices[first + fan_offsets + 1],
            loop_vertices[first + fan_offsets + 2],
        ),
        axis=1,
    )


def unique_pairs(pairs: np.ndarray) -> np.ndarray:
    """The distinct rows of an (N, 2) array of non-negative integers, sorted (as np.unique(axis=0) gives
    them, several times faster: each row is one integer key)."""
    pairs = np.asarray(pairs, np.int64)
    if len(pairs) == 0:
        return pairs.reshape(0, 2)
    base = int(pairs[:, 1].max()) + 1
    keys = np.unique(pairs[:, 0] * base + pairs[:, 1])
    return np.stack((keys // base, keys % base), axis=1)


def connected_pieces(vertex_count: int, triangles: np.ndarray) -> np.ndarray:
    """A label per vertex; vertices share a label when edges connect them (isolated vertices stand alone)."""
    labels = np.arange(vertex_count)
    if triangles.size == 0:
        return labels
    a = np.concatenate((triangles[:, 0], triangles[:, 1], triangles[:, 2]))
    b = np.concatenate((triangles[:, 1], triangles[:, 2], triangles[:, 0]))
    while True:
        low = np.minimum(labels[a], labels[b])
        new = labels.copy()
        np.minimum.at(new, a, low)
        np.minimum.at(new, b, low)
        new = new[new]  # pointer jumping: labels converge in a few rounds, not one per edge hop
        new = new[new]
        if np.array_equal(new, labels):
            return labels
        labels = new


def largest_piece(vertex_count: int, triangles: np.ndarray, among: np.ndarray | None = None) -> np.ndarray:
    """Vertex indices of the biggest connected piece (by vertex count), optionally among some vertices."""
    return biggest_pieces(vertex_count, triangles, among, count=1)[0]


def biggest_pieces(vertex_count: int, triangles: np.ndarray, among: np.ndarray | None, count: int = 3):
    """Up to `count` connected pieces (among some vertices, or all), biggest first, none under a tenth of
    the first."""
    labels = connected_pieces(vertex_count, triangles)
    used = np.zeros(vertex_count, bool)
    used[triangles.ravel()] = True
    if among is not None:
        keep = np.zeros(vertex_count, bool)
        keep[among] = True
        used &= keep
    if not used.any():
        raise HeadError("The mesh has no faces: a head needs polygons to find a face on. Import a mesh head.")
    sizes = np.bincount(labels[used], minlength=vertex_count)
    order = np.argsort(-sizes, kind="stable")[:count]
    return [
        np.flatnonzero(used & (labels == label)) for label in order if sizes[label] >= 0.1 * sizes[order[0]]
    ]


def round_triangles(vertices: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Which triangles belong to closed pieces about as deep and tall as wide (eyeballs: their box's
    shortest side ROUND_EXTENT of its longest or more, at most OPEN_RIM_SHARE of their vertices on an open
    rim), not to flat or cupped ones (lashes, corneas, clothing, an eye-occlusion shell over the eyeball,
    open all round its edge)."""
    if len(triangles) == 0:
        return np.zeros(0, bool)
    labels = connected_pieces(len(vertices), triangles)
    corners = triangles.ravel()
    low = np.full((len(vertices), 3), np.inf)
    high = np.full((len(vertices), 3), -np.inf)
    np.minimum.at(low, labels[corners], vertices[corners])
    np.maximum.at(high, labels[corners], vertices[corners])
    extent = high - low
    sides = np.sort(
        np.concatenate((triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]])), axis=1
    )
    sides, count = np.unique(sides, axis=0, return_counts=True)
    on_rim = np.zeros(len(vertices), bool)
    on_rim[sides[count == 1].ravel()] = True
    used = np.unique(corners)
    size = np.bincount(labels[used], minlength=len(vertices))
    rim = np.bincount(labels[used], weights=on_rim[used], minlength=len(vertices))
    with np.errstate(invalid="ignore", divide="ignore"):
        round_label = (extent.min(1) > ROUND_EXTENT * extent.max(1)) & (rim <= OPEN_RIM_SHARE * size)
    return round_label[labels[triangles[:, 0]]]


def edge_graph(vertex_count: int, triangles: np.ndarray, vertices: np.ndarray):
    """(E, 2) unique edges and their lengths."""
    edges = np.concatenate((triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]))
    edges = unique_pairs(np.sort(edges, axis=1))
    lengths = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1)
    return edges, lengths


def smooth_over_edges(values: np.ndarray, edges: np.ndarray, movable: np.ndarray, iterations: int):
    """Average each movable vertex with its neighbours (Jacobi sweeps); the others hold their values.

    The neighbour sums are segment sums over the edges sorted by vertex (reduceat), which numpy does
    far faster than scattered adds."""
    values = values.astype(np.float64, copy=True)
    if len(edges) == 0:
        return values
    shape = (-1,) + (1,) * (values.ndim - 1)
    ends = np.concatenate((edges[:, 0], edges[:, 1]))
    others = np.concatenate((edges[:, 1], edges[:, 0]))
    order = np.argsort(ends, kind="stable")
    ends, others = ends[order], others[order]
    starts = np.flatnonzero(np.diff(ends, prepend=-1))
    owners = ends[starts]
    degree = np.diff(np.append(starts, len(ends))).astype(np.float64).reshape(shape)
    movable = movable[owners].reshape(shape)
    for _ in range(iterations):
        averaged = (values[owners] + np.add.reduceat(values[others], starts, axis=0)) / (1.0 + degree)
        values[owners] = np.where(movable, averaged, values[owners])
    return values


def geodesic_distance(vertex_count: int, edges, lengths, seeds: np.ndarray, allowed: np.ndarray):
    """Distance along the mesh's edges from the seed vertices, through allowed vertices only (inf: unreached).

    Bellman-Ford sweeps over all edges at once: a few hundred numpy passes, no Python loop per vertex.
    """
    return _grow_from_seeds(vertex_count, edges, lengths, seeds, allowed, track=False)[0]


def nearest_seed(vertex_count: int, edges, lengths, seeds: np.ndarray, allowed: np.ndarray):
    """(distance, seed) along the mesh's edges: each vertex's nearest seed vertex (-1: unreached)."""
    return _grow_from_seeds(vertex_count, edges, lengths, seeds, allowed, track=True)


def _grow_from_seeds(vertex_count, edges, lengths, seeds, allowed, track):
    distance = np.full(vertex_count, np.inf)
    owner = np.full(vertex_count, -1, np.int64)
    seeds = np.asarray(seeds, np.int64)
    seeds = seeds[allowed[seeds]]
    distance[seeds] = 0.0
    owner[seeds] = seeds
    usable = allowed[edges[:, 0]] & allowed[edges[:, 1]]
    a = np.concatenate((edges[usable, 0], edges[usable, 1]))
    b = np.concatenate((edges[usable, 1], edges[usable, 0]))
    step = np.concatenate((lengths[usable], lengths[usable]))
    if len(b) == 0:
        return distance, owner
    order = np.argsort(b, kind="stable")  # edges grouped by the vertex they reach: segment minima
    a, b, step = a[order], b[order], step[order]
    starts = np.flatnonzero(np.diff(b, prepend=-1))
    reached = b[starts]
    counts = np.diff(np.append(starts, len(b)))
    for _ in range(MAX_SWEEPS):
        through = distance[a] + step
        offers = np.minimum.reduceat(through, starts)
        better = offers < distance[reached]
        if not better.any():
            break
        distance[reached[better]] = offers[better]
        if track:  # the first edge of each group that makes the offer brings its seed
            winner = np.where(through == np.repeat(offers, counts), np.arange(len(b)), len(b))
            first = np.minimum.reduceat(winner, starts)
            owner[reached[better]] = owner[a[first[better]]]
    return distance, owner
