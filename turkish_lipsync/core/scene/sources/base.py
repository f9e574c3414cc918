"""What a scene's speech source is, and what it is asked for."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...base.model import Utterance
from ...base.registry import Registry
from ...speech.aligner_settings import DEFAULT_ALIGNER, AlignerSettings
from ...text.script import Script
from ..cast import Cast


@dataclass(frozen=True, eq=False)
class SceneRequest:
    """A script to speak with its cast, and how: what every scene source may need."""

    script: Script
    cast: Cast
    utterances: tuple[Utterance, ...]  # each line's, in its speaker's voice
    timing: str = "phone"
    rate: float = 1.0
    engine: str = "espeak"
    seed: int = 0
    scene_recording: Path | None = None
    speaker_recordings: dict[str, Path] | None = None  # by speaker's key
    line_recordings: tuple[Path, ...] = ()
    cues: Path | None = None
    aligner: AlignerSettings = DEFAULT_ALIGNER

    @property
    def addressees(self) -> tuple[str, ...]:
        return self.script.addressees()

    def rng(self) -> np.random.Generator:
        """The scene's own draws (the gaps between turns), from its seed."""
        return np.random.default_rng([self.seed, 31])


class SceneSource:
    name: str = ""
    given_as: str = ""  # how an error names what the user gave ("a recording of the whole scene")
    priority: int = 0  # asked first when higher

    def claims(self, request: SceneRequest) -> bool:
        raise NotImplementedError

    def speak(self, request: SceneRequest):
        """The scene's SceneSpeech (scene/speech.py)."""
        raise NotImplementedError


SCENE_SOURCES: Registry[SceneSource] = Registry("scene speech source", __package__, Path(__file__).parent)


def scene_source_for(request: SceneRequest) -> SceneSource:
    """The source that speaks this request: the first, by priority, that claims it."""
    for source in sorted(SCENE_SOURCES.entries().values(), key=lambda source: -source.priority):
        if source.claims(request):
            return source
    raise AssertionError("the lines' own voices claim every request no other source takes")
