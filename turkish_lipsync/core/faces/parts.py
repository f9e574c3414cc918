"""The parts of a face that touch: upper and lower lip, upper and lower lid, and the inside of the mouth.

Lips and lids are pairs of surfaces pressed together, so a closest-point search cannot tell them apart;
their labels come from the mesh's connectivity instead. A band of skin clearly above the mouth line and
one clearly below it are grown over the mesh's edges (a geodesic Voronoi split): whatever the upper
band reaches first is upper lip, so the inner surface of the upper lip and the upper half of a mouth bag
stay upper even where they touch the lower lip. Eyes are split the same way at the line between their
corners. The same code labels the reference and the target, so each part can sample its own kind.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from .depth import DepthMap, hidden_depth
from .topology import edge_graph, geodesic_distance, smooth_over_edges

# Label names, in the order of FaceParts.label values (0 is the rest of the skin).
PART_LABELS: tuple[str, ...] = (
    "skin",
    "upper_lip",
    "lower_lip",
    "upper_lid_left",
    "lower_lid_left",
    "upper_lid_right",
    "lower_lid_right",
)
OPPOSITE_PART = {
    "upper_lip": "lower_lip",
    "lower_lip": "upper_lip",
    "upper_lid_left": "lower_lid_left",
    "lower_lid_left": "upper_lid_left",
    "upper_lid_right": "lower_lid_right",
    "lower_lid_right": "upper_lid_right",
}
# A lip or lid vertex whose distances to the two sides differ by less than this share of their sum lies
# where the sides meet (mouth and eye corners) and may sample either.
SURE_MARGIN = 0.25
# Region radii around the mouth and each eye, in mouth widths and eye widths.
MOUTH_REACH = 1.0
EYE_REACH = 0.9


@dataclass(frozen=True)
class FaceParts:
    """Per-vertex labels of a head's skin (indices into PART_LABELS; -1 off the skin), and mouth depth.

    inside_mouth: 0 on the outer face, rising to 1 deep inside the mouth (behind the lips), where
    the mesh is the mouth bag, gums, teeth or tongue and follows the jaw rigidly.
    """

    label: np.ndarray
    seen: np.ndarray  # the front view sees the vertex (it is not behind the lips, lids or nose)
    sure: np.ndarray  # the label is clear (far nearer one side than the other): the part samples its own kind
    inside_mouth: np.ndarray
    lower_jaw: np.ndarray  # inside the mouth: 1 where the lower jaw carries the mesh, 0 the upper, blended
    seam_height: float  # z of the line between the lips at the midline
    middle_x: float

    def indices(self, name: str) -> np.ndarray:
        return np.flatnonzero(self.label == PART_LABELS.index(name))


def split_between(vertex_count: int, edges, lengths, first: np.ndarray, second: np.ndarray, allowed, central):
    """(owner, sure) per vertex: 0 nearer the first seeds, 1 the second, -1 neither; sure where one is
    clearly nearer or the vertex is central (between the corners, where lips and lids touch); beside
    the corners, where the sides meet and a corner landmark's error moves the split, neither is."""
    to_first = geodesic_distance(vertex_count, edges, lengths, first, allowed)
    to_second = geodesic_distance(vertex_count, edges, lengths, second, allowed)
    owner = np.where(to_first <= to_second, 0, 1)
    owner[~np.isfinite(np.minimum(to_first, to_second))] = -1
    with np.errstate(invalid="ignore"):
        margin = np.abs(to_first - to_second) / (to_first + to_second)
    sure = (owner >= 0) & ((margin > SURE_MARGIN) | ~np.isfinite(margin) | central)
    return owner, sure


@dataclass(frozen=True, eq=False)
class _Skin:
    """The skin's edges to grow labels over, and which vertices the front view sees."""

    vertices: np.ndarray
    on_skin: np.ndarray
    edges: np.ndarray
    lengths: np.ndarray
    hidden: np.ndarray  # behind the lips, lids or nose, seen from the front

    def split(self, first, second, allowed, central):
        """split_between over the skin's edges."""
        return split_between(len(self.vertices), self.edges, self.lengths, first, second, allowed, central)


@dataclass(frozen=True, eq=False)
class _MouthLine:
    """Where the lips meet: the mouth's middle and width, and each vertex's height over the line."""

    middle_x: float
    width: float
    seam_height: float  # z of the line at the midline
    lip_height: float
    above: np.ndarray  # per vertex: how far above the line between the lips
    inner_front: float  # y of the lips' inner edges (the front of the gap between them)


