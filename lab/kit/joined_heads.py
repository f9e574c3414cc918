"""Test heads of the kinds users bring, made from the heads we have: every part one island of the head's
own mesh, lash cards or single lashes along the lid margins, eye-occlusion shells and tear lines over the
eyes, the teeth and tongue welded into one piece (a "gums and tongue" island).

Everything here works on arrays (vertices in the mesh's frame, triangles), without Blender, so the core
tests, lab/measure/parts.py and the Blender tests build the same heads. The parts added here come
with the motion they would have under an artist's key: each lash, shell or tear-line vertex turns about
the eyeball's centre as the lid point it grows from does (exactly at that point, rigidly about the
eyeball elsewhere), which is how rigs carry lashes on the lid.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from turkish_lipsync.core.faces.head_parts import find_parts
from turkish_lipsync.core.faces.landmarks import face_frame
from turkish_lipsync.core.faces.parts import PART_LABELS, find_face_parts
from turkish_lipsync.core.faces.topology import largest_piece, triangulate

MARGIN_SAMPLES = 14  # points along each lid margin, corners aside
LASH_ROWS = 4


@dataclass(frozen=True)
class Eye:
    """One eye of a head, in the mesh's frame: its lid margins (inner corner first) and eyeball."""

    side: str
    upper_margin: np.ndarray  # (K, 3)
    lower_margin: np.ndarray  # (K, 3)
    centre: np.ndarray  # the eyeball's centre
    radius: float
    width: float  # corner to corner
    up: np.ndarray  # the face's up and forward directions
    forward: np.ndarray


@dataclass
class AddedParts:
    """Pieces added to a head: vertices, triangles (indices into the added vertices), and for each added
    vertex the lid point it grows from (index into the eye's margins) and which eye and lid."""

    vertices: list[np.ndarray]
    triangles: list[np.ndarray]
    roots: list[np.ndarray]  # (V, 3) the lid point each vertex follows
    eyes: list[Eye]
    kinds: list[str]

    def arrays(self, offset: int) -> tuple[np.ndarray, np.ndarray]:
        """All added vertices and their triangles, indexed after `offset` existing vertices."""
        triangles, start = [], offset
        for points, faces in zip(self.vertices, self.triangles, strict=True):
            triangles.append(faces + start)
            start += len(points)
        return np.concatenate(self.vertices), np.concatenate(triangles)


def find_eyes(vertices: np.ndarray, triangles: np.ndarray, landmarks) -> list[Eye]:
    """The lid margins of both eyes (the lowest seen point of the upper lid and the highest of the
    lower lid at each of MARGIN_SAMPLES places across the eye) and the eyeballs (found as parts)."""
    origin, axes = face_frame(landmarks)
    upright = (vertices - origin) @ axes
    marks = {name: (np.asarray(point) - origin) @ axes for name, point in landmarks.items()}
    skin = largest_piece(len(vertices), triangles)
    face = find_face_parts(upright, triangles, skin, marks)
    parts = find_parts(vertices, triangles, landmarks)
    eyes = []
    for side in ("left", "right"):
        if side not in parts.eye_balls:
            raise ValueError(f"no {side} eyeball found: shells and truth turn about it")
        ball = upright[parts.eye_balls[side]]
        centre = ball.mean(0)
        radius = float(np.linalg.norm(ball - centre, axis=1).mean())
        inner, outer = marks[f"eye_inner_{side}"], marks[f"eye_outer_{side}"]
        width = float(np.linalg.norm(outer - inner))
        # The lids' own skin in front of the eyeball (the socket's lining shows through the opening too).
        outside = np.linalg.norm(upright - centre, axis=1) > radius
        margins = []
        for lid, pick in (("upper", np.argmin), ("lower", np.argmax)):
            label = PART_LABELS.index(f"{lid}_lid_{side}")
            lid_vertices = np.flatnonzero(face.seen & outside & (face.label == label))
            chosen = []
            for s in np.linspace(0.1, 0.9, MARGIN_SAMPLES):
                x = inner[0] + s * (outer[0] - inner[0])
                near = lid_vertices[np.abs(upright[lid_vertices, 0] - x) < 0.04 * width]
                if len(near) == 0:
                    near = lid_vertices[np.argsort(np.abs(upright[lid_vertices, 0] - x))[:3]]
                vertex = near[pick(upright[near, 2])]
                if vertex not in chosen:  # each lash grows from a vertex of its own
                    chosen.append(vertex)
            points = upright[chosen]
            points = points[np.argsort(points[:, 0])]
            xs = np.linspace(points[0, 0], points[-1, 0], MARGIN_SAMPLES)  # even along the margin
            points = np.stack([np.interp(xs, points[:, 0], points[:, axis]) for axis in range(3)], 1)
            if side == "right":
                points = points[::-1]  # inner corner first
            margins.append(points @ axes.T + origin)
        eyes.append(
            Eye(
                side, margins[0], margins[1], centre @ axes.T + origin, radius, width, axes[:, 2], -axes[:, 1]
            )
        )
    return eyes


