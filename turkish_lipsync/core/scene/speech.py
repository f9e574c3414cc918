"""A scene's speech: every line spoken in its speaker's voice, or found in the recordings, on one timeline.

Where each line comes from is a scene source (sources/: each line in its own voice or recording, one
recording of the whole scene, one per speaker, a Papagayo project); `speak_scene` asks them which one a
request is for. Each line's timeline is on the scene's timeline; a speaker's timeline holds only their own
lines, so their mouth is at rest while the others speak. A scene's sound is its pieces mixed
(`SceneSpeech.mix`), one speaker's their pieces alone (`voice_of`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..base.errors import LipSyncError
from ..base.model import EmotionSpan, Pause, SpokenWord, Timeline, Utterance
from ..speech import Synthesis
from ..speech.aligner_settings import DEFAULT_ALIGNER, AlignerSettings
from ..speech.audio import resampled_pcm
from ..speech.decoders import RECORDING_KINDS, RECORDING_SUFFIXES
from ..speech.timeline import check_timing_follows
from ..speech.timing import build_timeline
from ..text.normalize import normalize
from ..text.script import Script, ScriptLine, speaker_key
from ..text.utterance import assemble_utterance
from .cast import Cast, spoken_by
from .tables import conversation_table

HEARD_DB = -35.0  # a line's audio this far under its loud end is silence
TAIL = 0.5  # seconds of the scene after its last phone (the last listener still reacting)


@dataclass(frozen=True, eq=False)
class SceneLine:
    """A line on the scene's timeline."""

    index: int
    speaker: str  # the speaker's key
    addressee: str  # a speaker's key or CAMERA
    timeline: Timeline  # its phones, words and emotions at scene times
    utterance: Utterance

    @property
    def first_phone(self) -> float:
        return min(phone.start for phone in self.timeline.phones)

    @property
    def last_phone(self) -> float:
        return max(phone.end for phone in self.timeline.phones)


@dataclass(frozen=True, eq=False)
class SoundPiece:
    """A sound of the scene placed at `start` seconds: a line's, a speaker's recording, or the scene's."""

    name: str  # what the sequencer's strip is called (the speaker, and the line's number)
    speaker: str | None  # the speaker's key; None for a recording of the whole scene
    start: float
    audio: Synthesis
    line: int | None = None  # the line it holds alone


@dataclass(frozen=True, eq=False)
class SceneSpeech:
    script: Script | None  # None for a text with no speakers (one head speaks it all)
    cast: Cast
    lines: tuple[SceneLine, ...]
    pieces: tuple[SoundPiece, ...]
    duration: float
    timing: str
    warnings: tuple[str, ...] = ()

    @property
    def sample_rate(self) -> int:
        return max((piece.audio.sample_rate for piece in self.pieces), default=0)

    def mix(self) -> Synthesis | None:
        """Everything the scene says, on its timeline (None without audio)."""
        return self._mixed(self.pieces, "scene")

    def voice_of(self, key: str) -> Synthesis | None:
        """One speaker's voice alone on the scene's timeline: their pieces, or their lines' spans of a
        recording of the whole scene (None without audio)."""
        own = [piece for piece in self.pieces if piece.speaker == key]
        shared = [piece for piece in self.pieces if piece.speaker is None]
        mixed = self._mixed(own + shared, key)
        if mixed is None or not shared:
            return mixed
        keep = np.zeros(mixed.samples.size, bool)
        rate = mixed.sample_rate
        for line in self.lines:
            if line.speaker == key:
                keep[max(0, int((line.first_phone - 0.05) * rate)) : int((line.last_phone + 0.05) * rate)] = (
                    True
                )
        return replace(mixed, samples=np.where(keep, mixed.samples, 0).astype(np.int16))

    def _mixed(self, pieces, engine: str) -> Synthesis | None:
        rate = self.sample_rate
        if not pieces or not rate:
            return None
        total = np.zeros(int(math.ceil(self.duration * rate)) + 1, np.float64)
        for piece in pieces:
            samples = piece.audio.samples
            if piece.audio.sample_rate != rate:
                samples = resampled_pcm(samples.astype(np.float32) / 32768.0, piece.audio.sample_rate, rate)
            first = int(round(piece.start * rate))
            stop = min(first + samples.size, total.size)
            total[first:stop] += samples[: stop - first]
        pcm = np.clip(np.round(total), -32768, 32767).astype(np.int16)
        return Synthesis(pcm, rate, (), (), engine)

    def speaker_timeline(self, key: str) -> Timeline:
        """A speaker's own lines on the scene's timeline (the whole scene long)."""
        return Timeline.joined([line.timeline for line in self.lines if line.speaker == key], self.duration)

    def scene_timeline(self) -> Timeline:
        """Every line on the scene's timeline."""
        return Timeline.joined([line.timeline for line in self.lines], self.duration)


@dataclass(frozen=True)
class SceneSources:
    """Where the scene's speech comes from: recordings or a cue file instead of the speech engine."""

    scene_recording: Path | None = None
    speaker_recordings: dict[str, Path] | None = None  # by speaker's key (the cast's roles hold them)
    line_recordings: tuple[Path, ...] = ()
    cues: Path | None = None


