"""Motion: the 37 viseme and 6 emotion shape-key weights over time, at a frame rate.

Two models over one timeline, each a `MotionModel` in MOTION_MODELS: the default co-articulated model
(natural.py) and the thesis's linear morphing (thesis.py), with their frame helpers below them (frames.py)
and the quality report above them (quality.py).
"""

from __future__ import annotations

from ..base.model import Timeline, WeightTracks
from .base import MOTION_MODELS, MotionModel


def motion_choices():
    return MOTION_MODELS.choices()


def weight_tracks(
    timeline: Timeline, fps: float, mode: str = "natural", emotion_strength: float = 1.0
) -> WeightTracks:
    """The weight tracks of a timeline in the chosen motion model ("natural" is the default)."""
    if fps <= 0:
        raise ValueError(f"frame rate must be positive, got {fps}")
    return MOTION_MODELS.get(mode).weight_tracks(timeline, fps, emotion_strength)


__all__ = ["MOTION_MODELS", "MotionModel", "motion_choices", "weight_tracks"]
