"""Face landmarks found from the geometry of a head that looks toward -Y with Z up.

Users import heads of every scale, topology and origin, often without named parts, so the landmarks that
register the reference head onto theirs are found from the shape alone: the head is cut from the body at
the neck, a front-view depth map is rasterised, the midline profile below the nose gives the lips and the
chin, the groove between the lips runs sideways to the mouth corners, and the eyes are the recesses
beside the nose with the brows above them. Left means the character's left, which is +X.
"""

from __future__ import annotations

import numpy as np

from ..base.errors import HeadError

# Slices (of 200, from the top) where find_head_region looks for no neck yet.
CROWN_SLICES = 10
# An eye's opening and upper lid reach at most this far above its corners (face sizes).
EYE_HEIGHT = 0.05
# Under the chin the profile falls back more than UNDER_CHIN_FALL within UNDER_CHIN_RUN (face sizes).
UNDER_CHIN_FALL = 0.04
UNDER_CHIN_RUN = 0.02
# The lids' margins at the middle of each eye: found only where a separate eyeball shows between the lids.
LID_LANDMARK_NAMES: tuple[str, ...] = (
    "upper_lid_left",
    "lower_lid_left",
    "upper_lid_right",
    "lower_lid_right",
)
LANDMARK_NAMES: tuple[str, ...] = (
    "nose_tip",
    "upper_lip",
    "lower_lip",
    "upper_lip_inner",
    "lower_lip_inner",
    "mouth_corner_left",
    "mouth_corner_right",
    "chin",
    "eye_outer_left",
    "eye_inner_left",
    "eye_outer_right",
    "eye_inner_right",
    "brow_left",
    "brow_right",
)

# Depth-map pixels across the head's height: about 1 mm on a real head, enough for lips and eye corners.
DEPTH_MAP_ROWS = 320
# The hidden share of a face is read off depth maps this many pixels from the brows to the chin; another
# piece hides the skin where it stands this share of that height in front of it.
HIDDEN_FACE_ROWS = 120
HIDDEN_FACE_GAP = 0.01


# ---------------------------------------------------------------- mesh topology


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
    return _biggest_pieces(vertex_count, triangles, among, count=1)[0]


# ---------------------------------------------------------------- the head on a body


def find_head_region(vertices: np.ndarray, polygons) -> np.ndarray:
    """Indices of the vertices above the neck; every vertex when the mesh has no shoulders (a head alone).

    The neck is the narrowest slice between the widest part of the head and the shoulders, which are
    found walking down from the top as the first slice much wider than the head.
    """
    vertices = np.asarray(vertices, np.float64)
    triangles = triangulate(polygons)
    body = largest_piece(len(vertices), triangles)
    z = vertices[body, 2]
    x = vertices[body, 0]
    top, bottom = z.max(), z.min()
    height = top - bottom
    if height <= 0:
        raise HeadError("The mesh is flat (no height along Z): a head must stand upright, Z up, facing -Y.")
    slice_count = 200
    slice_of = np.clip(((top - z) / height * slice_count).astype(int), 0, slice_count - 1)
    low = np.full(slice_count, np.inf)
    high = np.full(slice_count, -np.inf)
    np.minimum.at(low, slice_of, x)
    np.maximum.at(high, slice_of, x)
    width = high - low
    width[~np.isfinite(width)] = np.nan
    widest, narrowest, neck_slice = 0.0, np.inf, -1
    for index, value in enumerate(width):
        if np.isnan(value):
            continue
        # The crown's first slices hold a few vertices each (a tilted head's top): no neck is there.
        if index >= CROWN_SLICES and value > 1.6 * widest and narrowest < 0.85 * widest:
            neck_z = top - (neck_slice + 0.5) / slice_count * height
            centre = 0.5 * (low[:neck_slice].min() + high[:neck_slice].max())
            above = vertices[:, 2] >= neck_z
            near = np.abs(vertices[:, 0] - centre) <= widest
            return np.flatnonzero(above & near)
        if value >= widest:
            widest, narrowest = value, np.inf
        elif value < narrowest:
            narrowest, neck_slice = value, index
    return np.arange(len(vertices))


# ---------------------------------------------------------------- front-view depth map


