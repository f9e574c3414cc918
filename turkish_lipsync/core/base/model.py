"""The data model shared by every stage: markup, words, letters, timeline, weight tracks.

Stages hand each other these frozen values; nothing here knows about Blender.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

EMOTIONS: tuple[str, ...] = ("happy", "sad", "angry", "afraid", "surprised", "disgusted")

# Every shape key, action and strip the add-on owns starts with this; a rebuild replaces only those.
OWNED_PREFIX = "TR_"
VISEME_KEY_PREFIX = OWNED_PREFIX + "viseme_"
EMOTION_KEY_PREFIX = OWNED_PREFIX + "emotion_"
# The mouth part of an emotion, stored negated: keyed while a viseme needs the lips, it lets the
# lips close under any emotion while the upper face keeps the emotion at full strength.
EMOTION_MOUTH_RELEASE_SUFFIX = "_mouth_release"
BLINK_KEYS: tuple[str, str] = ("TR_blink_left", "TR_blink_right")
BROW_RAISE_KEY = "TR_brow_raise"
# Keys that turn each eye (and let its lids follow): weight 1 turns the eye LOOK_KEY_DEGREES that way, as
# the character sees it ("left" is the character's left); the build scales each head's own keys to that.
LOOK_KEY_DEGREES = 20.0
LOOK_DIRECTIONS: tuple[str, ...] = ("left", "right", "up", "down")
EYE_SIDES: tuple[str, str] = ("left", "right")


def look_key_name(eye: str, direction: str) -> str:
    return f"{OWNED_PREFIX}eye_{eye}_look_{direction}"


LOOK_KEYS: tuple[str, ...] = tuple(look_key_name(eye, d) for eye in EYE_SIDES for d in LOOK_DIRECTIONS)


def viseme_key_name(viseme: str) -> str:
    return VISEME_KEY_PREFIX + viseme


def emotion_key_name(emotion: str) -> str:
    return EMOTION_KEY_PREFIX + emotion


def emotion_release_key_name(emotion: str) -> str:
    return EMOTION_KEY_PREFIX + emotion + EMOTION_MOUTH_RELEASE_SUFFIX


# ---------------------------------------------------------------- markup (jsml.py)


@dataclass(frozen=True)
class Style:
    """How a stretch of text is spoken, from the JSML elements around it."""

    emotion: str | None = None  # one of EMOTIONS
    emotion_weight: float = 1.0  # the thesis's expression weight, 0..1
    rate: float = 1.0  # multiplier of the engine's default speaking rate
    pitch: float = 1.0  # multiplier of the engine's default pitch
    volume: float = 1.0  # multiplier of the default volume
    emphasis: bool = False
    voice: str = ""  # the speech engine's voice variant of the speaker (a conversation's cast); "" its own


@dataclass(frozen=True)
class TextRun:
    """Text between markup, with the source index (0-based, in characters) of each character."""

    text: str
    offsets: tuple[int, ...]
    style: Style


@dataclass(frozen=True)
class Pause:
    """Silence: a BREAK, a sentence or paragraph end, or punctuation."""

    seconds: float
    offset: int  # source index of what caused it
    kind: str  # "break", "sentence", "paragraph", "comma", "clause", "line" (a line break: no silence)


# ---------------------------------------------------------------- normalised text (normalize.py)


@dataclass(frozen=True)
class SpokenWord:
    """A word as it is spoken: lowercase Turkish letters only (numbers and abbreviations expanded)."""

    text: str
    offsets: tuple[int, ...]  # per letter: the source index it came from
    style: Style


# ---------------------------------------------------------------- utterance (utterance.py)


@dataclass(frozen=True)
class Letter:
    char: str
    offset: int  # source index
    word_index: int
    syllable_index: int  # index into Utterance.syllables
    viseme: str  # thesis model name (a, bpa, ..., neutral)
    is_vowel: bool


@dataclass(frozen=True)
class Syllable:
    text: str
    word_index: int
    first_letter: int  # index into Utterance.letters
    letter_count: int


@dataclass(frozen=True)
class Word:
    text: str
    first_letter: int
    letter_count: int
    first_syllable: int
    syllable_count: int
    style: Style
    pause_before: float = 0.0  # seconds of silence before this word
    # The word begins a line of the written text (one line break before it, no punctuation): no silence is
    # asked for, but a reader may pause there (a script's lines, a list one item a line).
    line_start: bool = False
    # Punctuation closing the word's phrase where a pause follows: "." "?" "!" "," or "" (none, a BREAK).
    # The voice needs it: a question rises.
    ending: str = ""


@dataclass(frozen=True)
class Utterance:
    source: str
    words: tuple[Word, ...]
    syllables: tuple[Syllable, ...]
    letters: tuple[Letter, ...]
    final_pause: float = 0.0  # seconds of silence after the last word
    unspoken: tuple[str, ...] = ()  # stretches of the source spoken as nothing (other scripts, emoji)


# ---------------------------------------------------------------- timeline (timing.py, speech/)


@dataclass(frozen=True)
class Phone:
    """One letter's visible span: when the phone that realises it is spoken."""

    start: float
    end: float
    letter_index: int
    letter: str
    syllable: str
    word_index: int
    viseme: str


