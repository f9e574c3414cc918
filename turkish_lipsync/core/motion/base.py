"""What a motion model is: a timeline to weight tracks at a frame rate. Models register in MOTION_MODELS."""

from __future__ import annotations

from pathlib import Path

from ..base.model import Timeline, WeightTracks
from ..base.registry import Registry


class MotionModel:
    name: str = ""
    label: str = ""
    description: str = ""

    def weight_tracks(self, timeline: Timeline, fps: float, emotion_strength: float = 1.0) -> WeightTracks:
        raise NotImplementedError


MOTION_MODELS: Registry[MotionModel] = Registry("motion model", __package__, Path(__file__).parent)