class DepthMap:
    """How far forward (-Y) the surface comes at each point of a front-view grid; NaN where no surface.

    Pixel (row, column) looks at x = left + column * pixel, z = top - row * pixel.
    """

    def __init__(self, vertices: np.ndarray, triangles: np.ndarray, pixel: float, like=None) -> None:
        """like: another DepthMap whose grid this one shares (to compare what two meshes show)."""
        self.pixel = pixel
        if like is not None:
            self.pixel, self.left, self.top = like.pixel, like.left, like.top
            rows, columns = like.front.shape
        else:
            used = vertices[np.unique(triangles)]
            self.left = used[:, 0].min() - 2 * pixel
            self.top = used[:, 2].max() + 2 * pixel
            columns = int(np.ceil((used[:, 0].max() + 2 * pixel - self.left) / pixel)) + 1
            rows = int(np.ceil((self.top - used[:, 2].min() + 2 * pixel) / pixel)) + 1
        self.front = self._rasterise(vertices, triangles, rows, columns)

    def _rasterise(self, vertices: np.ndarray, triangles: np.ndarray, rows: int, columns: int) -> np.ndarray:
        u = (vertices[:, 0] - self.left) / self.pixel
        v = (self.top - vertices[:, 2]) / self.pixel
        forward = -vertices[:, 1]
        tu, tv, tf = u[triangles], v[triangles], forward[triangles]
        # Clipped to the grid: a map sharing another's grid may hold triangles beyond it.
        u0 = np.maximum(np.ceil(tu.min(1)), 0).astype(np.int64)
        u1 = np.minimum(np.floor(tu.max(1)), columns - 1).astype(np.int64)
        v0 = np.maximum(np.ceil(tv.min(1)), 0).astype(np.int64)
        v1 = np.minimum(np.floor(tv.max(1)), rows - 1).astype(np.int64)
        span_u = np.clip(u1 - u0 + 1, 0, None)
        counts = span_u * np.clip(v1 - v0 + 1, 0, None)
        owner = np.repeat(np.arange(len(triangles)), counts)
        local = np.arange(owner.size) - np.repeat(np.cumsum(counts) - counts, counts)
        pu = u0[owner] + local % span_u[owner]
        pv = v0[owner] + local // span_u[owner]
        a_u, b_u, c_u = tu[owner].T
        a_v, b_v, c_v = tv[owner].T
        area = (b_u - a_u) * (c_v - a_v) - (c_u - a_u) * (b_v - a_v)
        with np.errstate(divide="ignore", invalid="ignore"):
            w_b = ((pu - a_u) * (c_v - a_v) - (c_u - a_u) * (pv - a_v)) / area
            w_c = ((b_u - a_u) * (pv - a_v) - (pu - a_u) * (b_v - a_v)) / area
            w_a = 1.0 - w_b - w_c
            tolerance = -1e-9
            inside = (area != 0) & (w_a >= tolerance) & (w_b >= tolerance) & (w_c >= tolerance)
        f = tf[owner[inside]]
        depth = w_a[inside] * f[:, 0] + w_b[inside] * f[:, 1] + w_c[inside] * f[:, 2]
        image = np.full(rows * columns, -np.inf)
        np.maximum.at(image, pv[inside] * columns + pu[inside], depth)
        image = image.reshape(rows, columns)
        image[~np.isfinite(image)] = np.nan
        return image

    def column_of(self, x: float) -> int:
        return int(round((x - self.left) / self.pixel))

    def row_of(self, z: float) -> int:
        return int(round((self.top - z) / self.pixel))

    def x_of(self, column) -> np.ndarray:
        return self.left + np.asarray(column, np.float64) * self.pixel

    def z_of(self, row) -> np.ndarray:
        return self.top - np.asarray(row, np.float64) * self.pixel

    def point(self, row: int, column: int) -> np.ndarray:
        """The surface point seen at a pixel, in head coordinates."""
        return np.array([self.x_of(column), -self.front[row, column], self.z_of(row)])


def _box_blur(image: np.ndarray, radius: int) -> np.ndarray:
    """Mean over a (2r+1)^2 window, edges clamped; summed-area table so it costs the same at any radius."""
    padded = np.pad(image, radius + 1, mode="edge")
    table = padded.cumsum(0).cumsum(1)
    size = 2 * radius + 1
    total = table[size:, size:] - table[:-size, size:] - table[size:, :-size] + table[:-size, :-size]
    return total[: image.shape[0], : image.shape[1]] / size**2


# ---------------------------------------------------------------- landmarks


# Turns that bring a face looking elsewhere to look toward -Y with Z up, tried in this order when the
# face is not found as it stands: looking toward +Y (a VRM 0.x avatar), toward +X or -X, lying on its
# back (looking toward +Z) or on its face (-Z).
FACINGS: tuple[tuple[str, np.ndarray], ...] = (
    ("+Y", np.array([[-1.0, 0, 0], [0, -1, 0], [0, 0, 1]])),
    ("+X", np.array([[0.0, 1, 0], [-1, 0, 0], [0, 0, 1]])),
    ("-X", np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])),
    ("+Z", np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])),
    ("-Z", np.array([[1.0, 0, 0], [0, 0, 1], [0, -1, 0]])),
)


def find_landmarks(vertices: np.ndarray, polygons) -> dict[str, np.ndarray]:
    """The landmarks of LANDMARK_NAMES as (3,) points in the mesh's coordinates, and those of
    LID_LANDMARK_NAMES where the mesh's eyeballs show between its lids.

    A face looking toward -Y with Z up is searched first; when none is found there, the head is turned
    to each other facing (FACINGS), then tilted (TILTS), and searched again; a face found leaning or
    turned is searched once more seen straight on. Raises HeadError when no view shows a face (no nose
    above a mouth, no eyes).
    """
    vertices = np.asarray(vertices, np.float64)
    if vertices.ndim != 2 or vertices.shape[1] != 3 or len(vertices) < 4:
        raise HeadError("The head mesh has too few vertices to find a face on; import a head mesh.")
    if not np.isfinite(vertices).all():
        raise HeadError("The head mesh has vertices at infinite or undefined positions; clean up the mesh.")
    triangles = triangulate(polygons)
    if triangles.size and (triangles.min() < 0 or triangles.max() >= len(vertices)):
        raise HeadError("The head mesh has polygons that refer to missing vertices; clean up the mesh.")
    return _search_views(vertices, triangles)


def axis_rotation(axis: int, degrees: float) -> np.ndarray:
    """The 3x3 rotation by `degrees` about coordinate axis `axis` (0 X, 1 Y, 2 Z)."""
    first, second = [index for index in range(3) if index != axis]
    angle = np.radians(degrees)
    turn = np.eye(3)
    turn[first, first] = turn[second, second] = np.cos(angle)
    turn[first, second], turn[second, first] = -np.sin(angle), np.sin(angle)
    return turn