@dataclass(frozen=True)
class WordSpan:
    start: float
    end: float
    index: int
    text: str


@dataclass(frozen=True)
class EmotionSpan:
    start: float
    end: float
    emotion: str
    weight: float


@dataclass(frozen=True)
class Hesitation:
    """A hesitation said aloud in a pause of a recording ("ııı", "eee", "mmm"): no letter of the text, but
    a sound the mouth shapes, as the viseme of its letter said alone."""

    start: float
    end: float
    sound: str  # the letter it is heard as
    viseme: str


@dataclass(frozen=True)
class Timeline:
    phones: tuple[Phone, ...]
    words: tuple[WordSpan, ...]
    emotions: tuple[EmotionSpan, ...]
    emphases: tuple[tuple[float, float], ...]  # (start, end) of emphasised words
    duration: float  # seconds, including the final pause
    timing: str  # "phone", "word", "table" or "recording"
    # Onsets of the phones the engine reported, where an engine ran (for quality checks).
    engine_onsets: tuple[float, ...] = ()
    hesitations: tuple[Hesitation, ...] = ()  # said aloud in a recording's pauses, in order

    def retimed(self, moved: Callable[[float], float], duration: float | None = None) -> Timeline:
        """The timeline with every time it holds (phones, words, emotions, emphases, the engine's onsets,
        hesitations) mapped by `moved`, and the duration given (its own if None)."""
        return replace(
            self,
            phones=tuple(replace(p, start=moved(p.start), end=moved(p.end)) for p in self.phones),
            words=tuple(replace(w, start=moved(w.start), end=moved(w.end)) for w in self.words),
            emotions=tuple(replace(e, start=moved(e.start), end=moved(e.end)) for e in self.emotions),
            emphases=tuple((moved(a), moved(b)) for a, b in self.emphases),
            duration=self.duration if duration is None else duration,
            engine_onsets=tuple(moved(onset) for onset in self.engine_onsets),
            hesitations=tuple(replace(h, start=moved(h.start), end=moved(h.end)) for h in self.hesitations),
        )

    def shifted(self, offset: float, duration: float) -> Timeline:
        """The timeline moved `offset` seconds later, on a timeline `duration` long (a line in a scene)."""
        return self.retimed(lambda time: time + offset, duration)

    def remapped(self, old: tuple[float, ...], new: tuple[float, ...]) -> Timeline:
        """The times within old[0]..old[-1] moved linearly onto `new` (knots in order), the rest kept."""

        def moved(time: float) -> float:
            return float(np.interp(time, old, new)) if old[0] <= time <= old[-1] else time

        return self.retimed(moved)

    @staticmethod
    def joined(timelines: Sequence[Timeline], duration: float, timing: str = "") -> Timeline:
        """Timelines already on one time axis as one: their words and letters numbered on from one to the
        next, the engine's onsets in order; `timing` (the first's if empty) names the result's."""
        phones, words, emotions, emphases, onsets, hesitations = [], [], [], [], [], []
        word_base = letter_base = 0
        for timeline in timelines:
            phones += [
                replace(p, word_index=p.word_index + word_base, letter_index=p.letter_index + letter_base)
                for p in timeline.phones
            ]
            words += [replace(w, index=w.index + word_base) for w in timeline.words]
            emotions += timeline.emotions
            emphases += timeline.emphases
            onsets += timeline.engine_onsets
            hesitations += timeline.hesitations
            word_base += len(timeline.words)
            letter_base += len(timeline.phones)
        return Timeline(
            tuple(phones),
            tuple(words),
            tuple(emotions),
            tuple(emphases),
            duration,
            timing or (timelines[0].timing if timelines else "phone"),
            tuple(sorted(onsets)),
            tuple(sorted(hesitations, key=lambda hesitation: hesitation.start)),
        )


