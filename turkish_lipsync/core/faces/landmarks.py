"""Face landmarks found from the geometry of a head that looks toward -Y with Z up.

Users import heads of every scale, topology and origin, often without named parts, so the landmarks that
register the reference head onto theirs are found from the shape alone: the head is cut from the body at
the neck, a front-view depth map is rasterised, the midline profile below the nose gives the lips and the
chin, the groove between the lips runs sideways to the mouth corners, and the eyes are the recesses
beside the nose with the brows above them. Left means the character's left, which is +X.
"""

from __future__ import annotations

import functools

import numpy as np

from ..base.errors import HeadError, LipSyncError
from .depth import DepthMap
from .face_reader import FaceReader
from .reference import load_reference_head
from .topology import biggest_pieces, largest_piece, round_triangles, triangulate

# Slices (of 200, from the top) where find_head_region looks for no neck yet.
CROWN_SLICES = 10
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
    found = _search_views(vertices, triangles)
    # A lid's margin read off a degenerate eye may be undefined: it is left out, as where none shows.
    found = {
        name: point for name, point in found.items() if np.isfinite(point).all() or name in LANDMARK_NAMES
    }
    undefined = [name for name, point in found.items() if not np.isfinite(point).all()]
    if undefined:
        raise HeadError(
            f"The face's {', '.join(undefined)} could not be placed on this mesh; place the markers with "
            "Show Landmarks, or clean up the mesh."
        )
    return found


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
    for axis, steps in ((1, (15, 30)), (0, (15, 30)), (2, (10, 20)))
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
# A face the reference's landmarks show standing this far off the view it was read in (degrees) is read
# again facing them, and nodding from there by these.
POSE_DEGREES = 7.0
POSE_NODS = (-10.0, 10.0)
POSE_ROUNDS = 3
# A reading its own pose stands more than POSE_DEGREES off counts this much worse (a share of the face's
# size) than the reference's fit of it says; nods are tried where the fit facing the pose is worse than
# POSE_FIT.
OFF_POSE_DOUBT = 0.02
POSE_FIT = 0.05
# A reading the reference's landmarks fit this badly (_fit_template: the furthest landmark, as a share of
# the face's size) is doubted even when it agrees with itself: the bent faces of lab/measure/transfer.py
# read at most 0.07, a "face" read off the chin and neck of a head turned 12 degrees 0.16.
DOUBTFUL_MISFIT = 0.1


def _search_views(vertices: np.ndarray, triangles: np.ndarray, posing: bool = True) -> dict[str, np.ndarray]:
    """The landmarks of the first view that shows a face and agrees with itself seen straight on: looking
    toward -Y, then each other facing, then -Y and +Y tilted by TILTS (view = mesh @ turn.T). posing:
    each reading is also read again facing the pose the reference's landmarks fitted onto it show
    (_facing_the_reference), and a reading they fit worse than DOUBTFUL_MISFIT is doubted; of the
    doubted readings the one they fit best is taken when no view gives a sure one. Without posing, the
    doubted reading that agrees best with itself."""
    first_error, doubtful = None, None  # doubtful: (landmarks, how doubtful) of the best reading not taken
    views = [np.eye(3), *(turn for _, turn in FACINGS)]
    views += [tilt @ facing for facing in views[:2] for tilt in TILTS]
    for turn in views:
        try:
            found = _find_facing_front(vertices @ turn.T, triangles)
        except HeadError as error:
            first_error = first_error or error
            continue
        found = {name: point @ turn for name, point in found.items()}
        refined, disagreement, _ = _seen_straight_on(vertices, triangles, found, turn)
        agrees = disagreement <= AGREEMENT
        if posing:
            # The pose is judged against the view the face was first read in: a face corrected only for
            # roll and turn, still nodding, is read again.
            reading, doubt = _facing_the_reference(vertices, triangles, refined if agrees else found, turn)
            sure = agrees and doubt <= DOUBTFUL_MISFIT
        else:
            reading, doubt, sure = (refined if agrees else found), disagreement, agrees
        if sure:
            return reading
        if doubtful is None or doubt < doubtful[1]:
            doubtful = (reading, doubt)
    if doubtful is not None:
        return doubtful[0]
    raise HeadError(
        f"{first_error} (The head was also searched turned to look toward +Y, +X, -X, up and down, "
        "and tilted.)"
    ) from first_error


def _facing_the_reference(vertices, triangles, found, turn) -> tuple[dict[str, np.ndarray], float]:
    """(landmarks, doubt): the reference head's landmarks fitted onto a reading show the face's pose (a
    nodding head too: face_frame reads roll and turn, not nod); a reading standing more than
    POSE_DEGREES off its own view is read again facing that pose, up to POSE_ROUNDS times, and nodding by
    POSE_NODS from there where it still fits badly (over POSE_FIT). Of the readings, the one the reference
    fits best (_fit_template) with OFF_POSE_DOUBT added for a reading its pose stands off (one read at a
    slant misplaces a feature: a chin 19 % of the face off, that fit only 0.003 worse than read straight)."""
    template = _template_landmarks()
    if template is None:
        return found, 0.0
    readings, current, view = [(found, turn)], found, turn
    for _ in range(POSE_ROUNDS):
        facing = _fit_template(template, current)[0].T  # view = mesh @ facing.T shows it upright
        if _angle_between(facing, view) <= POSE_DEGREES:
            break
        again = _read_in_view(vertices, triangles, facing)
        if again is None:
            break
        readings.append((again, facing))
        current, view = again, facing
    if len(readings) > 1 and _fit_template(template, current)[1] > POSE_FIT:
        for degrees in POSE_NODS:
            nodding = axis_rotation(0, degrees) @ view
            again = _read_in_view(vertices, triangles, nodding)
            if again is not None:
                readings.append((again, nodding))
    doubts = []
    for reading, seen_from in readings:
        rotation, misfit = _fit_template(template, reading)
        doubts.append(misfit + OFF_POSE_DOUBT * (_angle_between(rotation.T, seen_from) > POSE_DEGREES))
    best = int(np.argmin(doubts))
    return readings[best][0], doubts[best]


