"""Timing sources: what gives a text its speech (the utterance, a timeline and the audio it belongs to).

The speech engine's voice, a user's recording aligned to the text, a cue file made by another tool: each is
one module here with a `TimingSource` subclass registered in `TIMING_SOURCES`. `speak(request)` asks them in
order of priority which one the request is for.
"""

from __future__ import annotations

from .base import TIMING_SOURCES, SpeechRequest, TimingSource


def timing_source_for(request: SpeechRequest) -> TimingSource:
    """The source that speaks this request: the first, by priority, that claims it."""
    sources = sorted(TIMING_SOURCES.entries().values(), key=lambda source: -source.priority)
    for source in sources:
        if source.claims(request):
            return source
    raise AssertionError("the speech engine claims every request no other source takes")


def speak(request: SpeechRequest):
    """(utterance, Speech) of the request, from the source it is for."""
    return timing_source_for(request).speak(request)


__all__ = ["TIMING_SOURCES", "SpeechRequest", "TimingSource", "speak", "timing_source_for"]
