"""Papagayo's project file (.pgo): refine the timing by hand in Papagayo-NG, then read it back.

It counts in frames: the spoken text, its words with their frame spans, and each word's phonemes at the frame
they start (frames from 0), in Papagayo's Preston Blair phoneme set (AI, E, etc, FV, L, MBP, O, rest, U, WQ).
A project holds one voice or several (Papagayo-NG's characters): a conversation is written with one voice per
character, named after the speaker, and read back voice by voice (core/scene/speech.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...base.model import Timeline
from .common import (
    CueFileError,
    CueFormat,
    CueSource,
    MouthCue,
    frame_of,
    read_counted,
    register,
)
from .shapes import REST, shape_for_phoneme, shape_for_viseme, shape_table, uses_preston_blair

PAPAGAYO_HEADER = "lipsync version 1"


@dataclass(frozen=True)
class PapagayoWord:
    text: str
    start_frame: int
    end_frame: int  # the word's last frame (inclusive)
    phonemes: tuple[tuple[int, str], ...]  # (frame, Rhubarb shape), in order


@dataclass(frozen=True)
class PapagayoDocument:
    fps: float
    sound_path: str
    duration_frames: int
    text: str  # the voice's text, lines joined with newlines
    words: tuple[PapagayoWord, ...]
    voice_count: int
    voice_name: str = "Voice 1"

    def word_cues(self, word: PapagayoWord) -> tuple[MouthCue, ...]:
        """A word's phonemes as cues: each lasts until the next, the last until the word's end."""
        frames = [frame for frame, _ in word.phonemes] + [word.end_frame + 1]
        return tuple(
            MouthCue(frames[i] / self.fps, max(frames[i], frames[i + 1]) / self.fps, shape)
            for i, (_, shape) in enumerate(word.phonemes)
        )


def timeline_as_pgo(timeline: Timeline, fps: float, sound_path: str = "", text: str = "") -> str:
    """A Papagayo project of the timeline (one voice, one phrase per stretch of speech between pauses), so
    the timing can be refined in Papagayo-NG and read back as a timing source."""
    return voices_as_pgo([("Voice 1", timeline, text)], fps, sound_path, timeline.duration)


def voices_as_pgo(
    voices: list[tuple[str, Timeline, str]], fps: float, sound_path: str = "", duration: float = 0.0
) -> str:
    """A Papagayo project of several voices, each (name, its timeline, its text or "" for its phrases), on
    one timeline `duration` seconds long (the longest voice's where shorter)."""
    duration = max([duration] + [timeline.duration for _, timeline, _ in voices])
    duration_frames = max(1, math.ceil(duration * fps - 1e-6))
    # Papagayo reads a whole frame rate: 29.97 is written 30 and the frames counted at 29.97 (0.1% slow).
    lines = [PAPAGAYO_HEADER, sound_path, str(round(fps)), str(duration_frames), str(len(voices))]
    for name, timeline, text in voices:
        lines += _voice_lines(name, timeline, fps, text)
    return "\n".join(lines) + "\n"


def _voice_lines(name: str, timeline: Timeline, fps: float, text: str) -> list[str]:
    """One voice of a project: its name, text and phrases (stretches of speech between pauses)."""
    names = shape_table().preston_blair
    words_by_index = {word.index: word for word in timeline.words}
    phrases: list[list[int]] = []
    for word in timeline.words:
        if not phrases or word.start - words_by_index[phrases[-1][-1]].end > 1e-3:
            phrases.append([])
        phrases[-1].append(word.index)
    phrase_texts = [" ".join(words_by_index[index].text for index in phrase) for phrase in phrases]
    lines = [f"\t{' '.join(name.split()) or 'Voice'}"]
    lines += [
        "\t" + ("|".join(phrase_texts) if not text else "|".join(text.splitlines())),
        f"\t{len(phrases)}",
    ]
    for phrase, phrase_text in zip(phrases, phrase_texts, strict=True):
        spans = [_word_frames(words_by_index[index], fps) for index in phrase]
        lines += [f"\t\t{phrase_text}", f"\t\t{spans[0][0]}", f"\t\t{spans[-1][1]}", f"\t\t{len(phrase)}"]
        for index, (start, end) in zip(phrase, spans, strict=True):
            phonemes: list[tuple[int, str]] = []
            for phone in timeline.phones:
                if phone.word_index != index:
                    continue
                frame = max(start, min(end, frame_of(phone.start, fps)))
                name_of_mouth = names[shape_for_viseme(phone.viseme)]
                if phonemes and phonemes[-1][0] == frame:
                    phonemes[-1] = (frame, name_of_mouth)
                elif not phonemes or phonemes[-1][1] != name_of_mouth:
                    phonemes.append((frame, name_of_mouth))
            lines.append(f"\t\t\t{words_by_index[index].text} {start} {end} {len(phonemes)}")
            lines += [f"\t\t\t\t{frame} {mouth}" for frame, mouth in phonemes]
    return lines


def _word_frames(word, fps: float) -> tuple[int, int]:
    """First and last frame (inclusive) a word is spoken on."""
    start = frame_of(word.start, fps)
    return start, max(start, math.ceil(word.end * fps - 1e-6) - 1)


class _Lines:
    """The lines of a .pgo with their numbers, for errors that say where."""

    def __init__(self, path: Path, text: str) -> None:
        self.path = path
        self.lines = text.splitlines()
        self.number = 0

    def next(self, what: str) -> str:
        if self.number >= len(self.lines):
            raise CueFileError(f"{self.path}: ends early: expected {what} at line {self.number + 1}")
        self.number += 1
        return self.lines[self.number - 1].strip()

    def number_of(self, what: str, kind=int):
        value = self.next(what)
        try:
            return kind(value)
        except ValueError:
            raise CueFileError(f"{self.path}: line {self.number}: expected {what}, got {value!r}") from None

    def fields(self, what: str, count: int) -> list[str]:
        parts = self.next(what).split()
        if len(parts) < count:
            raise CueFileError(f"{self.path}: line {self.number}: expected {what}")
        return parts


def read_pgo(path: Path) -> PapagayoDocument:
    """The first voice of a Papagayo project: its text, words and phonemes (Preston Blair or Rhubarb)."""
    return read_pgo_voices(path)[0]


def read_pgo_voices(path: Path) -> tuple[PapagayoDocument, ...]:
    """Every voice of a Papagayo project (one document each, the project's sound and length shared)."""
    text = read_counted(path)
    lines = _Lines(path, text)
    if lines.next("the header").lower() != PAPAGAYO_HEADER:
        raise CueFileError(f"{path}: line 1 must be '{PAPAGAYO_HEADER}': is this a Papagayo project (.pgo)?")
    sound_path = lines.next("the sound file")
    fps = lines.number_of("the frame rate", float)
    if not 1 <= fps <= 1000:
        raise CueFileError(f"{path}: line 3: frame rate {fps} is out of range")
    duration_frames = lines.number_of("the length in frames")
    voice_count = lines.number_of("the number of voices")
    if voice_count < 1:
        raise CueFileError(f"{path}: line {lines.number}: the project has no voice")
    documents = []
    for number in range(voice_count):
        if number and lines.number >= len(lines.lines):
            break  # a project that announces more voices than it holds: the ones it holds
        name = lines.next("the voice's name") or f"Voice {number + 1}"
        voice_text = lines.next("the voice's text").replace("|", "\n").strip()
        words = _voice_words(path, lines, first=number == 0)
        documents.append(
            PapagayoDocument(fps, sound_path, duration_frames, voice_text, words, voice_count, name)
        )
    return tuple(documents)


def _voice_words(path: Path, lines: _Lines, first: bool) -> tuple[PapagayoWord, ...]:
    """The words of one voice: its phrases' words, each with its phonemes as Rhubarb shapes."""
    raw_words: list[tuple[str, int, int, list[tuple[int, str, int]]]] = []
    for _ in range(lines.number_of("the number of phrases")):
        lines.next("the phrase's text")
        lines.number_of("the phrase's first frame")
        lines.number_of("the phrase's last frame")
        for _ in range(lines.number_of("the number of words")):
            fields = lines.fields("'WORD START END PHONEMES'", 4)
            try:
                start, end, count = (int(value) for value in fields[-3:])
            except ValueError:
                raise CueFileError(
                    f"{path}: line {lines.number}: expected 'WORD START END PHONEMES'"
                ) from None
            phonemes = []
            for _ in range(count):
                frame, name = lines.fields("'FRAME PHONEME'", 2)[:2]
                if not frame.lstrip("-").isdigit():
                    raise CueFileError(f"{path}: line {lines.number}: frame {frame!r} is not a whole number")
                phonemes.append((int(frame), name, lines.number))
            raw_words.append((" ".join(fields[:-3]), start, max(start, end), phonemes))
    preston_blair = uses_preston_blair(name for *_, phonemes in raw_words for _, name, _ in phonemes)
    words = []
    previous_frame = None
    for word_text, start, end, phonemes in raw_words:
        shapes = []
        for frame, name, number in phonemes:
            if previous_frame is not None and frame < previous_frame:
                raise CueFileError(
                    f"{path}: line {number}: phoneme frame {frame} comes before frame {previous_frame} of "
                    "the one before it: phonemes must be in the order they are spoken"
                )
            previous_frame = frame
            shape = shape_for_phoneme(name, preston_blair)
            if shape is None:
                raise CueFileError(
                    f"{path}: line {number}: {name!r} is not a Preston Blair or Rhubarb mouth; choose the "
                    "Preston Blair phoneme set in Papagayo"
                )
            shapes.append((frame, shape))
        words.append(PapagayoWord(word_text, start, end, tuple(shapes)))
    if not words and first:
        raise CueFileError(
            f"{path}: the first voice has no words broken into phonemes; break them down first"
        )
    return tuple(words)


def spoken_words(document: PapagayoDocument) -> tuple[tuple[str, tuple[MouthCue, ...]], ...]:
    """Each word's text and cues, no two cues overlapping: a word whose last frame is the next word's first
    (spans are inclusive, so both claim it) ends where the next one begins."""
    words = [(word.text, list(document.word_cues(word))) for word in document.words]
    following = np.inf  # where the next word's first cue begins
    for _, cues in reversed(words):
        kept = [MouthCue(c.start, min(c.end, following), c.shape) for c in cues if c.start < following]
        if cues:
            following = min(following, cues[0].start)
        cues[:] = kept
    return tuple((text, tuple(cues)) for text, cues in words)


def rest_between(words: tuple[tuple[str, tuple[MouthCue, ...]], ...]) -> tuple[MouthCue, ...]:
    """Every phoneme of the words as cues, with rest (X) between the words."""
    cues: list[MouthCue] = []
    time = 0.0
    for _, word_cues in words:
        if word_cues and word_cues[0].start > time:
            cues.append(MouthCue(time, word_cues[0].start, REST))
        cues += word_cues
        time = max(time, word_cues[-1].end) if word_cues else time
    return tuple(cues)


@register
class PapagayoPgo(CueFormat):
    name = "papagayo-pgo"
    order = 5
    suffixes = (".pgo",)
    label = "Papagayo Project"
    description = "Words and mouths per frame for Papagayo-NG (.pgo)"

    def read(self, path: Path, fps: float) -> CueSource:
        """The first voice's words and phonemes at the project's own frame rate (fps is not used)."""
        document = read_pgo(path)
        warnings = ()
        if document.voice_count > 1:
            warnings = (f"{path} has {document.voice_count} voices; only the first one's timing is used.",)
        words = spoken_words(document)
        cues = rest_between(words)
        if not cues:
            raise CueFileError(f"{path}: the first voice's words hold no phonemes; break them down first")
        return CueSource(
            path,
            cues,
            max(document.duration_frames / document.fps, cues[-1].end),
            text=document.text,
            sound_file=document.sound_path,
            word_cues=words,
            warnings=warnings,
        )

    def write(self, timeline: Timeline, fps: float, *, sound_file: str = "", text: str = ""):
        warnings = ()
        if abs(fps - round(fps)) > 1e-6:
            warnings = (
                f"Papagayo counts whole frame rates: the project says {round(fps)} fps for the scene's "
                f"{fps:g}, so it plays {abs(round(fps) / fps - 1):.1%} off in Papagayo itself.",
            )
        return timeline_as_pgo(timeline, fps, sound_file, text), warnings