def _strip(roots: np.ndarray, directions: np.ndarray, lengths: np.ndarray, rows: int) -> np.ndarray:
    """(K, rows + 1, 3) points of strips growing from roots along directions (K, rows, 3) per row."""
    steps = lengths[:, None, None] / rows * directions
    return np.concatenate((roots[:, None], roots[:, None] + np.cumsum(steps, axis=1)), axis=1)


def _lash_directions(eye: Eye, lid: str, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Per margin point, the direction of each of LASH_ROWS segments (curling away from the eye), and the
    lash's length (longest at the middle of the lid, as lashes are)."""
    sign = 1.0 if lid == "upper" else -1.0
    across = np.cross(eye.forward, eye.up)
    across *= 1.0 if eye.side == "right" else -1.0  # toward the outer corner
    along = np.linspace(0, 1, count)
    angles = np.radians(np.linspace(15.0, 55.0, LASH_ROWS)) * sign
    directions = np.cos(angles)[None, :, None] * eye.forward + np.sin(angles)[None, :, None] * eye.up
    directions = directions + 0.25 * (along - 0.3)[:, None, None] * across
    directions /= np.linalg.norm(directions, axis=2, keepdims=True)
    length = (0.3 if lid == "upper" else 0.17) * eye.width * (0.55 + 0.45 * np.sin(np.pi * along))
    return directions, length


def lash_cards(eyes: list[Eye], strips: int = 3) -> AddedParts:
    """Lash cards (a ribbon of quads per strip) growing from both lids of both eyes; `strips` islands per
    lid, side by side."""
    added = AddedParts([], [], [], eyes, [])
    for eye in eyes:
        for lid in ("upper", "lower"):
            margin = eye.upper_margin if lid == "upper" else eye.lower_margin
            directions, length = _lash_directions(eye, lid, len(margin))
            roots = margin + 0.01 * eye.width * eye.forward  # just in front of the lid's skin
            grid = _strip(roots, directions, length, LASH_ROWS)  # (K, R + 1, 3)
            for columns in np.array_split(np.arange(len(margin)), strips):
                piece = grid[columns]
                k, r = piece.shape[:2]
                index = np.arange(k * r).reshape(k, r)
                quads = np.stack((index[:-1, :-1], index[1:, :-1], index[1:, 1:], index[:-1, 1:]), -1)
                added.vertices.append(piece.reshape(-1, 3))
                added.triangles.append(triangulate(quads.reshape(-1, 4)))
                added.roots.append(np.repeat(margin[columns], r, axis=0))
                added.kinds.append(f"{eye.side} {lid} lash card")
    return added


def lash_strands(eyes: list[Eye], per_lid: int = 14) -> AddedParts:
    """Single lashes, each a thin strip of quads and an island of its own, along both lids."""
    added = AddedParts([], [], [], eyes, [])
    for eye in eyes:
        for lid in ("upper", "lower"):
            margin = eye.upper_margin if lid == "upper" else eye.lower_margin
            directions, length = _lash_directions(eye, lid, len(margin))
            across = np.cross(eye.forward, eye.up) * 0.008 * eye.width
            for column in np.linspace(0, len(margin) - 1, per_lid).round().astype(int):
                root = margin[column] + 0.01 * eye.width * eye.forward
                line = _strip(root[None], directions[column][None], length[column][None], LASH_ROWS)[0]
                points = np.concatenate((line - across, line + across))
                r = len(line)
                quads = np.stack(
                    (np.arange(r - 1), np.arange(1, r), np.arange(r + 1, 2 * r), np.arange(r, 2 * r - 1)), -1
                )
                added.vertices.append(points)
                added.triangles.append(triangulate(quads))
                added.roots.append(np.repeat(margin[column][None], 2 * r, axis=0))
                added.kinds.append(f"{eye.side} {lid} lash")
    return added


def eye_shells(eyes: list[Eye]) -> AddedParts:
    """An eye-occlusion shell over each eyeball (a cap between the lid margins, its rim tucked under the
    lids) and a tear line along each lower margin, where the lid meets the eyeball."""
    added = AddedParts([], [], [], eyes, [])
    for eye in eyes:
        upper = eye.upper_margin - eye.centre
        lower = eye.lower_margin - eye.centre
        for kind, spread, radius in (("occlusion shell", np.linspace(-0.12, 1.12, 9), 1.03),
                                     ("tear line", np.array([-0.05, 0.06]), 1.01)):  # fmt: skip
            directions = lower[:, None] + spread[None, :, None] * (upper - lower)[:, None]
            directions /= np.linalg.norm(directions, axis=2, keepdims=True)
            grid = eye.centre + radius * eye.radius * directions  # (K, rows, 3)
            k, r = grid.shape[:2]
            index = np.arange(k * r).reshape(k, r)
            quads = np.stack((index[:-1, :-1], index[1:, :-1], index[1:, 1:], index[:-1, 1:]), -1)
            # Each row follows the nearer lid: the upper half the upper margin, the lower half the lower.
            roots = np.where(
                (spread >= 0.5)[None, :, None], eye.upper_margin[:, None], eye.lower_margin[:, None]
            )
            added.vertices.append(grid.reshape(-1, 3))
            added.triangles.append(triangulate(quads.reshape(-1, 4)))
            added.roots.append(np.broadcast_to(roots, grid.shape).reshape(-1, 3))
            added.kinds.append(f"{eye.side} {kind}")
    return added


def riding_truth(added: AddedParts, skin_vertices: np.ndarray, skin_deltas: np.ndarray) -> np.ndarray:
    """The added vertices' motion under a key whose skin motion is skin_deltas: each vertex turns about
    its eye's centre as its root on the lid does (the root's motion read off the nearest skin vertices)."""
    motions = []
    for points, roots in zip(added.vertices, added.roots, strict=True):
        eye = min(added.eyes, key=lambda eye: np.linalg.norm(roots.mean(0) - eye.centre))
        moved = np.empty_like(points)
        for row, (point, root) in enumerate(zip(points, roots, strict=True)):
            near = np.argsort(np.linalg.norm(skin_vertices - root, axis=1))[:3]
            root_motion = skin_deltas[near].mean(0)
            before, after = root - eye.centre, root + root_motion - eye.centre
            turn = _rotation_between(before, after)
            moved[row] = eye.centre + turn @ (point - eye.centre) + (after - turn @ before)
        motions.append(moved - points)
    return np.concatenate(motions)


def _rotation_between(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """The smallest rotation turning direction first onto direction second (Rodrigues)."""
    a, b = first / np.linalg.norm(first), second / np.linalg.norm(second)
    axis, cosine = np.cross(a, b), float(a @ b)
    sine = float(np.linalg.norm(axis))
    if sine < 1e-12:
        return np.eye(3)
    axis /= sine
    cross = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + sine * cross + (1 - cosine) * cross @ cross


def weld(vertices: np.ndarray, triangles: np.ndarray, first: np.ndarray, second: np.ndarray, back=False):
    """Triangles joining two pieces into one (at their closest pair of vertices; with back, at the
    closest pair of their deepest fifths, as the mouth's lining joins the gums behind the last teeth)."""
    candidates, others = first, second
    if back:  # the deepest fifth of each (the face looks toward -Y)
        candidates = first[vertices[first, 1] >= np.percentile(vertices[first, 1], 80)]
        others = second[vertices[second, 1] >= np.percentile(vertices[second, 1], 80)]
    gaps = np.linalg.norm(vertices[candidates][:, None] - vertices[others][None], axis=2)
    a, b = np.unravel_index(np.argmin(gaps), gaps.shape)
    a, b = candidates[a], others[b]
    around = triangles[(triangles == a).any(1)]
    neighbour = next(int(v) for v in around.ravel() if v != a)
    return np.array([[a, neighbour, b]])


@dataclass
class KitHead:
    """A test head: one mesh of every part, the motion each key should give it, and which vertices are
    which part (for the report)."""

    name: str
    vertices: np.ndarray
    triangles: np.ndarray
    truth: dict[str, np.ndarray]  # key -> (N, 3) deltas over every vertex
    labels: dict[str, np.ndarray]  # part name -> vertex indices ("skin" among them)
    materials: np.ndarray | None = None  # one per triangle, where the parts differ only by material

    def with_added(self, added: AddedParts, name: str) -> KitHead:
        """The head with the added pieces as islands of its mesh, their motion riding its skin's."""
        points, faces = added.arrays(len(self.vertices))
        skin = self.labels["skin"]
        truth = {
            key: np.concatenate((deltas, riding_truth(added, self.vertices[skin], deltas[skin])))
            for key, deltas in self.truth.items()
        }
        labels = dict(self.labels)
        start = len(self.vertices)
        for kind, piece in zip(added.kinds, added.vertices, strict=True):
            part = kind.split(" ", 1)[1]  # "left upper lash card" -> "upper lash card"
            labels[part] = np.concatenate(
                (labels.get(part, np.empty(0, np.int64)), start + np.arange(len(piece)))
            )
            start += len(piece)
        return KitHead(
            name,
            np.concatenate((self.vertices, points)),
            np.concatenate((self.triangles, faces)),
            truth,
            labels,
        )

    def without(self, *parts: str, name: str) -> KitHead:
        """The head without some of its parts (its eyeballs, say): their vertices and triangles dropped."""
        keep = np.ones(len(self.vertices), bool)
        for part in parts:
            keep[self.labels[part]] = False
        index = np.full(len(self.vertices), -1, np.int64)
        index[keep] = np.arange(keep.sum())
        triangles = self.triangles[keep[self.triangles].all(1)]
        labels = {part: index[found][keep[found]] for part, found in self.labels.items() if part not in parts}
        truth = {key: deltas[keep] for key, deltas in self.truth.items()}
        return KitHead(name, self.vertices[keep], index[triangles], truth, labels)

    def welded(self, joins: list[tuple[str, str, bool]], name: str, by_material: bool = False) -> KitHead:
        """The head with parts joined into one piece by a triangle each (first, second, at the back of
        the first); by_material: the parts tell themselves apart by material only (one per part)."""
        extra = [
            weld(self.vertices, self.triangles, self.labels[a], self.labels[b], back) for a, b, back in joins
        ]
        triangles = np.concatenate((self.triangles, *extra))
        materials = None
        if by_material:
            part_of = np.zeros(len(self.vertices), np.int64)
            for number, part in enumerate(self.labels):
                part_of[self.labels[part]] = number
            materials = part_of[triangles[:, 0]]
        return KitHead(name, self.vertices, triangles, self.truth, self.labels, materials)


def joined_head(name: str, parts: dict[str, tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]]) -> KitHead:
    """One mesh of several: part name -> (vertices, triangles, key -> deltas); the first part is the skin."""
    vertices, triangles, labels, start = [], [], {}, 0
    keys = list(dict.fromkeys(key for _, _, truth in parts.values() for key in truth))
    truth = {key: [] for key in keys}
    for number, (part, (points, faces, deltas)) in enumerate(parts.items()):
        vertices.append(points)
        triangles.append(faces + start)
        labels["skin" if number == 0 else part] = start + np.arange(len(points))
        for key in keys:
            truth[key].append(deltas.get(key, np.zeros_like(points)))
        start += len(points)
    return KitHead(
        name,
        np.concatenate(vertices),
        np.concatenate(triangles),
        {key: np.concatenate(found) for key, found in truth.items()},
        labels,
    )
