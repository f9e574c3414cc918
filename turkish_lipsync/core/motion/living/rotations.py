"""Rotations in the character's own frame (x toward its left, y up, z forward), as HeadAndEyes defines them.

Shared by the living layers, the exports and the Blender layer, so the sign conventions live in one place.
"""

from __future__ import annotations

import numpy as np


def head_matrices(angles: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotations from (N, 3) yaw, pitch, roll in degrees: R = R_yaw R_pitch R_roll."""
    yaw, pitch, roll = np.radians(np.asarray(angles, np.float64)).T
    return _about(1, yaw) @ _about(0, -pitch) @ _about(2, roll)


def eye_matrices(angles: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotations of eyes from (N, 2 or 3) yaw, pitch (, roll) in degrees, applied in that order."""
    angles = np.asarray(angles, np.float64)
    yaw, pitch = np.radians(angles[:, :2]).T
    roll = np.radians(angles[:, 2]) if angles.shape[1] > 2 else np.zeros(len(angles))
    return _about(1, yaw) @ _about(0, -pitch) @ _about(2, roll)


def direction(yaw: np.ndarray, pitch: np.ndarray) -> np.ndarray:
    """(N, 3) unit vectors looking yaw degrees toward the left and pitch degrees up from forward (+z)."""
    yaw, pitch = np.radians(yaw), np.radians(pitch)
    return np.stack([np.sin(yaw) * np.cos(pitch), np.sin(pitch), np.cos(yaw) * np.cos(pitch)], axis=-1)


def angles_of(vectors: np.ndarray) -> np.ndarray:
    """(N, 2) yaw, pitch in degrees of (N, 3) directions (the inverse of direction)."""
    x, y, z = np.asarray(vectors, np.float64).T
    return np.degrees(np.stack([np.arctan2(x, z), np.arctan2(y, np.hypot(x, z))], axis=1))


def _about(axis: int, angle: np.ndarray) -> np.ndarray:
    """(N, 3, 3) right-handed rotations by angle (radians) about the x (0), y (1) or z (2) axis."""
    c, s = np.cos(angle), np.sin(angle)
    first, second = (axis + 1) % 3, (axis + 2) % 3
    m = np.zeros((np.size(angle), 3, 3))
    m[:, axis, axis] = 1
    m[:, first, first], m[:, first, second], m[:, second, first], m[:, second, second] = c, -s, s, c
    return m
