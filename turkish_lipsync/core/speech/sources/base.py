"""What a timing source is, and what it is asked for."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ...base.model import Utterance
from ...base.registry import Registry
from ..aligner_settings import DEFAULT_ALIGNER, AlignerSettings
from ..recognition.settings import DEFAULT_RECOGNISER, RecogniserSettings
from ..timeline import Speech


@dataclass(frozen=True)
class SpeechRequest:
    """A text to speak and how: what every timing source may need."""

    text: str  # JSML or plain text; may be empty where the source has its own (a .pgo)
    timing: str = "phone"  # "phone", "word" or "table" (speech/timeline.py)
    rate: float = 1.0
    recording: Path | None = None
    cues: Path | None = None
    engine: str = "espeak"
    fps: float = 25.0  # for cue files that count frames without saying at what rate
    aligner: AlignerSettings = DEFAULT_ALIGNER  # how a recording is aligned to its text
    recogniser: RecogniserSettings = DEFAULT_RECOGNISER  # how a recording alone is heard


class TimingSource:
    name: str = ""
    label: str = ""
    description: str = ""
    working: str = ""  # what a progress line says while it speaks a request
    priority: int = 0  # asked first when higher

    def claims(self, request: SpeechRequest) -> bool:
        raise NotImplementedError

    def speak(self, request: SpeechRequest) -> tuple[Utterance, Speech]:
        raise NotImplementedError


TIMING_SOURCES: Registry[TimingSource] = Registry("timing source", __package__, Path(__file__).parent)
