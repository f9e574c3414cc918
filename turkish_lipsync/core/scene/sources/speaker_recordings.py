"""One recording per speaker: each a track of the scene (it starts where the scene starts, silent while the
others speak), cut into one stretch per turn of theirs at its longest silences (the others' lines leave long
ones), each turn aligned to its own stretch."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...base.errors import LipSyncError
from ...base.model import Timeline, Utterance
from ...speech import Synthesis, synthesize_timeline
from ...speech.audio import levels_under_loud, read_audio, to_pcm16
from ...speech.recording import RecordedAudio
from ...speech.timing import letter_durations
from ...text.script import Script
from ..speech import HEARD_DB, SceneLine, SceneSpeech, SoundPiece, scene_utterance, split_timeline
from .base import SCENE_SOURCES, SceneRequest, SceneSource

MIN_TURN_SILENCE = 0.3  # seconds of silence in a speaker's track that may part two of their turns
SILENCE_WEIGHT = 0.2  # how much a longer silence is preferred as the end of a speaker's turn
STRETCH_MARGIN = 0.3  # seconds of silence kept around a turn's stretch of a speaker's track


@SCENE_SOURCES.register
class SpeakerRecordings(SceneSource):
    name = "speaker recordings"
    given_as = "recordings per speaker"
    priority = 10

    def claims(self, request: SceneRequest) -> bool:
        return bool(request.speaker_recordings)

    def speak(self, request: SceneRequest) -> SceneSpeech:
        script, cast, recordings = request.script, request.cast, request.speaker_recordings
        missing = [role.name for role in cast.roles if role.key not in recordings]
        if missing:
            raise LipSyncError(
                f"Recordings per speaker were given, but none for {', '.join(missing)}: give every speaker a "
                "recording (their track of the scene), or one recording of the whole scene."
            )
        timelines: dict[int, Timeline] = {}
        pieces, warnings = [], []
        duration = 0.0
        for role in cast.roles:
            samples, sample_rate = read_audio(recordings[role.key])
            track = Synthesis(to_pcm16(samples), sample_rate, (), (), "recording")
            duration = max(duration, track.duration)
            for turn, start, speech in _turns_aligned(request, role.key, track, recordings[role.key]):
                warnings += [f"{role.name}'s recording near {start:.1f} s: {w}" for w in speech.warnings]
                parts = split_timeline(speech.timeline, [request.utterances[i] for i in turn], duration)
                for index, part in zip(turn, parts, strict=True):
                    timelines[index] = part.shifted(start, duration)
            pieces.append(SoundPiece(role.name, role.key, 0.0, track))
        addressees = request.addressees
        lines = tuple(
            SceneLine(
                index,
                line.speaker,
                addressees[index],
                replace(timelines[index], duration=duration),
                request.utterances[index],
            )
            for index, line in enumerate(script.lines)
        )
        label = lines[0].timeline.timing if lines else request.timing
        return SceneSpeech(script, cast, lines, tuple(pieces), duration, label, tuple(warnings))


def _turns_aligned(request: SceneRequest, key: str, track: Synthesis, path):
    """(turn's lines, the stretch's start, its speech) for each turn of the speaker, each aligned to its
    stretch of the track (the whole track as one take where it has no clear silence between turns)."""
    turns = _turns_of(request.script, key)
    expected = [_expected_length([request.utterances[i] for i in turn]) for turn in turns]
    stretches = _stretches(track.samples, track.sample_rate, expected)
    if stretches is None:
        turns, stretches = [[i for turn in turns for i in turn]], [(0.0, track.duration)]
    rate = track.sample_rate
    for turn, (start, end) in zip(turns, stretches, strict=True):
        first, last = int(start * rate), int(np.ceil(end * rate))
        stretch = RecordedAudio(
            track.samples[first:last].astype(np.float32) / 32768, rate, f"{path} from {start:.2f} s"
        )
        utterance = scene_utterance(request.script, request.cast, turn, request.rate)
        yield (
            turn,
            start,
            synthesize_timeline(
                utterance, request.timing, recording=stretch, engine=request.engine, aligner=request.aligner
            ),
        )


def _turns_of(script: Script, key: str) -> list[list[int]]:
    """A speaker's turns: runs of their lines that no other speaker's line comes between."""
    turns: list[list[int]] = []
    for index, line in enumerate(script.lines):
        if line.speaker != key:
            continue
        if turns and turns[-1][-1] == index - 1:
            turns[-1].append(index)
        else:
            turns.append([index])
    return turns


def _stretches(pcm: np.ndarray, rate: int, expected: list[float]) -> list[tuple[float, float]] | None:
    """The track cut into one stretch of speech per turn (expected: each turn's length as the text's mean
    durations say), at silences of MIN_TURN_SILENCE and more, chosen so that the stretches' lengths keep
    the turns' proportions (a turn's own pauses are shorter than the others' turns, but not always); each
    stretch keeps a little silence around it. None where the track has too few silences."""
    hop = max(1, rate // 100)
    frames = pcm.size // hop
    loud = np.flatnonzero(levels_under_loud(pcm, hop) > HEARD_DB)
    count = len(expected)
    if not loud.size:
        return None
    candidates = np.flatnonzero(np.diff(loud) > int(MIN_TURN_SILENCE * 100))
    if candidates.size < count - 1:
        return None
    firsts = np.concatenate([[loud[0]], loud[candidates + 1]])  # where a stretch may begin
    lasts = np.concatenate([loud[candidates] + 1, [loud[-1] + 1]])  # ... and end
    bounds = _turn_bounds(loud, candidates, lasts, expected)
    margin = int(STRETCH_MARGIN * 100)
    stretches = []
    for number, (begin, end) in enumerate(bounds):
        first, last = firsts[begin], lasts[end]
        before = lasts[bounds[number - 1][1]] if number else 0
        after = firsts[bounds[number + 1][0]] if number + 1 < count else frames
        stretches.append(
            (
                max(first - margin, (before + first) // 2) * hop / rate,
                min(last + margin, (last + after) // 2) * hop / rate,
            )
        )
    return stretches


def _turn_bounds(
    loud: np.ndarray, candidates: np.ndarray, lasts: np.ndarray, expected: list[float]
) -> list[tuple[int, int]]:
    """Per turn, the first and last of the possible stretches it covers (a dynamic programme: each turn's
    speech in proportion to its expected length, a longer silence after it preferred)."""
    count = len(expected)
    # Speech (loud frames) up to each possible end, and the silence after it (a longer one parts turns).
    spoken = np.concatenate([np.searchsorted(loud, lasts[:-1]), [loud.size]])
    silence = np.log(np.diff(loud)[candidates] / (MIN_TURN_SILENCE * 100))
    scale = loud.size / max(sum(expected), 1e-6)

    def cost(turn: int, begin: int, end: int) -> float:
        speech = spoken[end] - (spoken[begin - 1] if begin else 0)
        fit = float(np.log(max(speech, 1) / max(expected[turn] * scale, 1e-6)) ** 2)
        return fit - (SILENCE_WEIGHT * silence[end] if end < len(silence) else 0.0)

    # best[turn][end]: the cheapest way for turns 0..turn to cover up to the end-th possible end.
    ends = len(lasts)
    best = np.full((count, ends), np.inf)
    choice = np.zeros((count, ends), int)
    for end in range(ends - count + 1):
        best[0][end] = cost(0, 0, end)
    for turn in range(1, count):
        for end in range(turn, ends):
            options = [best[turn - 1][e] + cost(turn, e + 1, end) for e in range(turn - 1, end)]
            choice[turn][end] = turn - 1 + int(np.argmin(options))
            best[turn][end] = min(options)
    bounds, end = [], ends - 1
    for turn in range(count - 1, -1, -1):
        begin = choice[turn][end] + 1 if turn else 0
        bounds.append((begin, end))
        end = choice[turn][end]
    bounds.reverse()
    return bounds


def _expected_length(utterances: list[Utterance]) -> float:
    """Seconds the utterances take to say by the text's mean letter durations, their own pauses too."""
    return sum(
        float(letter_durations(u).sum()) + sum(word.pause_before for word in u.words[1:]) for u in utterances
    )
