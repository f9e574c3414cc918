"""Closest points on a triangle surface, for many query points at once (numpy, no tree).

The search starts at each point's nearest vertex and looks at the triangles around it and its
neighbours: exact wherever the nearest vertex belongs to the closest triangle's neighbourhood, which
holds on the even meshes of heads.
"""

from __future__ import annotations

import numpy as np

from .topology import unique_pairs


def nearest_vertices(points: np.ndarray, candidates: np.ndarray, radius: float | None = None):
    """(index, distance) of the nearest candidate for each point. With a radius, only candidates within
    it count (a grid of cells that size is searched; points with none there get index -1, distance inf),
    so the cost follows the points and their neighbourhoods, not the whole mesh; without, every
    candidate (chunked brute force: BLAS beats a tree at a head's size)."""
    points = np.asarray(points, np.float64)
    candidates = np.asarray(candidates, np.float64)
    if radius is None or len(candidates) == 0 or len(points) == 0:
        return _nearest_of_all(points, candidates)
    return _nearest_in_cells(points, candidates, float(radius))


def _nearest_of_all(points: np.ndarray, candidates: np.ndarray):
    nearest = np.full(len(points), -1, np.int64)
    if len(candidates) == 0:
        return nearest, np.full(len(points), np.inf)
    squared = (candidates**2).sum(1)
    for start in range(0, len(points), 1024):
        chunk = points[start : start + 1024]
        distance = squared[None, :] - 2.0 * chunk @ candidates.T
        nearest[start : start + 1024] = np.argmin(distance, axis=1)
    return nearest, np.linalg.norm(points - candidates[nearest], axis=1)


_NEIGHBOUR_CELLS = np.stack(np.meshgrid(*([np.arange(-1, 2)] * 3), indexing="ij"), -1).reshape(-1, 3)
_PAIRS_PER_PASS = 1 << 21


