"""The parts of a head beside its skin, told by where they sit and what they touch.

Heads arrive with their eyes, teeth, tongue, gums, lashes and eye shells as separate objects, as islands
of the head's own mesh, or split from the skin by material only; names differ from head to head,
geometry does not. Each piece (a connected island, or a run of one material) is judged in the face's own
frame:

- round pieces about an eye wide by an eye are eyeballs; pieces that lie on an eyeball without touching
  the lids (cornea, iris) go with it; an eye's other pieces (lashes, occlusion shells, tear lines,
  caruncles) touch the lids and ride them;
- pieces inside the mouth, behind the lips, are teeth (reaching forward to the lips, upper or lower by
  the lip line), a tongue (further back), or a piece reaching both jaws (gums and tongue in one, both
  rows of teeth) that the transfer divides vertex by vertex;
- every other piece (brows as cards, a beard, hair) rides the skin it sits on.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from .closest import nearest_vertices
from .depth import DepthMap
from .eyes import sphere_fit
from .landmarks import face_frame
from .topology import connected_pieces, edge_graph, geodesic_distance, triangulate

# Vertices this close (a share of the mesh's size) are one place: pieces touching there are one.
WELD_DISTANCE = 1e-6
# Kinds of piece, and how each moves: eyes as solids with the eyeball; teeth with their jaw; the tongue
# bends as the reference's does; "mouth" pieces reach both jaws; riders follow the skin they touch.
EYE_KINDS = ("eyeball", "cornea")
JAW_KINDS = ("upper_teeth", "lower_teeth", "tongue", "mouth")
RIDER_KINDS = ("lashes", "eye_shell", "rider")
# A piece touches the lids where its rim lies within this many eye widths of the skin.
TOUCH_DISTANCE = 0.06
# A cornea or iris: within CORNEA_REACH eyeball radii of its centre, no wider than
# CORNEA_SPREAD degrees from its own middle, which looks no further than CORNEA_FACING from forward.
CORNEA_REACH = 1.15
CORNEA_SPREAD = 50.0
CORNEA_FACING = 25.0
# A piece reaches both jaws when its upper and lower fronts (within JAW_FRONT mouth widths of its front)
# are joined along its edges only by a detour this many times their distance.
JAW_FRONT = 0.35
BOTH_JAWS_DETOUR = 2.5


@dataclass(frozen=True)
class Piece:
    kind: str  # one of EYE_KINDS, JAW_KINDS, RIDER_KINDS
    side: str  # "left" or "right" for an eye's pieces, "" for the rest
    indices: np.ndarray  # sorted vertex indices


@dataclass(frozen=True)
class HeadParts:
    """A head's skin and the pieces beside it (vertex indices into the head's vertices)."""

    skin: np.ndarray
    pieces: tuple[Piece, ...]

    def indices(self, *kinds: str, side: str | None = None) -> np.ndarray:
        """The vertices of every piece of the given kinds (of one side only, when side is given)."""
        found = [
            piece.indices
            for piece in self.pieces
            if piece.kind in kinds and (side is None or piece.side == side)
        ]
        return np.sort(np.concatenate(found)) if found else np.empty(0, np.int64)

    @property
    def eye_balls(self) -> dict[str, np.ndarray]:
        """Each side's eyeball pieces (not its cornea), where the head has them."""
        found = {side: self.indices("eyeball", side=side) for side in ("left", "right")}
        return {side: indices for side, indices in found.items() if len(indices)}


