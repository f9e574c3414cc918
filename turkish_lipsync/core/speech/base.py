"""The speech-engine interface: one small base class, engines registered by name (as phonemizer does).

An engine turns an Utterance into PCM audio plus the events it emitted while speaking: one event per
phone (start, end, symbol, word) and one per word. Matching phones to letters is align.py's job, so an
engine only has to say which phone symbols may realise each letter (`letter_symbols`).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, replace
from threading import Lock
from typing import ClassVar

import numpy as np

from ..base.errors import SpeechEngineError
from ..base.model import Utterance


@dataclass(frozen=True)
class PhoneEvent:
    """A phone the engine spoke: its span in the audio (seconds) and the letters it realises."""

    start: float
    end: float
    symbol: str  # the engine's own phone name, marks included (e.g. "'a", "tS")
    word_index: int  # index into Utterance.words
    letters: tuple[int, ...] = ()  # indices into Utterance.letters, filled by align.py
    # Seconds of silence just before start that belong to this phone: a voiceless stop's closure, which
    # the engine reports at the burst (with_closures moves the start back over it).
    closure: float = 0.0

    def moved(self, seconds: float, words: int) -> PhoneEvent:
        """The event `seconds` later and `words` words on (a piece of a text spoken after the others)."""
        return replace(
            self, start=self.start + seconds, end=self.end + seconds, word_index=self.word_index + words
        )


@dataclass(frozen=True)
class WordEvent:
    """The engine's word-start event (the only event the thesis's speech interface delivered)."""

    start: float
    word_index: int

    def moved(self, seconds: float, words: int) -> WordEvent:
        """The event `seconds` later and `words` words on."""
        return replace(self, start=self.start + seconds, word_index=self.word_index + words)


@dataclass(frozen=True, eq=False)
class Synthesis:
    """Speech audio (mono 16-bit PCM) with the phone and word events that describe it."""

    samples: np.ndarray  # int16, mono
    sample_rate: int
    phone_events: tuple[PhoneEvent, ...]
    word_events: tuple[WordEvent, ...]
    engine: str  # the engine's registered name, or "recording" for a user's aligned recording

    @property
    def duration(self) -> float:
        return self.samples.size / self.sample_rate


class SpeechEngine(ABC):
    """A speech synthesiser: subclasses set `name`, register with @register_engine, implement the methods."""

    name: ClassVar[str]

    @classmethod
    @abstractmethod
    def letter_symbols(cls) -> dict[str, frozenset[str]]:
        """For each lowercase Turkish letter, the phone symbols (without stress marks) that may realise it."""

    @classmethod
    @abstractmethod
    def bare_symbol(cls, symbol: str) -> str | None:
        """The phone symbol without stress or length marks; None for a pause."""

    @abstractmethod
    def is_available(self) -> bool:
        """True when the engine can speak now (starting it if needed); never raises."""

    @abstractmethod
    def version(self) -> str:
        """The engine's name, version and origin, for reports; raises SpeechEngineError when unavailable."""

    @abstractmethod
    def synthesize(self, utterance: Utterance) -> Synthesis:
        """Speak exactly the utterance's words (Word.text), honouring their pauses and styles."""


_ENGINE_CLASSES: dict[str, type[SpeechEngine]] = {}
_ENGINE_INSTANCES: dict[str, SpeechEngine] = {}
_REGISTRY_LOCK = Lock()


def register_engine(engine_class: type[SpeechEngine]) -> type[SpeechEngine]:
    """Class decorator: make the engine available to get_engine() under its name."""
    _ENGINE_CLASSES[engine_class.name] = engine_class
    return engine_class


def engine_names() -> tuple[str, ...]:
    return tuple(sorted(_ENGINE_CLASSES))


def get_engine(name: str) -> SpeechEngine:
    """The process's one instance of the named engine (engines such as eSpeak NG initialise only once)."""
    with _REGISTRY_LOCK:
        engine = _ENGINE_INSTANCES.get(name)
        if engine is None:
            engine_class = _ENGINE_CLASSES.get(name)
            if engine_class is None:
                raise SpeechEngineError(
                    f"unknown speech engine {name!r}; choose one of: {', '.join(engine_names())}"
                )
            engine = _ENGINE_INSTANCES[name] = engine_class()
        return engine