# Tilts tried on a head that shows no face along any axis: rolled (about the view axis Y), pitched
# (about X) and turned (about Z) by these many degrees. A head rolled 10 degrees showed no mouth.
TILTS: tuple[np.ndarray, ...] = tuple(
    axis_rotation(axis, sign * degrees)
    for axis, steps in ((1, (15, 30)), (0, (15, 30)), (2, (20,)))
    for degrees in steps
    for sign in (1, -1)
)
# A face whose line across (mouth and eye corners) runs more than this far aslant in the view it was
# found in is searched again in a view turned to level it, so the depth map's rows run along its mouth.
REFINE_DEGREES = 3.0
# Seen straight on, every landmark must come back within this share of the face's size: further, and one
# of the two views read something else as a face (a forehead as the nose of a head looking down, a
# mouth corner run out along a cheek), so the search goes on.
AGREEMENT = 0.08


def _search_views(vertices: np.ndarray, triangles: np.ndarray) -> dict[str, np.ndarray]:
    """The landmarks of the first view that shows a face and agrees with itself seen straight on: looking
    toward -Y, then each other facing, then -Y and +Y tilted by TILTS (view = mesh @ turn.T)."""
    first_error, doubtful = None, None
    views = [np.eye(3), *(turn for _, turn in FACINGS)]
    views += [tilt @ facing for facing in views[:2] for tilt in TILTS]
    for turn in views:
        try:
            found = _find_facing_front(vertices @ turn.T, triangles)
        except HeadError as error:
            first_error = first_error or error
            continue
        found = {name: point @ turn for name, point in found.items()}
        refined, disagreement = _seen_straight_on(vertices, triangles, found, turn)
        if disagreement <= AGREEMENT:
            return refined
        if doubtful is None or disagreement < doubtful[1]:
            doubtful = (found, disagreement)
    if doubtful is not None:
        return doubtful[0]
    raise HeadError(
        f"{first_error} (The head was also searched turned to look toward +Y, +X, -X, up and down, "
        "and tilted.)"
    ) from first_error


def _seen_straight_on(vertices, triangles, found, turn) -> tuple[dict[str, np.ndarray], float]:
    """(landmarks, disagreement): when the line across the face (mouth corners, inner eye corners) runs
    aslant in the view it was found in (a head rolled or turned a little), the landmarks found again in a
    view turned to run along it, and how far the furthest moved (share of the face's size); the landmarks
    as found, 0, when the face was seen level. (Only roll and turn are corrected: the lean of the chin
    below the eyes is a matter of proportions as much as of pose.)"""
    view_across, view_up = turn[0], turn[2]
    across = (found["mouth_corner_left"] - found["mouth_corner_right"]) + (
        found["eye_inner_left"] - found["eye_inner_right"]
    )
    across /= np.linalg.norm(across)
    if np.degrees(np.arccos(np.clip(across @ view_across, -1.0, 1.0))) <= REFINE_DEGREES:
        return found, 0.0
    up = view_up - (view_up @ across) * across
    up /= np.linalg.norm(up)
    level = np.stack((across, np.cross(up, across), up))  # view = mesh @ level.T, as turn is
    try:
        again = _find_facing_front(vertices @ level.T, triangles)
    except HeadError:
        return found, np.inf
    again = {name: point @ level for name, point in again.items()}
    names = [name for name in found if name in again]
    points = np.array([found[name] for name in names])
    size = float(np.linalg.norm(np.ptp(points, axis=0)))
    moved = max(np.linalg.norm(again[name] - found[name]) for name in names) / size
    return again, float(moved)


# How far the line from the chin to the eyes leans back from the vertical on an upright face (measured on
# the reference head: 7.8 degrees), so that face_frame leaves an upright head as it is.
FACE_LEAN_DEGREES = 7.8


def face_frame(landmarks) -> tuple[np.ndarray, np.ndarray]:
    """(origin, axes) of the face: axes' columns point to the face's left, back and up, so that
    (points - origin) @ axes shows the face looking toward -Y with Z up, however the head is turned."""
    lm = {name: np.asarray(point, np.float64) for name, point in landmarks.items()}
    across = (lm["mouth_corner_left"] - lm["mouth_corner_right"]) + (
        lm["eye_inner_left"] - lm["eye_inner_right"]
    )
    across /= np.linalg.norm(across)
    eyes = 0.25 * (
        lm["eye_inner_left"] + lm["eye_inner_right"] + lm["eye_outer_left"] + lm["eye_outer_right"]
    )
    leaning = eyes - lm["chin"]  # up, and back by the face's lean: the eyes sit behind the chin
    leaning -= (leaning @ across) * across
    leaning /= np.linalg.norm(leaning)
    leaning_back = np.cross(leaning, across)
    lean = np.radians(FACE_LEAN_DEGREES)
    up = np.cos(lean) * leaning - np.sin(lean) * leaning_back
    back = np.sin(lean) * leaning + np.cos(lean) * leaning_back
    return lm["nose_tip"], np.stack((across, back, up), axis=1)