def _nearest_in_cells(points: np.ndarray, candidates: np.ndarray, radius: float):
    low = candidates.min(0) - radius
    cells = np.floor((candidates - low) / radius).astype(np.int64)
    shape = cells.max(0) + 2
    keys = (cells[:, 0] * shape[1] + cells[:, 1]) * shape[2] + cells[:, 2]
    order = np.argsort(keys, kind="stable")
    keys = keys[order]
    query_cells = np.floor((points - low) / radius).astype(np.int64)
    nearest = np.full(len(points), -1, np.int64)
    best = np.full(len(points), np.inf)
    step = max(1, _PAIRS_PER_PASS // (27 * int(np.unique(keys, return_counts=True)[1].max())))
    for start in range(0, len(points), step):
        rows = np.arange(start, min(start + step, len(points)))
        around = query_cells[rows, None, :] + _NEIGHBOUR_CELLS[None]  # (q, 27, 3)
        inside = np.all((around >= 0) & (around < shape), axis=2)
        query_keys = np.where(
            inside, (around[..., 0] * shape[1] + around[..., 1]) * shape[2] + around[..., 2], -1
        )
        first = np.searchsorted(keys, query_keys, "left")
        counts = np.where(inside, np.searchsorted(keys, query_keys, "right") - first, 0).ravel()
        if counts.sum() == 0:
            continue
        owner = np.repeat(np.repeat(rows, 27), counts)
        offsets = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
        candidate = order[np.repeat(first.ravel(), counts) + offsets]
        distance = np.linalg.norm(points[owner] - candidates[candidate], axis=1)
        pick = np.lexsort((distance, owner))  # each owner's nearest first
        owner, candidate, distance = owner[pick], candidate[pick], distance[pick]
        firsts = np.flatnonzero(np.diff(owner, prepend=-1))
        found = distance[firsts] <= radius
        nearest[owner[firsts][found]] = candidate[firsts][found]
        best[owner[firsts][found]] = distance[firsts][found]
    return nearest, best


def triangles_around(vertex_count: int, triangles: np.ndarray) -> np.ndarray:
    """For each vertex, the triangles touching it or one of its neighbours, padded with -1."""
    corner_vertex = triangles.ravel()
    order = np.argsort(corner_vertex, kind="stable")
    triangle_of_corner = np.repeat(np.arange(len(triangles)), 3)[order]
    first_corner = np.searchsorted(corner_vertex[order], np.arange(vertex_count + 1))
    edges = np.concatenate(
        [triangles[:, [i, j]] for i, j in ((0, 1), (1, 2), (2, 0), (1, 0), (2, 1), (0, 2))]
    )
    own = np.unique(corner_vertex)
    links = unique_pairs(np.concatenate((edges, np.stack((own, own), 1))))  # (vertex, neighbour)
    counts = first_corner[links[:, 1] + 1] - first_corner[links[:, 1]]
    vertex = np.repeat(links[:, 0], counts)
    offsets = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    triangle = triangle_of_corner[np.repeat(first_corner[links[:, 1]], counts) + offsets]
    pairs = unique_pairs(np.stack((vertex, triangle), 1))
    per_vertex = np.bincount(pairs[:, 0], minlength=vertex_count)
    table = np.full((vertex_count, max(int(per_vertex.max()), 1)), -1, np.int64)
    slot = np.arange(len(pairs)) - np.repeat(np.cumsum(per_vertex) - per_vertex, per_vertex)
    table[pairs[:, 0], slot] = pairs[:, 1]
    return table


def closest_points(
    points: np.ndarray, vertices: np.ndarray, triangles: np.ndarray, allowed=None, around=None
):
    """(triangle index, barycentric weights (P, 3), distance) of the closest surface point to each point.

    The search looks at the triangles around the nearest vertex and its neighbours. Where two sheets
    of surface nearly touch (eyelid and socket) it can pick the other sheet, a fraction of a millimetre
    further away, whose deltas are the same. allowed: a mask of the triangles to search (all if None);
    around: triangles_around of the triangles, when the caller searches the same surface many times.
    """
    points = np.asarray(points, np.float64)
    if allowed is None:
        allowed = np.ones(len(triangles), bool)
    if around is None:
        around = triangles_around(len(vertices), triangles)
    used = np.zeros(len(vertices), bool)
    used[triangles[allowed].ravel()] = True
    used = np.flatnonzero(used)
    nearest = used[nearest_vertices(points, vertices[used])[0]]
    best_distance = np.full(len(points), np.inf)
    best_triangle = np.zeros(len(points), np.int64)
    best_weights = np.zeros((len(points), 3))
    candidates = around[nearest]
    candidates = np.where((candidates >= 0) & allowed[np.maximum(candidates, 0)], candidates, -1)
    _search(
        points,
        vertices,
        triangles,
        candidates,
        np.arange(len(points)),
        best_distance,
        best_triangle,
        best_weights,
    )
    return best_triangle, best_weights, best_distance


def _search(points, vertices, triangles, candidates, rows_of, best_distance, best_triangle, best_weights):
    """Keep, for each point, the closest of its candidate triangles (columns of `candidates`)."""
    for column in range(candidates.shape[1]):
        triangle = candidates[:, column]
        valid = triangle >= 0
        if not valid.any():
            continue
        rows = rows_of[valid]
        corners = vertices[triangles[triangle[valid]]]
        weights, distance = _closest_on_triangles(points[rows], corners)
        better = distance < best_distance[rows]
        chosen = rows[better]
        best_distance[chosen] = distance[better]
        best_triangle[chosen] = triangle[valid][better]
        best_weights[chosen] = weights[better]


def _closest_on_triangles(points: np.ndarray, corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Barycentric weights of the closest point on each triangle (P, 3, 3) and its distance."""
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    ab, ac, ap = b - a, c - a, points - a
    d00 = (ab * ab).sum(1)
    d01 = (ab * ac).sum(1)
    d11 = (ac * ac).sum(1)
    d20 = (ap * ab).sum(1)
    d21 = (ap * ac).sum(1)
    denominator = d00 * d11 - d01 * d01
    with np.errstate(divide="ignore", invalid="ignore"):
        v = (d11 * d20 - d01 * d21) / denominator
        w = (d00 * d21 - d01 * d20) / denominator
    u = 1.0 - v - w
    weights = np.stack((u, v, w), 1)
    inside = (denominator > 0) & (u >= 0) & (v >= 0) & (w >= 0)
    weights[~inside] = np.nan
    best = np.where(inside, np.linalg.norm(points - (weights[:, :, None] * corners).sum(1), axis=1), np.inf)
    weights = np.where(inside[:, None], weights, 0.0)
    for first, second in ((0, 1), (1, 2), (2, 0)):
        start, edge = corners[:, first], corners[:, second] - corners[:, first]
        length = (edge * edge).sum(1)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.clip(((points - start) * edge).sum(1) / length, 0.0, 1.0)
        t = np.where(length > 0, t, 0.0)
        distance = np.linalg.norm(points - (start + t[:, None] * edge), axis=1)
        better = distance < best
        best = np.where(better, distance, best)
        edge_weights = np.zeros_like(weights)
        edge_weights[:, first] = 1.0 - t
        edge_weights[:, second] = t
        weights = np.where(better[:, None], edge_weights, weights)
    return weights, best
