"""Motion: the 37 viseme and 6 emotion shape-key weights over time, at a frame rate.

Two models over one timeline: the thesis's linear morphing (thesis.py) and the default co-articulated model
(natural.py), with their frame helpers below them (frames.py) and the quality report above them (quality.py).
"""

from __future__ import annotations

from ..model import Timeline, WeightTracks
from .natural import natural_weight_tracks
from .thesis import thesis_weight_tracks

MOTION_MODES = ("natural", "thesis")


def weight_tracks(
    timeline: Timeline, fps: float, mode: str = "natural", emotion_strength: float = 1.0, **options
) -> WeightTracks:
    """The weight tracks of a timeline in the chosen motion model ("natural" is the default)."""
    if fps <= 0:
        raise ValueError(f"frame rate must be positive, got {fps}")
    if mode == "thesis":
        return thesis_weight_tracks(timeline, fps, emotion_strength)
    if mode == "natural":
        return natural_weight_tracks(timeline, fps, emotion_strength, **options)
    raise ValueError(f"unknown motion mode {mode!r}; choose one of {', '.join(MOTION_MODES)}")