def find_parts(
    vertices: np.ndarray, polygons, landmarks: Mapping[str, np.ndarray], materials: np.ndarray | None = None
) -> HeadParts:
    """The head's skin and its other pieces (Piece kinds), from the mesh's islands and, where given, its
    materials (one per triangle of triangulate(polygons)): a run of one material is a piece of its own
    when it is a solid part (an eyeball, teeth, a tongue) even if it is joined to the skin; other
    material runs joined to the skin stay skin (lips or lids painted with a material of their own).
    """
    origin, axes = face_frame(landmarks)
    upright = (np.asarray(vertices, np.float64) - origin) @ axes
    marks = {name: (np.asarray(point, np.float64) - origin) @ axes for name, point in landmarks.items()}
    triangles = triangulate(polygons)
    islands = _islands(upright, triangles)
    used = np.zeros(len(upright), bool)
    used[triangles.ravel()] = True
    skin_island = np.bincount(islands[used], minlength=len(upright)).argmax()
    on_skin_island = used & (islands == skin_island)
    runs = _material_runs(len(upright), triangles, materials)
    reader = _PieceReader(upright, triangles, marks)
    pieces: list[Piece] = []
    skin = on_skin_island.copy()
    for label in np.unique(islands[used & ~on_skin_island]):
        pieces.append(reader.classify(np.flatnonzero(used & (islands == label))))
    if runs is not None:
        skin_run = _run_at(runs, on_skin_island, upright, marks["nose_tip"])
        for run in runs:
            run = run[on_skin_island[run]]
            if run is skin_run or len(run) == 0 or len(run) > 0.5 * on_skin_island.sum():
                continue
            piece = reader.classify(run)
            if piece.kind in ("eyeball", "upper_teeth", "lower_teeth", "tongue"):
                inner = run[~np.isin(run, skin_run)]  # the seam with the skin stays skin
                pieces.append(Piece(piece.kind, piece.side, inner))
                skin[inner] = False
    pieces = reader.settle_the_eyes(pieces, np.flatnonzero(skin))
    kept = []
    for piece, surface in zip(pieces, reader.of_the_surface(pieces, np.flatnonzero(skin)), strict=True):
        if surface:
            skin[piece.indices] = True  # a piece of the face's own surface (a stylised face in pieces)
        else:
            kept.append(piece)
    return HeadParts(skin=np.flatnonzero(skin), pieces=tuple(kept))


