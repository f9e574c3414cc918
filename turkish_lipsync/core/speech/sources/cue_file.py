"""A cue file made by another tool (Rhubarb, Papagayo, Moho) times our Turkish visemes (cue_timing.py)."""

from __future__ import annotations

from ..cue_timing import speech_from_cues
from .base import TIMING_SOURCES, SpeechRequest, TimingSource


@TIMING_SOURCES.register
class CueFileSource(TimingSource):
    name = "cues"
    label = "Cue file"
    description = "A Rhubarb, Papagayo or Moho file says when the mouth changes; the recording is its sound"
    working = "Timing the text by the cue file"
    priority = 20

    def claims(self, request: SpeechRequest) -> bool:
        return request.cues is not None

    def speak(self, request: SpeechRequest):
        return speech_from_cues(request.text, request.cues, request.recording, request.fps)
