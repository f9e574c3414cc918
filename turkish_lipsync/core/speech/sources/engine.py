"""The speech engine's own voice (eSpeak NG): the default timing source."""

from __future__ import annotations

from ...base.errors import TextError
from ...text.utterance import build_utterance, with_rate
from ..timeline import synthesize_timeline
from .base import TIMING_SOURCES, SpeechRequest, TimingSource


@TIMING_SOURCES.register
class EngineSource(TimingSource):
    name = "engine"
    label = "Speech engine"
    description = "The text spoken by eSpeak NG's Turkish voice, every phone keyed where it is spoken"
    working = "Reading the text and speaking it"
    priority = 0

    def claims(self, request: SpeechRequest) -> bool:
        return True

    def speak(self, request: SpeechRequest):
        if not request.text.strip():
            raise TextError("The text is empty: write some Turkish text (plain or JSML) to speak.")
        utterance = with_rate(build_utterance(request.text), request.rate)
        return utterance, synthesize_timeline(utterance, request.timing, engine=request.engine)