def hidden_face_share(vertices: np.ndarray, polygons, landmarks) -> float:
    """The share of the face (between the outer eye corners, from the brows to the chin, seen from the
    front) that other pieces of the same mesh hide: pieces standing in front of the skin there, eyeballs
    aside. MakeHuman's raw base mesh keeps its hair and clothing helpers over the face; a beard or lashes
    hide a little of it."""
    names = ("nose_tip", "chin", "eye_outer_left", "eye_outer_right", "brow_left", "brow_right")
    framing = ("mouth_corner_left", "mouth_corner_right", "eye_inner_left", "eye_inner_right")  # face_frame
    if not all(name in landmarks for name in names + framing):
        return 0.0
    origin, axes = face_frame(landmarks)
    upright = (np.asarray(vertices, np.float64) - origin) @ axes
    marks = {name: (np.asarray(landmarks[name], np.float64) - origin) @ axes for name in names}
    triangles = triangulate(polygons)
    labels = connected_pieces(len(upright), triangles)
    skin_label = labels[np.argmin(np.linalg.norm(upright - marks["nose_tip"], axis=1))]
    on_skin = labels[triangles[:, 0]] == skin_label
    if on_skin.all():
        return 0.0
    height = float(np.mean([marks["brow_left"][2], marks["brow_right"][2]]) - marks["chin"][2])
    if height <= 0:
        return 0.0
    # Only what lies over the face, from the right eye's outer corner to the left's, chin to brows.
    low = np.array([marks["eye_outer_right"][0], marks["chin"][2]])
    high = np.array([marks["eye_outer_left"][0], marks["chin"][2] + height])
    corners = upright[triangles][:, :, [0, 2]]
    over = np.all(corners.max(1) >= low, axis=1) & np.all(corners.min(1) <= high, axis=1)
    others = triangles[over & ~on_skin]
    others = others[~_round_pieces(upright, others)]
    if len(others) == 0 or not np.any(over & on_skin):
        return 0.0
    skin = DepthMap(upright, triangles[over & on_skin], height / HIDDEN_FACE_ROWS)
    cover = DepthMap(upright, others, skin.pixel, like=skin)
    rows = slice(max(skin.row_of(high[1]), 0), skin.row_of(low[1]) + 1)
    columns = slice(max(skin.column_of(low[0]), 0), skin.column_of(high[0]) + 1)
    front, hiding = skin.front[rows, columns], cover.front[rows, columns]
    face = np.isfinite(front)
    if not face.any():
        return 0.0
    hidden = face & np.isfinite(hiding) & (hiding > front + HIDDEN_FACE_GAP * height)
    return float(hidden.sum() / face.sum())


def _find_facing_front(vertices: np.ndarray, triangles: np.ndarray) -> dict[str, np.ndarray]:
    head = find_head_region(vertices, triangles)
    # The skin is normally the biggest piece; a hair or helmet mesh can be bigger, so the next biggest
    # pieces get their turn when no face is found on it.
    first_error = None
    for skin in _biggest_pieces(len(vertices), triangles, head):
        try:
            return _landmarks_on_piece(vertices, triangles, skin)
        except HeadError as error:
            first_error = first_error or error
    raise first_error


def _biggest_pieces(vertex_count: int, triangles: np.ndarray, among: np.ndarray | None, count: int = 3):
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


def _landmarks_on_piece(
    vertices: np.ndarray, triangles: np.ndarray, skin: np.ndarray
) -> dict[str, np.ndarray]:
    keep = np.zeros(len(vertices), bool)
    keep[skin] = True
    skin_triangles = triangles[keep[triangles].all(1)]
    if len(skin_triangles) == 0:
        raise HeadError("The head's biggest piece has no whole faces above the neck to find a face on.")
    size = float(np.ptp(vertices[skin, 2]))
    if size <= 0 or np.ptp(vertices[skin, 0]) <= 0:
        raise HeadError("The head mesh is flat; a head must stand upright (Z up) and face -Y.")
    depth = DepthMap(vertices, skin_triangles, size / DEPTH_MAP_ROWS)
    # Eyeballs (and anything else not of the skin) seen in front of it: the eye openings, where there are.
    other_triangles = triangles[~keep[triangles].any(1)]
    other_triangles = other_triangles[_round_pieces(vertices, other_triangles)]
    others = DepthMap(vertices, other_triangles, depth.pixel, like=depth) if len(other_triangles) else None
    points = _FaceReader(depth, size, others).landmarks()
    _check_proportions(points)
    return points


