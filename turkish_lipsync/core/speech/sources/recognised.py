"""A recording without its text: the Turkish letters are recognised from the audio alone (recognition/)."""

from __future__ import annotations

from ..recognition import speech_from_audio
from .base import TIMING_SOURCES, SpeechRequest, TimingSource


@TIMING_SOURCES.register
class RecognisedSource(TimingSource):
    name = "recognised"
    label = "Recognised from the recording"
    description = "A recording with no text: the letters it says are recognised and keyed where heard"
    working = "Hearing what the recording says (a few seconds for each minute of it)"
    priority = 10

    def claims(self, request: SpeechRequest) -> bool:
        return request.recording is not None and request.cues is None and not request.text.strip()

    def speak(self, request: SpeechRequest):
        return speech_from_audio(request.recording, request.recogniser)