def _islands(vertices: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """A label per vertex: its connected piece, vertices at one place counted as one (game exports split
    a face's mesh along its UV seams and hard edges: Godette's face arrives as 27 islands, its lids and
    eyes among them, that are one surface)."""
    size = float(np.ptp(vertices, axis=0).max()) if len(vertices) else 1.0
    cells = np.round(vertices / max(WELD_DISTANCE * size, 1e-300)).astype(np.int64)
    _, place = np.unique(cells, axis=0, return_inverse=True)
    place = place.ravel()
    labels = connected_pieces(int(place.max()) + 1, place[triangles])
    return labels[place]


def _material_runs(vertex_count: int, triangles: np.ndarray, materials) -> list[np.ndarray] | None:
    """Vertex sets of the runs of one material (triangles of one material joined by shared vertices);
    a vertex on the border between two materials belongs to both."""
    if materials is None:
        return None
    materials = np.asarray(materials, np.int64)
    if len(materials) != len(triangles) or len(np.unique(materials)) < 2:
        return None
    _, material = np.unique(materials, return_inverse=True)
    copies = triangles + material[:, None] * vertex_count  # each material's own copy of the vertices
    labels = connected_pieces(int(material.max() + 1) * vertex_count, copies)
    runs = []
    corner_labels = labels[copies.ravel()]
    corner_vertices = triangles.ravel()
    order = np.argsort(corner_labels, kind="stable")
    bounds = np.flatnonzero(np.diff(corner_labels[order], prepend=-1, append=-1))
    for start, stop in zip(bounds[:-1], bounds[1:], strict=True):
        runs.append(np.unique(corner_vertices[order[start:stop]]))
    return runs


def _run_at(runs: list[np.ndarray], on_skin: np.ndarray, upright: np.ndarray, nose_tip) -> np.ndarray:
    """The run holding the skin vertex nearest the nose tip: the face's own material."""
    candidates = np.flatnonzero(on_skin)
    nearest = candidates[np.argmin(np.linalg.norm(upright[candidates] - nose_tip, axis=1))]
    return next(run for run in runs if nearest in run)


class _PieceReader:
    """Judges pieces against the face's landmarks (all in the face's frame: -Y forward, Z up)."""

    def __init__(self, upright: np.ndarray, triangles: np.ndarray, marks) -> None:
        self.upright, self.triangles = upright, triangles
        corner_left, corner_right = marks["mouth_corner_left"], marks["mouth_corner_right"]
        self.mouth_width = float(np.linalg.norm(corner_left - corner_right))
        self.lip_line = 0.5 * (marks["upper_lip_inner"][2] + marks["lower_lip_inner"][2])
        self.lips_front = min(marks["upper_lip"][1], marks["lower_lip"][1])
        self.mouth_x = 0.5 * (corner_left[0] + corner_right[0])
        self.eyes = {
            side: (
                0.5 * (marks[f"eye_inner_{side}"] + marks[f"eye_outer_{side}"]),
                float(np.linalg.norm(marks[f"eye_inner_{side}"] - marks[f"eye_outer_{side}"])),
            )
            for side in ("left", "right")
        }

    def classify(self, indices: np.ndarray) -> Piece:
        points = self.upright[indices]
        centre = points.mean(0)
        for side, (eye_centre, eye_width) in self.eyes.items():
            offset = centre - eye_centre
            sideways = np.hypot(offset[0], offset[2])
            if (
                sideways < 0.6 * eye_width
                and _is_ball(points, eye_width)
                and -0.3 < offset[1] / eye_width < 1.2
            ):
                return Piece("eyeball", side, indices)
            if sideways < 0.8 * eye_width and -1.0 * eye_width < offset[1] < 1.2 * eye_width:
                return Piece("eye_shell", side, indices)  # settled once the eyeballs are known
        inside_mouth = (
            abs(centre[0] - self.mouth_x) < 0.6 * self.mouth_width
            and abs(centre[2] - self.lip_line) < 0.6 * self.mouth_width
            and self.lips_front < centre[1] < self.lips_front + 1.5 * self.mouth_width
        )
        if not inside_mouth:
            return Piece("rider", "", indices)
        if points[:, 1].min() - self.lips_front >= 0.3 * self.mouth_width:
            return Piece("tongue", "", indices)  # it does not reach forward to the lips
        height = (points[:, 2] - self.lip_line) / self.mouth_width
        if self._reaches_both_jaws(indices, height):
            return Piece("mouth", "", indices)
        return Piece("upper_teeth" if height.mean() >= 0 else "lower_teeth", "", indices)

    def _reaches_both_jaws(self, indices: np.ndarray, height: np.ndarray) -> bool:
        """Whether a piece inside the mouth holds both an upper front and a lower front (a tenth of a mouth
        width above and below the lip line, within JAW_FRONT of the piece's front) that its own edges join
        only the long way round (BOTH_JAWS_DETOUR times their distance): upper and lower gums meeting at
        the back of the mouth, not one row of teeth whose tips rise past the lip line."""
        points = self.upright[indices]
        front = points[:, 1] - points[:, 1].min() < JAW_FRONT * self.mouth_width
        upper = np.flatnonzero(front & (height > 0.1))
        lower = np.flatnonzero(front & (height < -0.1))
        if len(upper) == 0 or len(lower) == 0:
            return False
        local = np.full(len(self.upright), -1, np.int64)
        local[indices] = np.arange(len(indices))
        own = self.triangles[(local[self.triangles] >= 0).all(1)]
        edges, lengths = edge_graph(len(self.upright), own, self.upright)
        along = geodesic_distance(len(indices), local[edges], lengths, upper, np.ones(len(indices), bool))[
            lower
        ]
        across = float(nearest_vertices(points[upper], points[lower])[1].min())
        return bool(along.min() > BOTH_JAWS_DETOUR * max(across, 1e-12 * self.mouth_width))

    def settle_the_eyes(self, pieces: list[Piece], skin: np.ndarray) -> list[Piece]:
        """An eye's pieces other than its eyeball: on the eyeball and clear of the lids, a cornea or iris
        (it turns with the eye); otherwise lashes or a shell, which ride the lids. Without an eyeball,
        a piece well behind the eye's corners that does not touch the lids is the eye."""
        settled = []
        for piece in pieces:
            if piece.kind != "eye_shell":
                settled.append(piece)
                continue
            eye_centre, eye_width = self.eyes[piece.side]
            points = self.upright[piece.indices]
            balls = [other for other in pieces if other.kind == "eyeball" and other.side == piece.side]
            if balls:
                ball = self.upright[np.concatenate([other.indices for other in balls])]
                settled.append(Piece(_on_the_eyeball(points, ball), piece.side, piece.indices))
                continue
            touching = self._rim_touches(piece.indices, skin, eye_width)
            behind = (points.mean(0)[1] - eye_centre[1]) / eye_width
            if behind > 0.15 and not touching:
                settled.append(Piece("eyeball", piece.side, piece.indices))
            elif _hugs_a_ball(points, eye_width):
                settled.append(Piece("eye_shell", piece.side, piece.indices))
            else:
                settled.append(Piece("lashes", piece.side, piece.indices))
        return settled

    def of_the_surface(self, pieces: list[Piece], skin: np.ndarray) -> list[bool]:
        """Per piece, whether it is part of the face's surface rather than something on it: a piece that
        would ride the skin but has none behind it over most of its vertices in the front view fills a
        gap in the skin (Godette's face comes as pieces: its lids and the skin around its eyes are
        pieces beside the rest), where lashes, shells and brow cards lie over the skin."""
        riding = [piece.kind in RIDER_KINDS for piece in pieces]
        if not any(riding):
            return riding
        on_skin = np.zeros(len(self.upright), bool)
        on_skin[skin] = True
        depth = DepthMap(self.upright, self.triangles[on_skin[self.triangles].all(1)], self.mouth_width / 30)
        rows = np.clip(
            np.round((depth.top - self.upright[:, 2]) / depth.pixel).astype(int), 0, depth.front.shape[0] - 1
        )
        columns = np.clip(
            np.round((self.upright[:, 0] - depth.left) / depth.pixel).astype(int), 0, depth.front.shape[1] - 1
        )
        behind = np.isfinite(depth.front[rows, columns])
        return [
            ride and behind[piece.indices].mean() < 0.5 for ride, piece in zip(riding, pieces, strict=True)
        ]

    def _rim_touches(self, indices: np.ndarray, skin: np.ndarray, eye_width: float) -> bool:
        """Whether most of the piece's open rim (or, for a closed piece, any of it) lies on the skin."""
        rim = _open_rim(self.triangles, indices)
        if len(rim) == 0:
            return False
        _, distance = nearest_vertices(self.upright[rim], self.upright[skin], TOUCH_DISTANCE * eye_width)
        return bool(np.mean(distance <= TOUCH_DISTANCE * eye_width) > 0.5)


def _on_the_eyeball(points: np.ndarray, ball: np.ndarray) -> str:
    """What a piece beside an eyeball is: a cornea (or iris) hugs the eyeball as a cap round its
    forward axis (Vitruvian's: 36 degrees across); a shell hugs it too but spans the eye's opening or
    lies along a lid (occlusion, tear line); anything standing off it is lashes."""
    centre = ball.mean(0)
    radius = float(np.linalg.norm(ball - centre, axis=1).mean())
    offsets = points - centre
    reach = np.linalg.norm(offsets, axis=1) / radius
    directions = offsets / np.maximum(np.linalg.norm(offsets, axis=1, keepdims=True), 1e-300)
    middle = directions.mean(0)
    middle /= max(np.linalg.norm(middle), 1e-300)
    spread = np.degrees(np.arccos(np.clip(directions @ middle, -1.0, 1.0))).max()
    facing = np.degrees(np.arccos(np.clip(-middle[1], -1.0, 1.0)))  # from the face's forward, -Y
    if reach.max() < CORNEA_REACH and spread < CORNEA_SPREAD and facing < CORNEA_FACING:
        return "cornea"
    if np.mean((reach > 0.85) & (reach < 1.2)) >= 0.7:
        return "eye_shell"
    return "lashes"


def _hugs_a_ball(points: np.ndarray, eye_width: float) -> bool:
    """A piece lying on a sphere about an eyeball's size, bulging toward the viewer (an occlusion shell
    over an eye whose eyeball is not in the mesh); lash cards curl the other way, or round no ball."""
    if len(points) < 10:
        return False
    centre, radius, spread = sphere_fit(points)
    return 0.3 * eye_width < radius < 1.0 * eye_width and spread < 0.08 and centre[1] > points[:, 1].mean()


def _open_rim(triangles: np.ndarray, indices: np.ndarray) -> np.ndarray:
    """The vertices of a piece's edges that only one of its triangles has (its open rim)."""
    mine = np.zeros(int(triangles.max()) + 1, bool)
    mine[indices] = True
    own = triangles[mine[triangles].all(1)]
    edges = np.sort(np.concatenate((own[:, [0, 1]], own[:, [1, 2]], own[:, [2, 0]])), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    return np.unique(unique[counts == 1])


def _is_ball(points: np.ndarray, eye_width: float) -> bool:
    """A closed, round piece about an eye wide: an eyeball, wherever its centre sits."""
    radius = np.linalg.norm(points - points.mean(0), axis=1)
    return bool(radius.std() < 0.15 * radius.mean() and 0.25 * eye_width < radius.mean() < 0.8 * eye_width)
