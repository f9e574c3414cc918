"""Where the characters of a scene stand and where each one's targets are, seen from its own head.

Heads given by the user stand where they are; the default heads stand on an arc open to the camera
(conversation.toml [placement]): neighbours a conversational distance apart, each turned toward the arc's
centre but never so far from the camera that it hides its face. The same arc places the default heads in
Blender and the scene of the core alone (the command line, the tests), whose camera stands in front.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..base.rotations import head_matrices
from ..motion.living import GazeSetup
from ..motion.living.conversation import Surroundings
from ..text.script import CAMERA
from .tables import conversation_table

# The frame of a head at rest facing -Y with Z up (world axes of its left, up, forward), as Blender has the
# default head.
FACING_MINUS_Y = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


@dataclass(frozen=True, eq=False)
class Standing:
    """A character in the world: the pivot its head turns about, its rest frame (columns: its left, up,
    forward) and its eyes (GazeSetup, relative to the pivot in that frame)."""

    pivot: np.ndarray
    frame: np.ndarray
    setup: GazeSetup

    def eyes_middle(self) -> np.ndarray:
        """The point between the eyes, in the world: where the others look at this face."""
        return self.pivot + self.frame @ self.setup.eye_positions().mean(axis=0)

    def seen(self, point: np.ndarray) -> np.ndarray:
        """A world point in this head's rest frame, relative to its pivot."""
        return (np.asarray(point, np.float64) - self.pivot) @ self.frame


def arc_positions(count: int) -> list[tuple[np.ndarray, float]]:
    """(position of each character's pivot, its turn in degrees about the vertical from facing the camera,
    + toward its own left) on the arc, the first on the camera's left; the arc's front at the origin."""
    placement = conversation_table().placement
    if count == 1:
        return [(np.zeros(3), 0.0)]
    step = min(placement.arc_step, placement.arc_span / (count - 1))
    radius = placement.spacing / (2 * math.sin(math.radians(step) / 2))
    result = []
    for index in range(count):
        angle = (index - (count - 1) / 2) * step  # around the centre, + toward the camera's right
        position = np.array(
            [radius * math.sin(math.radians(angle)), radius * math.cos(math.radians(angle)) - radius, 0.0]
        )
        # Facing the centre is a turn of `angle` degrees toward the character's right; at most max_turn.
        turn = -float(np.clip(angle, -placement.max_turn, placement.max_turn))
        result.append((position, turn))
    return result


def turned_frame(turn: float) -> np.ndarray:
    """The rest frame of a head facing -Y turned `turn` degrees about Z (+ toward its left)."""
    c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
    rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return rotation @ FACING_MINUS_Y


def default_standings(keys: tuple[str, ...]) -> tuple[dict[str, Standing], np.ndarray]:
    """The core's own scene: the characters on the arc with default eyes, and a camera in front."""
    standings = {
        key: Standing(position, turned_frame(turn), GazeSetup())
        for key, (position, turn) in zip(keys, arc_positions(len(keys)), strict=True)
    }
    middle = np.mean([standing.eyes_middle() for standing in standings.values()], axis=0)
    camera = middle + np.array([0.0, -conversation_table().placement.camera_distance, 0.0])
    return standings, camera


def surroundings(
    who: str, standings: dict[str, Standing], camera: np.ndarray, faces: dict[str, np.ndarray] | None = None
) -> Surroundings:
    """What `who` may look at, in its own head's frame: every other face (where it is at rest, or at every
    frame: faces, world points by speaker) and the camera."""
    standing = standings[who]
    points = {
        key: standing.seen(faces[key] if faces and key in faces else other.eyes_middle())
        for key, other in standings.items()
        if key != who
    }
    points[CAMERA] = standing.seen(camera)
    return Surroundings(points)


def face_path(standing: Standing, head: np.ndarray) -> np.ndarray:
    """(frames, 3) world points between a character's eyes as its head turns (HeadAndEyes.head angles)."""
    middle = standing.setup.eye_positions().mean(axis=0)
    return standing.pivot + np.einsum("ij,njk,k->ni", standing.frame, head_matrices(head), middle)