def _round_pieces(vertices: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Which triangles belong to pieces about as deep and tall as wide (eyeballs), not to flat ones
    (lashes, corneas, clothing)."""
    if len(triangles) == 0:
        return np.zeros(0, bool)
    labels = connected_pieces(len(vertices), triangles)[triangles[:, 0]]
    keep = np.zeros(len(triangles), bool)
    for label in np.unique(labels):
        mine = labels == label
        extent = np.ptp(vertices[np.unique(triangles[mine])], axis=0)
        keep[mine] = extent.min() > 0.6 * extent.max()
    return keep


def _check_proportions(points: dict[str, np.ndarray], widths: bool = True) -> None:
    """Refuse landmarks no face has (a 'mouth' a tenth as wide as the eyes are apart: a crease in hair)."""
    mouth = np.linalg.norm(points["mouth_corner_left"] - points["mouth_corner_right"])
    eyes = np.linalg.norm(points["eye_outer_left"] - points["eye_outer_right"])
    heights = [points[name][2] for name in ("brow_left", "eye_inner_left", "nose_tip", "upper_lip", "chin")]
    # The eyes' inner corners lie apart, the left one toward +X: a head looking up far enough shows its
    # chin as the most forward point, and what lies above it (the lips) is no pair of eyes.
    inner_gap = points["eye_inner_left"][0] - points["eye_inner_right"][0]
    if (
        (widths and not 0.3 * eyes < mouth < 1.5 * eyes)
        or np.any(np.diff(heights) >= 0)
        or inner_gap < 0.15 * eyes
    ):
        raise HeadError(
            "What looks like a face toward -Y has no face's proportions (mouth width against the eyes' "
            "distance, the eyes apart, brows over eyes over nose over mouth over chin); place the "
            "landmark markers."
        )


class _FaceReader:
    """Reads the face off a depth map: nose, lips and chin on the midline, then mouth corners, eyes, brows."""

    def __init__(self, depth: DepthMap, size: float, others: DepthMap | None = None) -> None:
        self.depth = depth
        # Where another piece (an eyeball) shows in front of the skin, or through a hole in it.
        self.showing = np.zeros(depth.front.shape, bool)
        if others is not None:
            with np.errstate(invalid="ignore"):
                self.showing = np.isfinite(others.front) & ~(depth.front > others.front + 0.002 * size)
        self.size = size
        front = depth.front
        valid = np.isfinite(front)
        if valid.sum() < 100:
            raise HeadError("The head mesh covers too little of the front view to find a face.")
        # Holes (eye and mouth openings of a mask) count as deep recesses.
        self.floor = np.nanmin(front) - 0.05 * size
        self.filled = np.where(valid, front, self.floor)
        self.valid = valid
        self.groove = self._groove_strength()

    def pixels(self, fraction: float) -> int:
        return max(1, int(round(fraction * self.size / self.depth.pixel)))

    def landmarks(self) -> dict[str, np.ndarray]:
        nose_row, mid = self.nose_tip()
        mouth_row = self.mouth_line(nose_row, mid)
        points = {"nose_tip": self.depth.point(nose_row, mid)}
        points.update(self.midline(nose_row, mouth_row, mid))
        points.update(self.mouth_corners(mouth_row, mid))
        points.update(self.eyes_and_brows(nose_row, mid))
        return points

    def nose_tip(self) -> tuple[int, int]:
        """The most forward point near the vertical midline, between the forehead and the jaw."""
        rows = np.flatnonzero(self.valid.any(1))
        columns = np.flatnonzero(self.valid.any(0))
        centre = (columns[0] + columns[-1]) // 2
        half = self.pixels(0.04)
        top = rows[0] + int(0.25 * (rows[-1] - rows[0]))
        bottom = rows[0] + int(0.85 * (rows[-1] - rows[0]))
        window = np.where(self.valid, self.depth.front, -np.inf)[
            top:bottom, centre - half : centre + half + 1
        ]
        if not np.isfinite(window).any():
            raise HeadError("No surface faces -Y near the middle of the head; turn the face toward -Y.")
        row, column = np.unravel_index(np.argmax(window), window.shape)
        return top + int(row), centre - half + int(column)

    def _groove_strength(self) -> np.ndarray:
        """How much deeper each pixel is than the pixels a little above and below it (a horizontal crease)."""
        padded = np.pad(self.filled, ((3, 3), (0, 0)), mode="edge")
        rows = self.filled.shape[0]
        strength = np.zeros_like(self.filled)
        for step in (1, 2, 3):
            above = padded[3 - step : 3 - step + rows]
            below = padded[3 + step : 3 + step + rows]
            strength = np.maximum(strength, np.minimum(above, below) - self.filled)
        return strength

    def _bowl_depth(self, reach: int) -> np.ndarray:
        """How far a pixel lies below its surroundings both vertically and sideways: a socket or an opening.

        A crease or the side of the nose is low in one direction only, so it scores nothing.
        """
        padded = np.pad(self.filled, reach, mode="edge")
        rows, columns = self.filled.shape
        vertical = np.zeros_like(self.filled)
        sideways = np.zeros_like(self.filled)
        for step in np.unique(np.linspace(1, reach, 8).astype(int)):
            up = padded[reach - step : reach - step + rows, reach : reach + columns]
            down = padded[reach + step : reach + step + rows, reach : reach + columns]
            left = padded[reach : reach + rows, reach - step : reach - step + columns]
            right = padded[reach : reach + rows, reach + step : reach + step + columns]
            vertical = np.maximum(vertical, np.minimum(up, down) - self.filled)
            sideways = np.maximum(sideways, np.minimum(left, right) - self.filled)
        return np.minimum(vertical, sideways)

    def follow_crease(self, row: int, column: int, direction: int, threshold: float, steps: int):
        """Walk sideways along a horizontal crease while it stays deeper than threshold; its last pixel."""
        last = (row, column)
        weak = 0
        height, width = self.groove.shape
        for _ in range(steps):
            column += direction
            if not 2 <= column < width - 2:
                break
            window = self.groove[max(row - 2, 0) : row + 3, column]
            best = int(np.argmax(window))
            if window[best] < threshold:
                weak += 1
                if weak >= 2:
                    break
                continue
            weak = 0
            row = max(row - 2, 0) + best
            last = (row, column)
        return last

    def mouth_line(self, nose_row: int, mid: int) -> int:
        """The row of the crease (or gap) between the lips, the strongest horizontal groove under the nose."""
        first = nose_row + self.pixels(0.04)
        last = min(nose_row + self.pixels(0.3), self.filled.shape[0] - 1)
        if last <= first:
            raise HeadError("The head mesh ends just below the nose; no mouth was found under it.")
        half = self.pixels(0.03)
        strength = self.groove[first:last, max(mid - half, 0) : mid + half + 1]
        score = np.median(np.minimum(strength, 0.02 * self.size), axis=1)
        if score.max() <= 1e-4 * self.size:
            raise HeadError(
                "No mouth found under the nose (no crease or gap between lips facing -Y). Turn the head so "
                "its face looks toward -Y with Z up (Blender's front view), or place the landmark markers."
            )
        return first + int(np.argmax(score))

    def midline(self, nose_row: int, mouth_row: int, mid: int) -> dict[str, np.ndarray]:
        """Lips, their contact line and the chin on the vertical profile through the nose tip."""
        profile = self.filled[:, mid - 1 : mid + 2].max(1)
        reach = self.pixels(0.05)
        upper = mouth_row - reach + int(np.argmax(profile[mouth_row - reach : mouth_row]))
        lower = mouth_row + 1 + int(np.argmax(profile[mouth_row + 1 : mouth_row + reach + 1]))
        # Behind the lips by more than a few millimetres is the inside of the mouth (or a hole): the gap.
        gap_depth = min(profile[upper], profile[lower]) - 0.02 * self.size
        upper_inner = mouth_row
        while upper_inner > upper + 1 and profile[upper_inner] < gap_depth:
            upper_inner -= 1
        lower_inner = mouth_row
        while lower_inner < lower - 1 and profile[lower_inner] < gap_depth:
            lower_inner += 1
        if profile[mouth_row] < gap_depth:
            upper_inner = min(upper_inner, mouth_row - 1)
            lower_inner = max(lower_inner, mouth_row + 1)
        column_rows = np.flatnonzero(self.valid[:, mid])
        end = min(nose_row + self.pixels(0.45), column_rows[-1])
        start = lower + self.pixels(0.03)
        # Under the chin the surface turns to face down: the profile falls back faster than it descends,
        # and keeps falling (the groove under a full lower lip falls steeply too, but only millimetres).
        rows = np.arange(start, end + 1)
        ahead = profile[np.minimum(rows + self.pixels(UNDER_CHIN_RUN), end)] - profile[rows]
        steep = np.diff(profile[rows]) < -1.5 * self.depth.pixel
        falls = np.flatnonzero(steep & (ahead[:-1] < -UNDER_CHIN_FALL * self.size))
        if falls.size:
            end = start + int(falls[0])
        if end <= start:
            raise HeadError("The head mesh ends below the lower lip: no chin was found. Include the chin.")
        # The chin is the most forward point below the groove under the lower lip; a receding chin with
        # no groove: where a line from the lower lip first touches the profile below (its support point).
        below = np.arange(start, end + 1)
        values = profile[below]
        dip_before = np.minimum.accumulate(values)
        bulges = below[
            (values - dip_before > 0.001 * self.size) & (values >= np.maximum.accumulate(values[::-1])[::-1])
        ]
        if bulges.size:
            chin = int(bulges[0])
        else:
            chin = int(below[np.argmax((values - profile[lower]) / (below - lower))])
        point = self.depth.point
        return {
            "upper_lip": point(upper, mid),
            "lower_lip": point(lower, mid),
            "upper_lip_inner": point(upper_inner, mid),
            "lower_lip_inner": point(lower_inner, mid),
            "chin": point(chin, mid),
        }

    def mouth_corners(self, mouth_row: int, mid: int) -> dict[str, np.ndarray]:
        """Follow the crease between the lips sideways from the midline until it fades: the mouth corners."""
        # A gap between parted lips is far deeper than the crease near the corners: cap the reference.
        reference = min(
            np.median(self.groove[mouth_row - 1 : mouth_row + 2, mid - 2 : mid + 3].max(0)), 0.006 * self.size
        )
        steps = self.pixels(0.16)
        corners = {}
        for name, direction in (("mouth_corner_left", 1), ("mouth_corner_right", -1)):
            row, column = self.follow_crease(mouth_row, mid, direction, 0.25 * reference, steps)
            corners[name] = self._surface_near(row, column)
        return corners

    def eyes_and_brows(self, nose_row: int, mid: int) -> dict[str, np.ndarray]:
        """The eyes are the sockets on each side above the nose tip; the brows the ridge above them."""
        top = max(nose_row - self.pixels(0.3), 1)
        bottom = nose_row - self.pixels(0.04)
        bowl = self._bowl_depth(self.pixels(0.06))
        recess = _box_blur(self.filled, self.pixels(0.04)) - self.filled
        points = {}
        for side, direction in (("left", 1), ("right", -1)):
            near, far = mid + direction * self.pixels(0.03), mid + direction * self.pixels(0.26)
            first, last = max(min(near, far), 0), max(near, far)
            socket = bowl[top:bottom, first : last + 1]
            if socket.size == 0 or socket.max() <= 0.002 * self.size:
                raise HeadError(
                    f"No {side} eye found beside the nose (no socket where an eye should be). "
                    "Turn the head so its face looks toward -Y with Z up, or place the landmark markers."
                )
            seed = np.unravel_index(np.argmax(socket), socket.shape)
            window = recess[top:bottom, first : last + 1]
            blob = _grow_blob(window > min(0.015 * self.size, 0.5 * window[seed]), seed)
            rows, columns = np.nonzero(blob)
            if rows.size == 0:
                raise HeadError(
                    f"No {side} eye found beside the nose (its socket is too shallow to outline). "
                    "Turn the head so its face looks toward -Y with Z up, or place the landmark markers."
                )
            distance = np.abs(first + columns - mid)
            inner_column, outer_column = distance.min(), distance.max()
            inner_row = top + int(np.median(rows[distance == inner_column]))
            outer_row = top + int(np.median(rows[distance == outer_column]))
            # The opening narrows below a pixel toward the corners; its crease goes on to where the lids meet.
            threshold, steps = 0.004 * self.size, self.pixels(0.04)
            inner = self.follow_crease(
                inner_row, mid + direction * int(inner_column), -direction, threshold, steps
            )
            outer = self.follow_crease(
                outer_row, mid + direction * int(outer_column), direction, threshold, steps
            )
            opening = self._eye_opening(top, bottom, first, last, seed, mid)
            if opening is not None:
                inner, outer = opening
                # The lids' margins above and below the middle of the opening, where a blink meets.
                upper_margin, lower_margin = self.lid_margins
                points[f"upper_lid_{side}"] = self.depth.point(*upper_margin)
                points[f"lower_lid_{side}"] = self.depth.point(*lower_margin)
            elif socket[seed] < 0.01 * self.size or abs(outer[1] - inner[1]) < self.pixels(0.07):
                # Closed, smooth eyes (a low-poly mask): no opening or crease to read the corners from.
                # Faces put the eye centres about a fifth of the face's width either side of the middle,
                # and an eye is about as wide as the distance from its centre to the middle.
                row = top + int(seed[0])
                covered = np.flatnonzero(self.valid[row])
                centre = 0.2 * (covered[-1] - covered[0])
                inner = (row, mid + direction * int(round(0.5 * centre)))
                outer = (row, mid + direction * int(round(1.5 * centre)))
            points[f"eye_inner_{side}"] = self._surface_near(*inner)
            points[f"eye_outer_{side}"] = self._surface_near(*outer)
            centre_column = (inner[1] + outer[1]) // 2
            # The socket's recess may run on up a flat forehead: the eye ends a little above its corners.
            corners_row = min(inner[0], outer[0])
            eye_top = min(corners_row, max(top + rows.min(), corners_row - self.pixels(EYE_HEIGHT)))
            brow_rows = np.arange(max(eye_top - self.pixels(0.1), 0), eye_top)
            brow_row = int(brow_rows[np.argmax(self.filled[brow_rows, centre_column])])
            points[f"brow_{side}"] = self.depth.point(brow_row, centre_column)
        return points

    def _eye_opening(self, top: int, bottom: int, first: int, last: int, seed, mid: int) -> tuple | None:
        """(inner, outer) corner pixels of the eyeball seen through the lids, nearest the socket's
        deepest point; None when no separate eyeball shows there (eyes of the skin, or painted)."""
        window = self.showing[top:bottom, first : last + 1]
        if window.sum() < 8:
            return None
        rows, columns = np.nonzero(window)
        nearest = np.argmin((rows - seed[0]) ** 2 + (columns - seed[1]) ** 2)
        blob = _grow_blob(window, (rows[nearest], columns[nearest]))
        rows, columns = np.nonzero(blob)
        touches_border = rows.min() == 0 or columns.min() == 0
        touches_border |= rows.max() == window.shape[0] - 1 or columns.max() == window.shape[1] - 1
        if np.ptp(columns) < self.pixels(0.05) or touches_border:
            return None  # too small for an eye, or a sheet over the face (clothing helpers), not an eyeball
        ends = [
            (top + int(np.median(rows[columns == end])), first + int(end))
            for end in (columns.min(), columns.max())
        ]
        centre = (columns.min() + columns.max()) // 2
        margins = rows[columns == centre]
        self.lid_margins = (
            (top + int(margins.min()) - 1, first + centre),
            (top + int(margins.max()) + 1, first + centre),
        )
        return tuple(sorted(ends, key=lambda end: abs(end[1] - mid)))

    def _surface_near(self, row: int, column: int) -> np.ndarray:
        """The pixel's point on the bottom of its crease: skin around it, not the inside of an opening."""
        reach = self.pixels(0.006)
        patch = self.filled[
            max(row - reach, 0) : row + reach + 1, max(column - reach, 0) : column + reach + 1
        ]
        rim = patch.max()
        skin = patch[patch >= rim - 0.02 * self.size]
        return np.array([self.depth.x_of(column), -skin.min(), self.depth.z_of(row)])


def _grow_blob(mask: np.ndarray, seed: tuple[int, int]) -> np.ndarray:
    """The 4-connected region of a boolean mask that contains the seed pixel."""
    blob = np.zeros_like(mask)
    blob[seed] = True
    while True:
        grown = blob.copy()
        grown[1:] |= blob[:-1]
        grown[:-1] |= blob[1:]
        grown[:, 1:] |= blob[:, :-1]
        grown[:, :-1] |= blob[:, 1:]
        grown &= mask
        if np.array_equal(grown, blob):
            return blob
        blob = grown


# ---------------------------------------------------------------- landmarks from a head's own keys


def landmarks_from_motion(
    vertices: np.ndarray,
    polygons,
    mouth_open: np.ndarray,
    blink_left: np.ndarray | None = None,
    blink_right: np.ndarray | None = None,
) -> dict[str, np.ndarray]:
    """Landmarks read off what a head's own keys move, for faces whose shape shows no mouth or eyes
    (a mouth painted on the texture that only a key opens, stylised eyes).

    mouth_open: deltas of a key that opens the mouth; blink_*: of the blinks (the eyes are placed by the
    face's usual proportions without them). The face looks where the mouth lies from the head's centre.
    """
    vertices = np.asarray(vertices, np.float64)
    triangles = triangulate(polygons)
    mouth = _moved(mouth_open)
    if len(mouth) < 2:
        raise HeadError("The mouth-opening key moves nothing; place the landmark markers instead.")
    centre = vertices[np.unique(triangles)].mean(0)
    mouth_centre = vertices[mouth].mean(0)
    forward = np.array([mouth_centre[0] - centre[0], mouth_centre[1] - centre[1], 0.0])
    if np.linalg.norm(forward) == 0:
        raise HeadError("The mouth lies at the head's centre; place the landmark markers instead.")
    forward /= np.linalg.norm(forward)
    # A turn about Z taking forward to -Y; upright = points @ turn.T.
    turn = np.array([[-forward[1], forward[0], 0.0], [-forward[0], -forward[1], 0.0], [0.0, 0.0, 1.0]])
    upright = vertices @ turn.T
    points = _mouth_from_motion(upright, mouth, mouth_open @ turn.T)
    width = float(np.linalg.norm(points["mouth_corner_left"] - points["mouth_corner_right"]))
    for side, blink in (("left", blink_left), ("right", blink_right)):
        points.update(_eye_from_motion(upright, side, blink, points, width))
    points["nose_tip"] = _front_point(
        upright, points, 0.5 * (points["eye_inner_left"][2] + points["upper_lip"][2])
    )
    # The chin: the lowest point on the midline below the mouth, in front of the head's middle.
    below = np.abs(upright[:, 0] - points["upper_lip"][0]) < 0.15 * width
    below &= (upright[:, 1] < points["upper_lip"][1] + 1.5 * width) & (upright[:, 2] < points["lower_lip"][2])
    if not below.any():
        raise HeadError("No chin found below the mouth the key opens; place the landmark markers instead.")
    points["chin"] = upright[below][np.argmin(upright[below, 2])]
    _check_proportions(points, widths=False)  # stylised faces: big eyes over a small mouth
    return {name: point @ turn for name, point in points.items()}


def _moved(deltas: np.ndarray | None) -> np.ndarray:
    if deltas is None:
        return np.empty(0, np.int64)
    size = np.linalg.norm(np.asarray(deltas, np.float64), axis=1)
    return np.flatnonzero(size > 0.2 * size.max()) if size.max() > 0 else np.empty(0, np.int64)


def _mouth_from_motion(upright: np.ndarray, mouth: np.ndarray, deltas: np.ndarray) -> dict[str, np.ndarray]:
    """Corners at the sides of what the key moves; the lips above and below the middle of the line."""
    moved = upright[mouth]
    left, right = moved[np.argmax(moved[:, 0])], moved[np.argmin(moved[:, 0])]
    middle_x = 0.5 * (left[0] + right[0])
    width = float(left[0] - right[0])
    seam = 0.5 * (left[2] + right[2])
    front = upright[np.abs(upright[:, 2] - seam) < 0.2 * width]
    front = front[np.abs(front[:, 0] - middle_x) < 0.2 * width]
    front_y = float(front[:, 1].min()) if len(front) else float(moved[:, 1].min())
    lowered = deltas[mouth, 2] < 0
    lip = 0.15 * width
    upper_z = max(seam + lip, float(moved[~lowered, 2].max()) if (~lowered).any() else seam + lip)
    lower_z = min(seam - lip, float(moved[lowered, 2].min()) if lowered.any() else seam - lip)
    return {
        "upper_lip": np.array([middle_x, front_y, upper_z]),
        "lower_lip": np.array([middle_x, front_y, lower_z]),
        "upper_lip_inner": np.array([middle_x, front_y, seam]),
        "lower_lip_inner": np.array([middle_x, front_y, seam]),
        "mouth_corner_left": left,
        "mouth_corner_right": right,
    }


def _eye_from_motion(upright, side, blink, mouth_points, mouth_width) -> dict[str, np.ndarray]:
    """An eye's corners at the sides of what its blink moves, or where faces put eyes without one."""
    direction = 1 if side == "left" else -1
    middle_x = mouth_points["upper_lip"][0]
    moved = _moved(None if blink is None else blink @ np.eye(3))
    if len(moved) >= 2:
        points = upright[moved]
        inner = points[np.argmin(np.abs(points[:, 0] - middle_x))]
        outer = points[np.argmax(np.abs(points[:, 0] - middle_x))]
        height = float(np.median(points[:, 2]))
        inner, outer = inner.copy(), outer.copy()
        inner[2] = outer[2] = height
    else:
        height = mouth_points["upper_lip"][2] + 1.3 * mouth_width
        inner = _front_point(upright, mouth_points, height, middle_x + direction * 0.35 * mouth_width)
        outer = _front_point(upright, mouth_points, height, middle_x + direction * 1.2 * mouth_width)
    eye_width = float(abs(outer[0] - inner[0]))
    brow = _front_point(upright, mouth_points, inner[2] + 0.6 * eye_width, 0.5 * (inner[0] + outer[0]))
    return {f"eye_inner_{side}": inner, f"eye_outer_{side}": outer, f"brow_{side}": brow}


def _front_point(upright, mouth_points, height, x=None) -> np.ndarray:
    """The most forward vertex near (x, height): the face's surface there."""
    x = mouth_points["upper_lip"][0] if x is None else x
    width = float(np.linalg.norm(mouth_points["mouth_corner_left"] - mouth_points["mouth_corner_right"]))
    near = np.hypot(upright[:, 0] - x, upright[:, 2] - height) < 0.25 * width
    if not near.any():
        near = (
            np.hypot(upright[:, 0] - x, upright[:, 2] - height)
            <= np.hypot(upright[:, 0] - x, upright[:, 2] - height).min()
        )
    candidates = upright[near]
    return candidates[np.argmin(candidates[:, 1])].copy()


def landmark_layout_in_box(
    reference_landmarks: dict[str, np.ndarray],
    reference_skin: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
) -> dict[str, np.ndarray]:
    """The reference's landmarks scaled into a box, on its -Y face: a start for markers a user then moves.

    Used where no face can be found on a head, so the markers workflow has something to move.
    """
    low, high = reference_skin.min(axis=0), reference_skin.max(axis=0)
    lower, upper = np.asarray(lower, np.float64), np.asarray(upper, np.float64)
    scale = float(np.min((upper - lower)[[0, 2]] / np.maximum((high - low)[[0, 2]], 1e-12)))
    centre = (lower + upper) / 2
    reference_centre = (low + high) / 2
    layout = {}
    for name, point in reference_landmarks.items():
        placed = centre + (np.asarray(point, np.float64) - reference_centre) * scale
        placed[1] = lower[1] + (point[1] - low[1]) * scale  # the face's depth from the box's front
        layout[name] = placed
    return layout
