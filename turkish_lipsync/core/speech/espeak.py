"""eSpeak NG's Turkish voice through ctypes: audio plus phone and word events (the only ctypes module).

The library and its data come from the PyPI wheel espeakng-loader (its data path is passed explicitly);
a system libespeak-ng is the fallback. The library is initialised once per process: the system
library 1.51 hangs when initialised twice, and its state is global anyway, so every call holds a lock.

Each stretch of words without a pause or a change of style is spoken by one espeak_Synth call on plain
text, and the pauses of the utterance are inserted as exact silence between them. Plain text keeps
the event positions simple: a phone event carries the 1-based character position of its word in
that text, which identifies the word.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import threading
from bisect import bisect_right
from dataclasses import dataclass
from functools import cache

import numpy as np

from ..base.data import DATA_DIR, load_table
from ..base.errors import DataError, SpeechEngineError
from ..base.model import Style, Utterance
from .base import PhoneEvent, SpeechEngine, Synthesis, WordEvent, register_engine

INSTALL_HINT = (
    "install it with `pip install espeakng-loader` (or `apt install libespeak-ng1` on Debian/Ubuntu)"
)

DEFAULT_RATE = 175  # words per minute: eSpeak NG's own default (espeakRATE_NORMAL)
DEFAULT_PITCH = 50  # 0..100
DEFAULT_RANGE = 50  # 0..100, pitch range
DEFAULT_VOLUME = 100  # 0..200
RATE_LIMITS = (80, 450)
# Emphasis (JSML EMP): slower, higher, wider and a little louder, like a stressed word.
EMPHASIS_RATE = 0.85
EMPHASIS_PITCH = 1.2
EMPHASIS_RANGE = 1.5
EMPHASIS_VOLUME = 1.15
# A pause at least this long ends the stretch before it like a sentence, a shorter one like a comma.
SENTENCE_PAUSE = 0.3

# speak_lib.h
_AUDIO_OUTPUT_SYNCHRONOUS = 2
_INITIALIZE_PHONEME_EVENTS = 0x0001
_INITIALIZE_DONT_EXIT = 0x8000
_POS_CHARACTER = 1
_CHARS_UTF8 = 1
_EVENT_LIST_TERMINATED = 0
_EVENT_WORD = 1
_EVENT_PHONEME = 7
_PARAMETER_RATE = 1
_PARAMETER_VOLUME = 2
_PARAMETER_PITCH = 3
_PARAMETER_RANGE = 4


class _Event(ctypes.Structure):
    _fields_ = [
        ("type", ctypes.c_int),
        ("unique_identifier", ctypes.c_uint),
        ("text_position", ctypes.c_int),  # 1-based, in characters
        ("length", ctypes.c_int),
        ("audio_position", ctypes.c_int),  # milliseconds from the start of this synthesis call
        ("sample", ctypes.c_int),  # sample index from the start of this synthesis call
        ("user_data", ctypes.c_void_p),
        ("name", ctypes.c_char * 8),  # phone name for phoneme events (a union in C)
    ]


_SynthCallback = ctypes.CFUNCTYPE(
    ctypes.c_int, ctypes.POINTER(ctypes.c_short), ctypes.c_int, ctypes.POINTER(_Event)
)


@dataclass
class _Collector:
    """What one espeak_Synth call produced: audio chunks and (kind, position, sample, name) events."""

    chunks: list[np.ndarray]
    events: list[tuple[int, int, int, int, str]]
    sample_count: int = 0


class _Library:
    """The loaded and initialised library (one per process)."""

    def __init__(self, choice: LibraryChoice) -> None:
        self.lock = threading.Lock()
        self.choice = choice
        self.handle, data_path, self.origin = _load_library(choice)
        handle = self.handle
        handle.espeak_Info.argtypes = [ctypes.POINTER(ctypes.c_char_p)]
        handle.espeak_Info.restype = ctypes.c_char_p
        handle.espeak_Initialize.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_char_p, ctypes.c_int]
        handle.espeak_Initialize.restype = ctypes.c_int
        handle.espeak_SetSynthCallback.argtypes = [_SynthCallback]
        handle.espeak_SetVoiceByName.argtypes = [ctypes.c_char_p]
        handle.espeak_SetVoiceByName.restype = ctypes.c_int
        handle.espeak_SetParameter.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_int]
        handle.espeak_SetParameter.restype = ctypes.c_int
        handle.espeak_Synth.argtypes = [
            ctypes.c_void_p,
            ctypes.c_size_t,
            ctypes.c_uint,
            ctypes.c_int,
            ctypes.c_uint,
            ctypes.c_uint,
            ctypes.c_void_p,
            ctypes.c_void_p,
        ]
        handle.espeak_Synth.restype = ctypes.c_int
        path = data_path.encode() if data_path else None
        options = _INITIALIZE_PHONEME_EVENTS | _INITIALIZE_DONT_EXIT
        self.sample_rate = handle.espeak_Initialize(_AUDIO_OUTPUT_SYNCHRONOUS, 0, path, options)
        if self.sample_rate <= 0:
            raise SpeechEngineError(
                f"eSpeak NG ({self.origin}) failed to initialise "
                f"(data path {data_path or 'system default'}); "
                f"reinstall it: {INSTALL_HINT}"
            )
        if handle.espeak_SetVoiceByName(b"tr") != 0:
            raise SpeechEngineError(
                f"eSpeak NG ({self.origin}) has no Turkish voice 'tr'; "
                f"reinstall it with its data: {INSTALL_HINT}"
            )
        self.voice = ""  # the variant now set ("" the Turkish voice itself)
        self.collector = _Collector([], [])
        # Kept on the instance: ctypes must not free the callback while the library may call it.
        self.callback = _SynthCallback(self._on_synth)
        handle.espeak_SetSynthCallback(self.callback)
        self.version = (handle.espeak_Info(None) or b"").decode("utf-8", "replace")

    def _on_synth(self, wave, sample_count, events) -> int:
        collector = self.collector
        index = 0
        while events[index].type != _EVENT_LIST_TERMINATED:
            event = events[index]
            if event.type in (_EVENT_PHONEME, _EVENT_WORD):
                name = event.name.decode("utf-8", "replace") if event.type == _EVENT_PHONEME else ""
                sample = event.sample
                # The sample index is exact; trust it only while it agrees with the documented milliseconds.
                if abs(sample * 1000 / self.sample_rate - event.audio_position) > 1.5:
                    sample = round(event.audio_position * self.sample_rate / 1000)
                collector.events.append((event.type, event.text_position, sample, event.length, name))
            index += 1
        if sample_count > 0 and wave:
            collector.chunks.append(np.ctypeslib.as_array(wave, shape=(sample_count,)).copy())
            collector.sample_count += sample_count
        return 0

    def speak(self, text: str, style: Style) -> _Collector:
        """Audio and events of one stretch of plain text (caller holds the lock)."""
        if style.voice != self.voice:
            # A variant of the Turkish voice (a speaker of a conversation): the same language and phones,
            # another voice; setting it is not a second initialisation.
            name = f"tr+{style.voice}" if style.voice else "tr"
            if self.handle.espeak_SetVoiceByName(name.encode()) != 0:
                raise SpeechEngineError(
                    f"eSpeak NG ({self.origin}) has no voice variant {style.voice!r}; choose another voice "
                    f"(its data may lack the variants: {INSTALL_HINT})"
                )
            self.voice = style.voice
        rate, pitch, pitch_range, volume = _parameters(style)
        for parameter, value in (
            (_PARAMETER_RATE, rate),
            (_PARAMETER_PITCH, pitch),
            (_PARAMETER_RANGE, pitch_range),
            (_PARAMETER_VOLUME, volume),
        ):
            self.handle.espeak_SetParameter(parameter, value, 0)
        self.collector = _Collector([], [])
        data = text.encode("utf-8")
        buffer = ctypes.create_string_buffer(data)
        status = self.handle.espeak_Synth(
            buffer, len(data) + 1, 0, _POS_CHARACTER, 0, _CHARS_UTF8, None, None
        )
        if status != 0:
            raise SpeechEngineError(
                f"eSpeak NG could not speak {text[:40]!r} (error {status}); check the text or reinstall: "
                f"{INSTALL_HINT}"
            )
        return self.collector


@dataclass(frozen=True)
class LibraryChoice:
    """A libespeak-ng and its data folder the user chose (None: the bundled wheel, then the system's)."""

    library: str | None = None
    data: str | None = None


def _load_library(choice: LibraryChoice) -> tuple[ctypes.CDLL, str | None, str]:
    """The user's chosen library, else the espeakng-loader wheel's library and data, else the system's."""
    problems = []
    chosen_library, chosen_data = choice.library, choice.data
    if chosen_library:
        try:
            return ctypes.CDLL(chosen_library), chosen_data, f"chosen {chosen_library}"
        except OSError as error:
            raise SpeechEngineError(
                f"the eSpeak NG library chosen in the preferences ({chosen_library}) does not load: {error}. "
                "Pick the libespeak-ng file itself, or clear the path to use the bundled engine."
            ) from None
    try:
        import espeakng_loader

        path = espeakng_loader.get_library_path()
        return ctypes.CDLL(path), espeakng_loader.get_data_path(), f"espeakng-loader {path}"
    except ImportError:
        problems.append("the Python package espeakng-loader is not installed")
    except (OSError, RuntimeError) as error:
        problems.append(f"espeakng-loader's library did not load ({error})")
    for name in ("espeak-ng", "libespeak-ng.so.1"):
        found = ctypes.util.find_library(name) or name
        try:
            return ctypes.CDLL(found), None, f"system {found}"
        except OSError:
            continue
    problems.append("no system libespeak-ng was found")
    raise SpeechEngineError(
        f"eSpeak NG is not available: {'; '.join(problems)}. To fix it, {INSTALL_HINT}, "
        "or choose the library in the add-on's preferences, and try again."
    )


_CHOICE = LibraryChoice()
_LIBRARY: _Library | None = None
_LIBRARY_LOCK = threading.Lock()


def choose_library(library: str | None = None, data: str | None = None) -> None:
    """Use this libespeak-ng (and data folder) from the next start of the engine on (the preferences call it).

    A library that already started stays in use until Blender restarts: eSpeak NG cannot be started twice
    in one process. A start that failed is not remembered, so a corrected path works at the next try.
    """
    global _CHOICE
    with _LIBRARY_LOCK:
        _CHOICE = LibraryChoice(library or None, data or None)


def _library() -> _Library:
    """The process's one initialised library, started on first use with the chosen paths."""
    global _LIBRARY
    with _LIBRARY_LOCK:
        if _LIBRARY is None:
            _LIBRARY = _Library(_CHOICE)
        return _LIBRARY


def _parameters(style: Style) -> tuple[int, int, int, int]:
    """eSpeak NG's rate (wpm), pitch, pitch range and volume for a JSML style."""
    rate, pitch, pitch_range, volume = style.rate, style.pitch, 1.0, style.volume
    if style.emphasis:
        rate, pitch, pitch_range, volume = (
            rate * EMPHASIS_RATE,
            pitch * EMPHASIS_PITCH,
            EMPHASIS_RANGE,
            volume * EMPHASIS_VOLUME,
        )
    return (
        int(np.clip(round(DEFAULT_RATE * rate), *RATE_LIMITS)),
        int(np.clip(round(DEFAULT_PITCH * pitch), 0, 100)),
        int(np.clip(round(DEFAULT_RANGE * pitch_range), 0, 100)),
        int(np.clip(round(DEFAULT_VOLUME * volume), 0, 200)),
    )


@dataclass(frozen=True)
class _Stretch:
    """Consecutive words spoken in one call: no pause between them and one style."""

    first_word: int
    word_count: int
    pause_before: float
    pause_after: float
    ending: str  # punctuation of the last word ("" where none was written)
    style: Style


def _stretches(utterance: Utterance) -> list[_Stretch]:
    words = utterance.words
    bounds = [0]
    for index in range(1, len(words)):
        if words[index].pause_before > 0 or _spoken_style(words[index].style) != _spoken_style(
            words[index - 1].style
        ):
            bounds.append(index)
    bounds.append(len(words))
    stretches = []
    for first, stop in zip(bounds[:-1], bounds[1:], strict=True):
        after = words[stop].pause_before if stop < len(words) else utterance.final_pause
        stretches.append(
            _Stretch(
                first,
                stop - first,
                words[first].pause_before,
                after,
                words[stop - 1].ending,
                words[first].style,
            )
        )
    return stretches


def _spoken_style(style: Style) -> tuple[float, float, float, bool, str]:
    """The part of a style the voice hears (emotions only change the face)."""
    return (style.rate, style.pitch, style.volume, style.emphasis, style.voice)


@cache
def _symbol_table() -> tuple[dict[str, frozenset[str]], str, tuple[str, ...]]:
    table = load_table("espeak_tr")
    path = DATA_DIR / "espeak_tr.toml"
    letters = table.get("letters")
    prefix = table.get("pause_prefix")
    marks = table.get("marks")
    if not isinstance(letters, dict) or not letters:
        raise DataError(f"{path}: needs a [letters] table of letter = [phone symbols]")
    if not isinstance(prefix, str) or not prefix:
        raise DataError(f"{path}: pause_prefix must be a non-empty string")
    if not isinstance(marks, list) or not all(isinstance(mark, str) and len(mark) == 1 for mark in marks):
        raise DataError(f"{path}: marks must be a list of single characters")
    symbols = {}
    for letter, names in letters.items():
        if (
            len(letter) != 1
            or not isinstance(names, list)
            or not all(isinstance(n, str) and n for n in names)
        ):
            raise DataError(f"{path}: [letters] {letter!r} must be one letter = a list of phone symbols")
        symbols[letter] = frozenset(names)
    return symbols, prefix, tuple(marks)


@register_engine
class EspeakEngine(SpeechEngine):
    """eSpeak NG, Turkish voice, phone events on."""

    name = "espeak"

    @classmethod
    def letter_symbols(cls) -> dict[str, frozenset[str]]:
        return _symbol_table()[0]

    @classmethod
    def bare_symbol(cls, symbol: str) -> str | None:
        _, pause_prefix, marks = _symbol_table()
        if symbol.startswith(pause_prefix):
            return None
        return symbol.strip("".join(marks)) or None

    @property
    def sample_rate(self) -> int:
        return _library().sample_rate

    def is_available(self) -> bool:
        try:
            _library()
        except SpeechEngineError:
            return False
        return True

    def version(self) -> str:
        library = _library()
        return f"eSpeak NG {library.version} ({library.origin})"

    def synthesize(self, utterance: Utterance) -> Synthesis:
        library = _library()
        rate = library.sample_rate
        chunks: list[np.ndarray] = []
        phones: list[PhoneEvent] = []
        words: list[WordEvent] = []
        cursor = 0  # samples so far
        with library.lock:
            for stretch in _stretches(utterance):
                silence = round(stretch.pause_before * rate)
                if silence:
                    chunks.append(np.zeros(silence, np.int16))
                    cursor += silence
                stretch_words = utterance.words[stretch.first_word : stretch.first_word + stretch.word_count]
                text, positions = _stretch_text(
                    [word.text for word in stretch_words], stretch.pause_after, stretch.ending
                )
                spoken = library.speak(text, stretch.style)
                chunks.extend(spoken.chunks)
                self._collect_events(spoken, positions, stretch, cursor, rate, phones, words)
                cursor += spoken.sample_count
            silence = round(utterance.final_pause * rate)
            if silence:
                chunks.append(np.zeros(silence, np.int16))
        samples = np.concatenate(chunks) if chunks else np.zeros(0, np.int16)
        chunks.clear()
        return Synthesis(samples, rate, tuple(phones), tuple(words), self.name)

    def _collect_events(
        self,
        spoken: _Collector,
        positions: list[int],
        stretch: _Stretch,
        offset: int,
        rate: int,
        phones: list[PhoneEvent],
        words: list[WordEvent],
    ) -> None:
        """Phone events of one stretch, each ended by the next event's onset (pauses included)."""
        phone_events = [event for event in spoken.events if event[0] == _EVENT_PHONEME]
        levels = _hop_levels(spoken.chunks)
        for number, (_, position, sample, _, name) in enumerate(phone_events):
            following = phone_events[number + 1][2] if number + 1 < len(phone_events) else spoken.sample_count
            word = _word_at(positions, position)
            if word is None or self.bare_symbol(name) is None:
                continue
            start, end = (offset + sample) / rate, (offset + max(following, sample)) / rate
            closure = 0.0
            if number and self.bare_symbol(name) in VOICELESS_STOPS:
                closure = _closure(levels, phone_events[number - 1][2], sample, rate) / rate
            phones.append(PhoneEvent(start, end, name, stretch.first_word + word, closure=closure))
        seen = set()
        for kind, position, sample, _, _ in spoken.events:
            word = _word_at(positions, position) if kind == _EVENT_WORD else None
            if word is not None and word not in seen:
                seen.add(word)
                words.append(WordEvent((offset + sample) / rate, stretch.first_word + word))


# eSpeak NG reports a voiceless stop (or affricate) at its burst; the silence of its closure before that
# lies in the previous phone's span: 35-50 ms before p, t, k and ç, digital silence in its default voice,
# breath noise in its breathy variants.
VOICELESS_STOPS = frozenset(("p", "t", "k", "c", "tS"))
LEVEL_HOP = 32  # samples per level measured for closures (1.5 ms at 22,050 Hz)
CLOSURE_UNDER_DB = 40.0  # a closure is this far under the stretch's loud hops ...
CLOSURE_DROP_DB = 15.0  # ... or this far under the phone before's loudest (a breathy voice's holds noise)
LOUD_HOPS_PERCENTILE = 90
LONGEST_CLOSURE = 0.2  # seconds: a longer silence is a pause (never within one stretch of words)


def _hop_levels(chunks: list[np.ndarray]) -> np.ndarray:
    """Per LEVEL_HOP samples of a stretch's audio: its level in decibels relative to the stretch's loud
    hops."""
    samples = np.concatenate(chunks).astype(np.float32) if chunks else np.zeros(0, np.float32)
    count = samples.size // LEVEL_HOP
    if not count:
        return np.zeros(0)
    power = np.mean(samples[: count * LEVEL_HOP].reshape(count, LEVEL_HOP) ** 2, axis=1)
    decibels = 10 * np.log10(power + 1e-3)
    return decibels - np.percentile(decibels, LOUD_HOPS_PERCENTILE)


def _closure(levels: np.ndarray, previous: int, sample: int, rate: int) -> int:
    """Samples of silence just before `sample` (a stop's burst) after the previous phone's sound: 0 where
    the previous phone is silent up to the burst (the stop begins the sound) or the silence is a pause."""
    last = min(sample // LEVEL_HOP, levels.size)
    first = -(-previous // LEVEL_HOP)
    before = levels[first:last]
    if not before.size:
        return 0
    quiet = before < max(-CLOSURE_UNDER_DB, before.max() - CLOSURE_DROP_DB)
    if not quiet[-1] or quiet.all():
        return 0
    run = int(np.argmin(quiet[::-1]))  # quiet hops just before the burst
    closure = sample - (last - run) * LEVEL_HOP
    return closure if closure <= LONGEST_CLOSURE * rate else 0


def _stretch_text(words: list[str], pause_after: float, ending: str = "") -> tuple[str, list[int]]:
    """Plain text of the words and each word's 1-based character position in it.

    The written punctuation ends the text (a question rises); else the pause's length picks "." or ",".
    """
    positions = []
    position = 1
    for word in words:
        positions.append(position)
        position += len(word) + 1
    ending = ending or ("." if pause_after >= SENTENCE_PAUSE else ("," if pause_after > 0 else ""))
    return " ".join(words) + ending, positions


def _word_at(positions: list[int], position: int) -> int | None:
    """Index of the word starting at or before the 1-based character position (None before the first)."""
    index = bisect_right(positions, position) - 1
    return index if index >= 0 else None