def find_face_parts(
    vertices: np.ndarray, triangles: np.ndarray, skin: np.ndarray, landmarks: Mapping[str, np.ndarray]
) -> FaceParts:
    """Lips, lids and the mouth's inside on a head's skin (vertices facing -Y, Z up, left is +X)."""
    lm = {name: np.asarray(point, np.float64) for name, point in landmarks.items()}
    count = len(vertices)
    on_skin = np.zeros(count, bool)
    on_skin[skin] = True
    skin_triangles = triangles[on_skin[triangles].all(1)]
    edges, lengths = edge_graph(count, skin_triangles, vertices)
    label = np.full(count, -1)
    label[skin] = 0
    mouth = _mouth_line(vertices, lm)
    depth = DepthMap(vertices, skin_triangles, max(mouth.width / 60, 1e-9))
    hidden_by = hidden_depth(vertices, depth)
    face = _Skin(vertices, on_skin, edges, lengths, hidden_by > 0.04 * mouth.width)
    owner, sure_mouth = _split_lips(face, lm, mouth)
    label[owner == 0] = PART_LABELS.index("upper_lip")
    label[owner == 1] = PART_LABELS.index("lower_lip")
    inside = _inside_mouth(vertices, hidden_by, owner, mouth)
    lower_side = smooth_over_edges((owner == 1).astype(np.float64), edges, inside > 0, 30)
    sure = sure_mouth & (label > 0)
    for side in ("left", "right"):
        _split_lids(face, lm, side, label, sure)
    return FaceParts(
        label=label,
        seen=~face.hidden,
        sure=sure,
        inside_mouth=inside,
        lower_jaw=lower_side,
        seam_height=mouth.seam_height,
        middle_x=mouth.middle_x,
    )


def _mouth_line(vertices: np.ndarray, lm: Mapping[str, np.ndarray]) -> _MouthLine:
    middle_x = 0.5 * (lm["mouth_corner_left"][0] + lm["mouth_corner_right"][0])
    mouth_width = float(np.linalg.norm(lm["mouth_corner_left"] - lm["mouth_corner_right"]))
    seam = _seam_height(lm, middle_x)
    lip_height = max(
        lm["upper_lip"][2] - seam(middle_x), seam(middle_x) - lm["lower_lip"][2], 0.05 * mouth_width
    )
    return _MouthLine(
        middle_x=middle_x,
        width=mouth_width,
        seam_height=float(seam(middle_x)),
        lip_height=lip_height,
        above=vertices[:, 2] - seam(vertices[:, 0]),
        inner_front=0.5 * (lm["upper_lip_inner"][1] + lm["lower_lip_inner"][1]),
    )


def _split_lips(
    face: _Skin, lm: Mapping[str, np.ndarray], mouth: _MouthLine
) -> tuple[np.ndarray, np.ndarray]:
    """(owner, sure) per vertex: 0 the upper lip, 1 the lower, -1 neither (split_between)."""
    vertices, hidden, above, lip_height = face.vertices, face.hidden, mouth.above, mouth.lip_height
    x, y = vertices[:, 0], vertices[:, 1]
    centre = np.array([mouth.middle_x, 0.5 * (lm["upper_lip"][1] + lm["lower_lip"][1]), mouth.seam_height])
    mouth_region = face.on_skin & (np.linalg.norm(vertices - centre, axis=1) < MOUTH_REACH * mouth.width)
    across = np.abs(x - mouth.middle_x) < 0.35 * mouth.width
    upper_seed = np.flatnonzero(
        mouth_region & across & ~hidden & (above > 0.35 * lip_height) & (above < 1.5 * lip_height)
    )
    lower_seed = np.flatnonzero(
        mouth_region & across & ~hidden & (above < -0.35 * lip_height) & (above > -1.5 * lip_height)
    )
    owner, sure = face.split(upper_seed, lower_seed, mouth_region, across)
    # On the lips' visible front, between the corners, the mouth line itself decides: a strip of faces
    # closing a mask's mouth joins the lips there, and the growth alone may hand it to either side.
    front = (owner >= 0) & across & ~hidden & (y <= mouth.inner_front + 0.02 * mouth.width)
    front &= (np.abs(above) < lip_height) & (np.abs(above) > 0.05 * lip_height)
    owner[front] = np.where(above[front] > 0, 0, 1)
    return owner, sure