def speak_scene(
    script: Script,
    cast: Cast,
    *,
    timing: str = "phone",
    rate: float = 1.0,
    engine: str = "espeak",
    sources: SceneSources | None = None,
    seed: int = 0,
    aligner: AlignerSettings = DEFAULT_ALIGNER,
) -> SceneSpeech:
    """Every line of the script spoken (or found in the recordings) on the scene's timeline."""
    from .sources import SCENE_SOURCES, SceneRequest, scene_source_for

    sources = sources or SceneSources()
    speaker_recordings = {role.key: role.recording for role in cast.roles if role.recording is not None}
    speaker_recordings |= {speaker_key(k): Path(v) for k, v in (sources.speaker_recordings or {}).items()}
    request = SceneRequest(
        script,
        cast,
        tuple(line_utterance(script, line, cast, rate) for line in script.lines),
        timing,
        rate,
        engine,
        seed,
        sources.scene_recording,
        speaker_recordings,
        sources.line_recordings,
        sources.cues,
        aligner,
    )
    given = [
        source.given_as
        for source in SCENE_SOURCES.entries().values()
        if source.priority > 0 and source.claims(request)
    ] + (["recordings per line"] if sources.line_recordings else [])
    if len(given) > 1:
        raise LipSyncError(f"The scene is given {' and '.join(sorted(given))}; give only one of them.")
    check_timing_follows(timing, bool(given))
    return scene_source_for(request).speak(request)


def line_recordings_in(folder: Path) -> tuple[Path, ...]:
    """A folder's recordings, one per line, in the order of their names (01.wav, 02.wav, ...)."""
    if not folder.is_dir():
        raise LipSyncError(f"The line recordings folder {folder} does not exist; choose the folder again.")
    found = tuple(sorted(p for p in folder.iterdir() if p.suffix.lower() in RECORDING_SUFFIXES))
    if not found:
        raise LipSyncError(f"{folder} holds no recordings ({RECORDING_KINDS}): give one per line.")
    return found


def line_utterance(script: Script, line: ScriptLine, cast: Cast, rate: float = 1.0) -> Utterance:
    """The line's words as spoken, in its speaker's voice (offsets into the whole script)."""
    return spoken_by(assemble_utterance(script.source, normalize(line.items)), cast.role(line.speaker), rate)


# ---------------------------------------------------------------- recordings and cue files


def scene_utterance(
    script: Script, cast: Cast, lines: list[int] | None = None, rate: float = 1.0
) -> Utterance:
    """Several lines as one utterance (all of them by default), each word in its speaker's voice, with the
    usual gap (or the markup's BREAK) between lines: what a recording of them is aligned to. Its letters are
    the lines' letters in order (split_timeline parts its timeline again)."""
    turns = conversation_table().turns
    items: list[SpokenWord | Pause] = []
    chosen = range(len(script.lines)) if lines is None else lines
    for number, index in enumerate(chosen):
        line = script.lines[index]
        role = cast.role(line.speaker)
        spoken = list(normalize(line.items))
        while spoken and isinstance(spoken[0], Pause):
            spoken.pop(0)
        trailing: list[Pause] = []
        while spoken and isinstance(spoken[-1], Pause):  # its punctuation stays, its silence is the gap's
            trailing.insert(0, replace(spoken.pop(), seconds=0.0))
        if number:
            gap = (
                0.05
                if line.overlaps
                else (line.pause_before if line.pause_before is not None else turns.gap_median)
            )
            items.append(Pause(gap, line.offset, "break"))
        items += [
            replace(item, style=role.voice.style(item.style, rate)) if isinstance(item, SpokenWord) else item
            for item in spoken
        ] + trailing
    return assemble_utterance(script.source, items)


def split_timeline(timeline: Timeline, utterances: list[Utterance], duration: float) -> list[Timeline]:
    """The timeline of several lines spoken as one utterance, as one timeline per line (same times); a
    hesitation said aloud goes to the line it is said within (one between two lines to neither: whose it
    is, the take does not say)."""
    phones = sorted(timeline.phones, key=lambda phone: phone.letter_index)
    starts = np.array([phone.start for phone in phones])
    ends = np.array([phone.end for phone in phones])
    result, first = [], 0
    for utterance in utterances:
        count = len(utterance.letters)
        line_starts, line_ends = starts[first : first + count], ends[first : first + count]
        begun, ended = line_starts.min(initial=np.inf), line_ends.max(initial=-np.inf)
        within = tuple(h for h in timeline.hesitations if begun <= h.start and h.end <= ended)
        result.append(
            build_timeline(utterance, line_starts, line_ends, duration, timeline.timing, (), within)
        )
        first += count
    return result


# ---------------------------------------------------------------- timelines


def with_faint_emotions(timeline: Timeline, heard: list[Timeline], share: float) -> Timeline:
    """A listener's timeline with the emotions of the lines it hears, at `share` of their weight."""
    faint = [EmotionSpan(e.start, e.end, e.emotion, e.weight * share) for t in heard for e in t.emotions]
    if not faint or share <= 0:
        return timeline
    return replace(timeline, emotions=tuple(sorted((*timeline.emotions, *faint), key=lambda e: e.start)))
