"""Eyes of a head, found from its geometry and its keys: eyeballs, their centres, and the keys that turn them.

An eyeball is a round piece (its own object, or an island of the head's mesh with its cornea); its centre is
fitted to its vertices (a least-squares sphere), whatever the object's origin, so it can turn about it. A
head whose eyes are painted turns them with keys of its own (VRM's look_*, ARKit's eyeLook*, CharMorph's
Look_*): found by name here. Everything is in the head's own frame: x toward the character's left, y up, z
forward (core/base/rotations.py).
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from ..base.model import EYE_SIDES, LOOK_KEY_DEGREES
from ..base.rotations import direction
from .arkit_names import arkit_unit_for_key
from .topology import connected_pieces

ROUNDNESS = 0.12  # an eyeball's vertices lie within this share of its radius from the fitted sphere
CORNEA_REACH = 1.2  # pieces within this many radii of an eyeball's centre are its cornea or iris
# ARKit's per-eye units by where they turn each eye, in the character's frame.
ARKIT_LOOK_UNITS = {
    ("left", "left"): "eyeLookOutLeft",
    ("left", "right"): "eyeLookInLeft",
    ("left", "up"): "eyeLookUpLeft",
    ("left", "down"): "eyeLookDownLeft",
    ("right", "left"): "eyeLookInRight",
    ("right", "right"): "eyeLookOutRight",
    ("right", "up"): "eyeLookUpRight",
    ("right", "down"): "eyeLookDownRight",
}
_WAYS = {"up": "up", "down": "down", "dwn": "down", "dn": "down", "left": "left", "right": "right"}
_PER_EYE = re.compile(r"^(?:eye)?look(up|down|dwn|dn|in|out)(left|right|l|r)$")
_BOTH_EYES = re.compile(r"^(?:eye)?look(up|down|dwn|dn|left|right)$")


@dataclass(frozen=True)
class Ball:
    centre: np.ndarray  # (3,)
    radius: float
    indices: np.ndarray  # vertex indices of the ball and what sits on it (cornea, iris)


def sphere_fit(points: np.ndarray) -> tuple[np.ndarray, float, float]:
    """(centre, radius, largest distance from it as a share of the radius) of a least-squares sphere."""
    points = np.asarray(points, np.float64)
    system = np.column_stack([2 * points, np.ones(len(points))])
    solution, *_ = np.linalg.lstsq(system, (points**2).sum(axis=1), rcond=None)
    centre = solution[:3]
    radius = float(np.sqrt(max(solution[3] + centre @ centre, 1e-18)))
    spread = float(np.abs(np.linalg.norm(points - centre, axis=1) - radius).max() / radius)
    return centre, radius, spread


def round_pieces(vertices: np.ndarray, triangles: np.ndarray, size: float) -> list[Ball]:
    """The mesh's round pieces between 2 % and 12 % of the head's size across (eyeballs), each with the
    pieces that sit on it (a cornea, an iris)."""
    vertices = np.asarray(vertices, np.float64)
    if len(triangles) == 0:
        return []
    labels = connected_pieces(len(vertices), triangles)
    used = np.zeros(len(vertices), bool)
    used[np.asarray(triangles).ravel()] = True
    pieces = [np.flatnonzero((labels == label) & used) for label in np.unique(labels[used])]
    balls, others = [], []
    for piece in pieces:
        if len(piece) < 12:
            others.append(piece)
            continue
        centre, radius, spread = sphere_fit(vertices[piece])
        if spread < ROUNDNESS and 0.01 * size < radius < 0.06 * size:
            balls.append(Ball(centre, radius, piece))
        else:
            others.append(piece)
    result = []
    for ball in balls:
        sitting = [
            piece
            for piece in others
            if np.linalg.norm(vertices[piece] - ball.centre, axis=1).max() < CORNEA_REACH * ball.radius
        ]
        result.append(Ball(ball.centre, ball.radius, np.sort(np.concatenate([ball.indices, *sitting]))))
    return result


def own_look_keys(names: Iterable[str]) -> dict[tuple[str, str], tuple[str, bool]]:
    """(eye, direction) -> (the head's key that turns it, whether the key turns both eyes)."""
    found: dict[tuple[str, str], tuple[str, bool]] = {}
    both_eyes: list[tuple[str, str]] = []
    for name in names:
        unit = arkit_unit_for_key(name)
        eye_way = next((k for k, v in ARKIT_LOOK_UNITS.items() if v == unit), None) if unit else None
        if eye_way is not None:
            found.setdefault(eye_way, (name, False))
            continue
        plain = re.sub(r"[^a-z]", "", name.split("|")[-1].split(":")[-1].lower())
        per_eye = _PER_EYE.match(plain)
        if per_eye:
            way, side = per_eye.groups()
            eye = "left" if side.startswith("l") else "right"
            if way in ("in", "out"):
                inward = "right" if eye == "left" else "left"
                way = eye if way == "out" else inward
            found.setdefault((eye, _WAYS[way]), (name, False))
        elif _BOTH_EYES.match(plain):
            both_eyes.append((name, _WAYS[_BOTH_EYES.match(plain).group(1)]))
    for name, way in both_eyes:  # a key per eye is preferred to one that turns both
        for eye in EYE_SIDES:
            found.setdefault((eye, way), (name, True))
    return found


def turn_degrees(points: np.ndarray, deltas: np.ndarray, centre: np.ndarray, way: str) -> float:
    """How far (degrees, toward `way`) moving points by deltas turns them, in the head frame."""
    # The rotation part of the best rigid fit (Kabsch): an artist's key may also shift the ball a little.
    before = np.asarray(points, np.float64) - centre
    after = before + np.asarray(deltas, np.float64)
    before, after = before - before.mean(axis=0), after - after.mean(axis=0)
    covariance = before.T @ after
    u, _s, vt = np.linalg.svd(covariance)
    rotation = (u @ vt).T
    if np.linalg.det(rotation) < 0:
        return 0.0
    forward = rotation @ np.array([0.0, 0.0, 1.0])
    yaw = np.degrees(np.arctan2(forward[0], forward[2]))
    pitch = np.degrees(np.arctan2(forward[1], np.hypot(forward[0], forward[2])))
    return float({"left": yaw, "right": -yaw, "up": pitch, "down": -pitch}[way])


def rigid_turn(
    points: np.ndarray, centre: np.ndarray, way: str, degrees: float = LOOK_KEY_DEGREES
) -> np.ndarray:
    """Deltas (head frame) that turn points rigidly about centre by `degrees` toward `way`."""
    yaw = {"left": degrees, "right": -degrees}.get(way, 0.0)
    pitch = {"up": degrees, "down": -degrees}.get(way, 0.0)
    forward = direction(np.array([yaw]), np.array([pitch]))[0]
    rotation = _rotation_between(np.array([0.0, 0.0, 1.0]), forward)
    relative = np.asarray(points, np.float64) - centre
    return relative @ rotation.T - relative


def _rotation_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest rotation taking unit vector a to unit vector b (Rodrigues)."""
    axis = np.cross(a, b)
    sine, cosine = np.linalg.norm(axis), float(a @ b)
    if sine < 1e-12:
        return np.eye(3)
    k = axis / sine
    cross = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + sine * cross + (1 - cosine) * cross @ cross
