"""A user's recording of the text, aligned to the engine's rendition of the same text."""

from __future__ import annotations

from ...text.utterance import build_utterance, with_rate
from ..timeline import synthesize_timeline
from .base import TIMING_SOURCES, SpeechRequest, TimingSource


@TIMING_SOURCES.register
class RecordingSource(TimingSource):
    name = "recording"
    label = "Recording"
    description = "A recording of the text read aloud, aligned to it"
    working = "Aligning the recording to the text"
    priority = 10

    def claims(self, request: SpeechRequest) -> bool:
        return request.recording is not None and request.cues is None and bool(request.text.strip())

    def speak(self, request: SpeechRequest):
        utterance = with_rate(build_utterance(request.text), request.rate)
        speech = synthesize_timeline(
            utterance,
            request.timing,
            recording=request.recording,
            engine=request.engine,
            aligner=request.aligner,
        )
        return utterance, speech