def _inside_mouth(
    vertices: np.ndarray, hidden_by: np.ndarray, owner: np.ndarray, mouth: _MouthLine
) -> np.ndarray:
    """0 on the outer face, rising to 1 deep inside the mouth: hidden from the front behind the lips, or
    seen through the gap between them but well behind their inner edge (teeth between parted lips)."""
    width = mouth.width
    in_gap = (np.abs(vertices[:, 0] - mouth.middle_x) < 0.4 * width) & (
        np.abs(mouth.above) < mouth.lip_height
    )
    deep = np.maximum(hidden_by, np.where(in_gap, vertices[:, 1] - mouth.inner_front, 0.0))
    inside = np.clip((deep - 0.04 * width) / (0.2 * width), 0.0, 1.0)
    inside[owner < 0] = 0.0
    return inside


def _split_lids(
    face: _Skin, lm: Mapping[str, np.ndarray], side: str, label: np.ndarray, sure: np.ndarray
) -> None:
    """Label the side's upper and lower lid (where the lips did not) and say where that is sure."""
    vertices, hidden = face.vertices, face.hidden
    x, z = vertices[:, 0], vertices[:, 2]
    inner, outer = lm[f"eye_inner_{side}"], lm[f"eye_outer_{side}"]
    eye_width = float(np.linalg.norm(outer - inner))
    eye_centre = 0.5 * (inner + outer)
    slope = (outer[2] - inner[2]) / (outer[0] - inner[0]) if outer[0] != inner[0] else 0.0
    lid_line = eye_centre[2] + slope * (x - eye_centre[0])
    region = face.on_skin & (np.linalg.norm(vertices - eye_centre, axis=1) < EYE_REACH * eye_width)
    region &= label <= 0
    within = np.abs(x - eye_centre[0]) < 0.3 * eye_width
    rise = z - lid_line
    upper = np.flatnonzero(region & within & ~hidden & (rise > 0.15 * eye_width) & (rise < 0.45 * eye_width))
    lower = np.flatnonzero(region & within & ~hidden & (rise < -0.12 * eye_width) & (rise > -0.4 * eye_width))
    owner, sure_eye = face.split(upper, lower, region, np.abs(x - eye_centre[0]) < 0.35 * eye_width)
    sure[owner >= 0] = sure_eye[owner >= 0]
    label[owner == 0] = PART_LABELS.index(f"upper_lid_{side}")
    label[owner == 1] = PART_LABELS.index(f"lower_lid_{side}")


def _seam_height(lm: Mapping[str, np.ndarray], middle_x: float):
    """z of the line between the lips as a function of x: through both corners and the middle of the lips."""
    right, left = lm["mouth_corner_right"], lm["mouth_corner_left"]
    middle = 0.5 * (lm["upper_lip_inner"][2] + lm["lower_lip_inner"][2])
    xs = np.array([right[0], middle_x, left[0]])
    zs = np.array([right[2], middle, left[2]])

    def seam(x):
        return np.interp(x, xs, zs)

    return seam


def opening_gap(vertices: np.ndarray, deltas: np.ndarray, upper: np.ndarray, lower: np.ndarray, x: float):
    """How far apart two facing surfaces (lips, lids) stand on a vertical slice at x, after the key.

    The gap is the lowest point of the upper surface minus the highest of the lower one within a slab
    around x; it is negative where they press into each other, and NaN when either surface is absent.
    """
    moved = vertices + deltas
    width = _slab_width(vertices, upper, lower)
    gaps = []
    for part in (upper, lower):
        near = part[np.abs(vertices[part, 0] - x) <= width]
        gaps.append(moved[near, 2] if len(near) else None)
    if gaps[0] is None or gaps[1] is None:
        return float("nan")
    return float(gaps[0].min() - gaps[1].max())


def _slab_width(vertices: np.ndarray, upper: np.ndarray, lower: np.ndarray) -> float:
    """Half-width of the slice: a few typical edge spans of the parts, so each holds some vertices."""
    both = np.concatenate((upper, lower))
    span = float(np.ptp(vertices[both, 0])) if len(both) else 0.0
    return max(0.03 * span, 1e-9)
