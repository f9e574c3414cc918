"""Speech: engines that speak an Utterance, and the Timeline keyed on what they spoke.

Entry points: synthesize_timeline(utterance, timing, recording=..., engine=...) and
write_wav(path, synthesis).
"""

from . import espeak as _espeak  # noqa: F401  (registers the eSpeak NG engine)
from .audio import read_audio
from .base import PhoneEvent, SpeechEngine, Synthesis, WordEvent, engine_names, get_engine, register_engine
from .recording import align_recording
from .timeline import TIMINGS, Speech, synthesize_timeline
from .wav import write_wav

__all__ = [
    "TIMINGS",
    "PhoneEvent",
    "Speech",
    "SpeechEngine",
    "Synthesis",
    "WordEvent",
    "align_recording",
    "engine_names",
    "get_engine",
    "read_audio",
    "register_engine",
    "synthesize_timeline",
    "write_wav",
]