def _read_in_view(vertices, triangles, view) -> dict[str, np.ndarray] | None:
    """The landmarks read in a view (view = mesh @ view.T), in the mesh's frame; None where none are."""
    try:
        found = _find_facing_front(vertices @ view.T, triangles)
    except HeadError:
        return None
    return {name: point @ view for name, point in found.items()}


def _angle_between(first: np.ndarray, second: np.ndarray) -> float:
    """Degrees of the rotation between two views (rotation matrices)."""
    return float(np.degrees(np.arccos(np.clip((np.trace(first @ second.T) - 1) / 2, -1.0, 1.0))))


def _fit_template(template, found) -> tuple[np.ndarray, float]:
    """(rotation, misfit): the pose of found landmarks against the reference's, and how far the
    furthest of them (brows aside: they differ most from face to face) lies from an affine fit of the
    reference's (which takes up a face's other proportions, not a feature read off its place), as a
    share of the face's size."""
    names = [name for name in LANDMARK_NAMES if name in found and not name.startswith("brow")]
    source = np.array([template[name] for name in names])
    target = np.array([found[name] for name in names])
    size = float(np.linalg.norm(np.ptp(target, axis=0))) if len(target) else 0.0
    if len(target) < 4 or not np.isfinite(target).all() or size <= 0:
        return np.eye(3), np.inf  # landmarks that cannot be a face (a degenerate mesh): no pose
    design = np.hstack((source, np.ones((len(source), 1))))
    try:
        affine, *_ = np.linalg.lstsq(design, target, rcond=None)
        # The pose: the rotation of the affine fit (its polar part), which a face's other proportions (a
        # longer chin, a wider jaw) leave alone, where a similarity fit turns to meet them.
        u, _, vt = np.linalg.svd(affine[:3].T)
    except np.linalg.LinAlgError:
        return np.eye(3), np.inf
    rotation = u @ np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))]) @ vt
    return rotation, float(np.linalg.norm(design @ affine - target, axis=1).max()) / size


@functools.cache
def _template_landmarks() -> dict[str, np.ndarray] | None:
    """The reference head's landmarks as this reader finds them (its picked vertices follow another
    convention, which set the pose of the reference turned 5 degrees 6.5 degrees off); None where its
    data cannot be read."""
    try:
        reference = load_reference_head()
    except LipSyncError:
        return None
    return _search_views(np.asarray(reference.vertices, np.float64), triangulate(reference.polygons), False)


def _seen_straight_on(vertices, triangles, found, turn) -> tuple[dict[str, np.ndarray], float, np.ndarray]:
    """(landmarks, disagreement, the view they were read in): when the line across the face (mouth
    corners, inner eye corners) runs aslant in the view it was found in (a head rolled or turned a
    little), the landmarks found again in a view turned to run along it, and how far the furthest moved
    (share of the face's size); the landmarks as found, 0, when the face was seen level. (Only roll and
    turn are corrected here: the lean of the chin below the eyes is a matter of proportions as much as of
    pose; _facing_the_reference reads the nod.)"""
    view_across, view_up = turn[0], turn[2]
    across = (found["mouth_corner_left"] - found["mouth_corner_right"]) + (
        found["eye_inner_left"] - found["eye_inner_right"]
    )
    across /= np.linalg.norm(across)
    if np.degrees(np.arccos(np.clip(across @ view_across, -1.0, 1.0))) <= REFINE_DEGREES:
        return found, 0.0, turn
    up = view_up - (view_up @ across) * across
    up /= np.linalg.norm(up)
    level = np.stack((across, np.cross(up, across), up))  # view = mesh @ level.T, as turn is
    try:
        again = _find_facing_front(vertices @ level.T, triangles)
    except HeadError:
        return found, np.inf, turn
    again = {name: point @ level for name, point in again.items()}
    names = [name for name in found if name in again]
    points = np.array([found[name] for name in names])
    size = float(np.linalg.norm(np.ptp(points, axis=0)))
    moved = max(np.linalg.norm(again[name] - found[name]) for name in names) / size
    return again, float(moved), level


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


def _find_facing_front(vertices: np.ndarray, triangles: np.ndarray) -> dict[str, np.ndarray]:
    head = find_head_region(vertices, triangles)
    # The skin is normally the biggest piece; a hair or helmet mesh can be bigger, so the next biggest
    # pieces get their turn when no face is found on it.
    first_error = None
    for skin in biggest_pieces(len(vertices), triangles, head):
        try:
            return _landmarks_on_piece(vertices, triangles, skin)
        except HeadError as error:
            first_error = first_error or error
    raise first_error


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
    other_triangles = other_triangles[round_triangles(vertices, other_triangles)]
    others = DepthMap(vertices, other_triangles, depth.pixel, like=depth) if len(other_triangles) else None
    points = FaceReader(depth, size, others).landmarks()
    check_proportions(points)
    return points


def check_proportions(points: dict[str, np.ndarray], widths: bool = True) -> None:
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
