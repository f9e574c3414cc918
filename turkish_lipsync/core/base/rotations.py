"""Rotations in the character's own frame (x toward its left, y up, z forward), as HeadAndEyes defines them.

Shared by the living layers (motion), the eyes of a head (faces), the exports and the Blender layer: below
both peer stages, so that neither imports the other and the sign conventions live in one place.
"""

from __future__ import annotations

import numpy as np


def head_matrices(angles: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotations from (N, 3) yaw, pitch, roll in degrees: R = R_yaw R_pitch R_roll."""
    yaw, pitch, roll = np.radians(np.asarray(angles, np.float64)).T
    return _yaw_pitch_roll(yaw, pitch, roll)


def eye_matrices(angles: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotations of eyes from (N, 2 or 3) yaw, pitch (, roll) in degrees, applied in that order."""
    angles = np.asarray(angles, np.float64)
    yaw, pitch = np.radians(angles[:, :2]).T
    roll = np.radians(angles[:, 2]) if angles.shape[1] > 2 else np.zeros(len(angles))
    return _yaw_pitch_roll(yaw, pitch, roll)


def direction(yaw: np.ndarray, pitch: np.ndarray) -> np.ndarray:
    """(N, 3) unit vectors looking yaw degrees toward the left and pitch degrees up from forward (+z)."""
    yaw, pitch = np.radians(yaw), np.radians(pitch)
    return np.stack([np.sin(yaw) * np.cos(pitch), np.sin(pitch), np.cos(yaw) * np.cos(pitch)], axis=-1)


def angles_of(vectors: np.ndarray) -> np.ndarray:
    """(N, 2) yaw, pitch in degrees of (N, 3) directions (the inverse of direction)."""
    x, y, z = np.asarray(vectors, np.float64).T
    return np.degrees(np.stack([np.arctan2(x, z), np.arctan2(y, np.hypot(x, z))], axis=1))


def _yaw_pitch_roll(yaw: np.ndarray, pitch: np.ndarray, roll: np.ndarray) -> np.ndarray:
    """(N, 3, 3) R_y(yaw) R_x(-pitch) R_z(roll), angles in radians (right-handed rotations about the axes),
    multiplied out: less than half the time of three matrices per frame and two products."""
    cy, sy, cp, sp, cr, sr = (
        np.cos(yaw),
        np.sin(yaw),
        np.cos(pitch),
        -np.sin(pitch),
        np.cos(roll),
        np.sin(roll),
    )
    m = np.empty((np.size(yaw), 3, 3))
    m[:, 0, 0] = cy * cr + sy * sp * sr
    m[:, 0, 1] = sy * sp * cr - cy * sr
    m[:, 0, 2] = sy * cp
    m[:, 1, 0] = cp * sr
    m[:, 1, 1] = cp * cr
    m[:, 1, 2] = -sp
    m[:, 2, 0] = cy * sp * sr - sy * cr
    m[:, 2, 1] = sy * sr + cy * sp * cr
    m[:, 2, 2] = cy * cp
    return m
