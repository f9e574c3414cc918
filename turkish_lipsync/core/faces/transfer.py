"""Carry the reference head's 52 ARKit units over to a head that has none.

The landmarks register the reference onto the target (a similarity fit, and for heads whose proportions
differ a thin-plate-spline warp on top); each target skin vertex then takes the deltas of the closest
point on the reference surface, turned and scaled by the fitted similarity. Teeth and eyes are rigid:
each unit's motion of the reference's teeth and eyes is fitted as a rotation and translation and applied
to the target's, so the jaw carries the lower teeth without bending them, and the eyes turn in place.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping

import numpy as np

from ..errors import HeadError
from .landmarks import connected_pieces, find_landmarks, largest_piece, triangulate

# Reference part names (reference.parts) and the target part each one drives.
RIGID_PARTS: tuple[str, ...] = ("upper_teeth", "lower_teeth", "left_eye", "right_eye")
SOFT_PARTS: tuple[str, ...] = ("tongue",)

# Beyond these distances (fractions of the reference head's height, after registration) a target vertex
# is not near the reference skin any more (a torso, a hat): its deltas fade to nothing.
FALLOFF_NEAR = 0.05
FALLOFF_FAR = 0.15

# A similarity fit that leaves landmarks this far off (fraction of the face size) calls for the warp.
WARP_RESIDUAL = 0.02


# ---------------------------------------------------------------- registration


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


class ThinPlateWarp:
    """A smooth 3D warp that moves each source landmark exactly onto its target (kernel |r|, affine part)."""

    def __init__(self, source: np.ndarray, target: np.ndarray, smoothing: float = 0.0) -> None:
        self.source = np.asarray(source, np.float64)
        count = len(self.source)
        kernel = np.linalg.norm(self.source[:, None] - self.source[None], axis=2)
        kernel += smoothing * np.eye(count)  # > 0: follow the landmarks loosely, as their placing is rough
        affine = np.hstack((np.ones((count, 1)), self.source))
        system = np.zeros((count + 4, count + 4))
        system[:count, :count] = kernel
        system[:count, count:] = affine
        system[count:, :count] = affine.T
        right = np.zeros((count + 4, 3))
        right[:count] = target
        solution = np.linalg.lstsq(system, right, rcond=None)[0]
        self.weights, self.affine = solution[:count], solution[count:]

    def __call__(self, points: np.ndarray) -> np.ndarray:
        out = self.affine[0] + points @ self.affine[1:]
        for start in range(0, len(points), 8192):
            chunk = points[start : start + 8192]
            kernel = np.linalg.norm(chunk[:, None] - self.source[None], axis=2)
            out[start : start + 8192] += kernel @ self.weights
        return out


# ---------------------------------------------------------------- closest points on a surface


def _nearest_vertex(points: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Index of the nearest vertex for each point (chunked brute force: BLAS beats a tree at this size)."""
    nearest = np.empty(len(points), np.int64)
    squared = (vertices**2).sum(1)
    for start in range(0, len(points), 1024):
        chunk = points[start : start + 1024]
        distance = squared[None, :] - 2.0 * chunk @ vertices.T
        nearest[start : start + 1024] = np.argmin(distance, axis=1)
    return nearest


def _triangles_around(vertex_count: int, triangles: np.ndarray) -> np.ndarray:
    """For each vertex, the triangles touching it or one of its neighbours, padded with -1."""
    corner_vertex = triangles.ravel()
    order = np.argsort(corner_vertex, kind="stable")
    triangle_of_corner = np.repeat(np.arange(len(triangles)), 3)[order]
    first_corner = np.searchsorted(corner_vertex[order], np.arange(vertex_count + 1))
    edges = np.concatenate(
        [triangles[:, [i, j]] for i, j in ((0, 1), (1, 2), (2, 0), (1, 0), (2, 1), (0, 2))]
    )
    own = np.unique(corner_vertex)
    links = np.unique(np.concatenate((edges, np.stack((own, own), 1))), axis=0)  # (vertex, neighbour)
    counts = first_corner[links[:, 1] + 1] - first_corner[links[:, 1]]
    vertex = np.repeat(links[:, 0], counts)
    offsets = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    triangle = triangle_of_corner[np.repeat(first_corner[links[:, 1]], counts) + offsets]
    pairs = np.unique(np.stack((vertex, triangle), 1), axis=0)
    per_vertex = np.bincount(pairs[:, 0], minlength=vertex_count)
    table = np.full((vertex_count, max(int(per_vertex.max()), 1)), -1, np.int64)
    slot = np.arange(len(pairs)) - np.repeat(np.cumsum(per_vertex) - per_vertex, per_vertex)
    table[pairs[:, 0], slot] = pairs[:, 1]
    return table


def closest_points(points: np.ndarray, vertices: np.ndarray, triangles: np.ndarray):
    """(triangle index, barycentric weights (P, 3), distance) of the closest surface point to each point.

    The search looks at the triangles around the nearest vertex and its neighbours. Where two sheets
    of surface nearly touch (eyelid and socket) it can pick the other sheet, a fraction of a millimetre
    further away, whose deltas are the same.
    """
    points = np.asarray(points, np.float64)
    used = np.unique(triangles)
    nearest = used[_nearest_vertex(points, vertices[used])]
    best_distance = np.full(len(points), np.inf)
    best_triangle = np.zeros(len(points), np.int64)
    best_weights = np.zeros((len(points), 3))
    candidates = _triangles_around(len(vertices), triangles)[nearest]
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