# ---------------------------------------------------------------- weight tracks (tracks.py, motion.py)


@dataclass(frozen=True, eq=False)
class Track:
    """One shape key's weight over time: keys at (possibly fractional) frames, 0 = utterance start."""

    name: str  # shape key name, e.g. "TR_viseme_a"
    frames: np.ndarray  # float64, increasing
    values: np.ndarray  # float64, same length


@dataclass(frozen=True, eq=False)
class HeadAndEyes:
    """Rotations at every frame of the weight tracks (frame i is i / fps after the utterance start), degrees.

    Angles are those of the character's own frame, whatever way the head faces in a scene: yaw + turns
    toward the character's left, pitch + looks up, roll + tilts the top of the head toward the character's
    right shoulder (right-handed about the facing direction). The head's angles are relative to its rest
    pose, applied yaw, then pitch, then roll (R = R_yaw R_pitch R_roll); each eye's are relative to the head,
    yaw then pitch. A left eye at yaw +5 looks 5 degrees toward the character's left.
    """

    head: np.ndarray  # (frame_count, 3): yaw, pitch, roll of the head relative to its rest pose
    left_eye: np.ndarray  # (frame_count, 2 or 3): yaw, pitch (, roll) of the eye relative to the head
    right_eye: np.ndarray


@dataclass(frozen=True, eq=False)
class WeightTracks:
    fps: float
    frame_count: int  # frames covered by the utterance
    interpolation: str  # Blender keyframe interpolation: "LINEAR", "BEZIER" or "CONSTANT"
    tracks: tuple[Track, ...]
    mode: str = "natural"  # "natural" (co-articulation) or "thesis" (eq. 5.3/5.4)
    extra: dict = field(default_factory=dict)
    # Head and eye rotations of the living layers (core/motion/living), None when they are off.
    head_and_eyes: HeadAndEyes | None = None

    def track(self, name: str) -> Track | None:
        return next((t for t in self.tracks if t.name == name), None)

    def sample(self, frames: np.ndarray) -> tuple[tuple[str, ...], np.ndarray]:
        """Weights at the given frames (linear between keys), as (names, array[frame, track])."""
        frames = np.asarray(frames, dtype=np.float64)
        out = np.empty((frames.size, len(self.tracks)))
        for column, track in enumerate(self.tracks):
            if self.interpolation == "CONSTANT":
                index = np.clip(np.searchsorted(track.frames, frames, side="right") - 1, 0, None)
                out[:, column] = track.values[index]
            else:
                out[:, column] = np.interp(frames, track.frames, track.values)
        return tuple(t.name for t in self.tracks), out