# ---------------------------------------------------------------- parts of the target


def find_parts(vertices: np.ndarray, polygons, landmarks: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Teeth, tongue and eyes of a head, as vertex indices, from its separate pieces and where they sit.

    Material and object names differ from head to head; geometry does not: a piece inside the mouth
    that reaches forward to the lips is a row of teeth (upper above the lip line, lower below), one
    further back is the tongue; pieces behind each eye's corners are that eye (eyeball, iris, cornea).
    Parts a head lacks are left out.
    """
    vertices = np.asarray(vertices, np.float64)
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
    parts.update(left_eye=[], right_eye=[])
    eyes = {
        side: (
            0.5 * (lm[f"eye_inner_{side}"] + lm[f"eye_outer_{side}"]),
            float(np.linalg.norm(lm[f"eye_inner_{side}"] - lm[f"eye_outer_{side}"])),
        )
        for side in ("left", "right")
    }
    teeth = []
    for piece in pieces:
        points = vertices[piece]
        centre = points.mean(0)
        for side, (eye_centre, eye_width) in eyes.items():
            offset = centre - eye_centre
            sideways = np.hypot(offset[0], offset[2])
            # An eyeball's centre lies well behind the corners; lashes and lids hang in front of it.
            if sideways < 0.6 * eye_width and 0.15 * eye_width < offset[1] < 1.2 * eye_width:
                parts[f"{side}_eye"].append(piece)
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
    if len(teeth) == 1 and 0.25 < (vertices[teeth[0], 2] >= lip_line).mean() < 0.75:
        above = vertices[teeth[0], 2] >= lip_line  # both rows in one piece: split it at the lip line
        parts["upper_teeth"].append(teeth[0][above])
        parts["lower_teeth"].append(teeth[0][~above])
    else:
        for piece in teeth:
            row = "upper_teeth" if vertices[piece, 2].mean() >= lip_line else "lower_teeth"
            parts[row].append(piece)
    return {name: np.sort(np.concatenate(found)) for name, found in parts.items() if found}


# ---------------------------------------------------------------- the transfer


@functools.lru_cache(maxsize=4)
def _reference_landmarks_of(reference) -> dict[str, np.ndarray]:
    """The reference's landmarks found the same way as a target's, so both follow one convention."""
    return find_landmarks(reference.vertices, reference.polygons)


def _part_triangles(triangles: np.ndarray, indices: np.ndarray, vertex_count: int) -> np.ndarray:
    keep = np.zeros(vertex_count, bool)
    keep[indices] = True
    return triangles[keep[triangles].all(1)]


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
    with find_parts when not given. warp: "similarity", "thin_plate" or "auto" (the warp when the
    similarity fit leaves the landmarks more than a few percent of the face apart). reference_landmarks
    default to find_landmarks on the reference, the convention the target's landmarks follow.
    """
    if warp not in ("auto", "similarity", "thin_plate"):
        raise ValueError(f"warp must be 'auto', 'similarity' or 'thin_plate', not {warp!r}")
    target_vertices = np.asarray(target_vertices, np.float64)
    target_triangles = triangulate(target_polygons)
    if reference_landmarks is None:
        reference_landmarks = _reference_landmarks_of(reference)
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
    use_warp = warp == "thin_plate" or (warp == "auto" and residual > WARP_RESIDUAL * face_size)

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
        placed = ThinPlateWarp(placed_landmarks[distinct], target_points[distinct])(placed)
    turn = scale * rotation  # deltas follow the global rotation and scale only

    reference_triangles = triangulate(reference.polygons)
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

    # Skin (and everything that is not a known part): closest point on the reference skin.
    skin = np.flatnonzero(~in_part)
    reference_skin = reference_parts.get("skin", np.arange(len(reference_vertices)))
    height = scale * float(np.ptp(reference_vertices[reference_skin, 2]))
    _carry_by_closest_point(
        result, skin, target_vertices, placed, reference_triangles, reference_skin, units, turn, height
    )
    # The tongue bends (tongueOut): closest point on the reference tongue.
    for name in SOFT_PARTS:
        if name in target_parts and name in reference_parts and len(target_parts[name]):
            _carry_by_closest_point(
                result,
                np.asarray(target_parts[name]),
                target_vertices,
                placed,
                reference_triangles,
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
    result, targets, target_vertices, placed, reference_triangles, reference_indices, units, turn, height
) -> None:
    """Deltas at the closest reference point, interpolated over its triangle, turned and scaled."""
    triangles = _part_triangles(reference_triangles, reference_indices, len(placed))
    if len(triangles) == 0 or len(targets) == 0:
        return
    triangle, weights, distance = closest_points(target_vertices[targets], placed, triangles)
    corners = triangles[triangle]
    if height is None:
        fade = np.ones(len(targets))
    else:
        fade = np.clip((FALLOFF_FAR * height - distance) / ((FALLOFF_FAR - FALLOFF_NEAR) * height), 0, 1)
    weights = weights * fade[:, None]
    for name, delta in units.items():
        local = (delta[corners] * weights[:, :, None]).sum(1)
        result[name][targets] = local @ turn.T


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
