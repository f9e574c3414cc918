"""One recording of the whole scene: the whole script (each line in its speaker's voice, with usual gaps) is
aligned to it as one take, and each line's words keep the times the take gives them. A line marked as
overlapping is aligned again on its own stretch of the take."""

from __future__ import annotations

import numpy as np

from ...base.errors import LipSyncError
from ...base.model import Timeline, Utterance
from ...speech import Synthesis, synthesize_timeline
from ...speech.recording import RecordedAudio
from ..speech import SceneLine, SceneSpeech, SoundPiece, scene_utterance, split_timeline
from ..tables import conversation_table
from .base import SCENE_SOURCES, SceneRequest, SceneSource

STRETCH_SHIFT = 0.1  # seconds an overlapping line's stretch is begun earlier to see whether the line moves


@SCENE_SOURCES.register
class SceneRecording(SceneSource):
    name = "scene recording"
    given_as = "a recording of the whole scene"
    priority = 10

    def claims(self, request: SceneRequest) -> bool:
        return request.scene_recording is not None

    def speak(self, request: SceneRequest) -> SceneSpeech:
        script, utterances = request.script, list(request.utterances)
        whole = scene_utterance(script, request.cast, rate=request.rate)
        speech = synthesize_timeline(
            whole, request.timing, recording=request.scene_recording, engine=request.engine,
            aligner=request.aligner,
        )  # fmt: skip
        duration = speech.synthesis.duration
        timelines = split_timeline(speech.timeline, utterances, duration)
        for index, line in enumerate(script.lines):
            if line.overlaps and index:
                others = [
                    i
                    for i, other in enumerate(script.lines)
                    if other.speaker == line.speaker and not other.overlaps and timelines[i].phones
                ]
                pace = _pace([timelines[i] for i in others], [utterances[i] for i in others], request)
                timelines[index] = _overlapping(
                    speech.synthesis, timelines[index - 1], timelines[index], index, request, pace
                )
        addressees = request.addressees
        lines = tuple(
            SceneLine(index, line.speaker, addressees[index], timelines[index], utterances[index])
            for index, line in enumerate(script.lines)
        )
        piece = SoundPiece("scene", None, 0.0, speech.synthesis)
        return SceneSpeech(
            script, request.cast, lines, (piece,), duration, speech.timeline.timing, speech.warnings
        )


def _own_timeline(utterance: Utterance, request: SceneRequest) -> Timeline:
    """The line as the engine says it alone."""
    return synthesize_timeline(utterance, request.timing, engine=request.engine).timeline


def _pace(timelines: list[Timeline], utterances: list[Utterance], request: SceneRequest) -> float:
    """How long a speaker takes over their lines as the take has them, against the engine's (1: none)."""
    taken = sum(_span(timeline) for timeline in timelines)
    own = sum(_span(_own_timeline(u, request)) for u in utterances)
    return taken / own if taken > 0 and own > 0 else 1.0


def _span(timeline: Timeline) -> float:
    return max(p.end for p in timeline.phones) - min(p.start for p in timeline.phones)


def _overlapping(
    take: Synthesis, before: Timeline, aligned: Timeline, index: int, request: SceneRequest, pace: float
) -> Timeline:
    """A line marked as overlapping, aligned again on its own: one take of the scene is aligned one voice
    after another, which puts it after the line it overlaps. Aligned to the stretch of the take from a little
    more than the marked overlap before the other line's end to its own end, where its words are the only
    ones that can match; kept as it was where that finds nothing clear."""
    line, utterance = request.script.lines[index], request.utterances[index]
    overlap = line.overlap if line.overlap is not None else conversation_table().turns.overlap
    other_end = max(phone.end for phone in before.phones)
    own_end = max(phone.end for phone in aligned.phones)
    was = min(phone.start for phone in aligned.phones)
    pinned = []

    def aligned_from(start: float) -> tuple[Timeline, tuple[str, ...]] | None:
        first, last = int(start * take.sample_rate), int((own_end + 0.3) * take.sample_rate)
        stretch = RecordedAudio(
            take.samples[first:last].astype(np.float32) / 32768,
            take.sample_rate,
            f"{request.scene_recording} from {start:.2f} s (line {index + 1})",
        )
        try:
            found = synthesize_timeline(
                utterance, request.timing, recording=stretch, engine=request.engine, aligner=request.aligner
            )
        except LipSyncError:
            return None
        return found.timeline.shifted(start, aligned.duration), found.warnings

    for lead in (overlap + 0.15, overlap + 0.05, overlap, overlap + 0.3):
        start = max(other_end - lead, 0.0)
        result = aligned_from(start)
        if result is None:
            continue
        refined, warnings = result
        begins = min(phone.start for phone in refined.phones)
        # The other voice in the stretch may be heard as words the line does not have: the line is kept
        # where it begins in the stretch and no later than the whole take's alignment put it. A line that
        # begins with the stretch itself, or moves with it when the stretch begins earlier, took the other
        # voice for its first word (below); a line heard where it is said stays where it is.
        if begins < start + 0.02 or _moves_with(aligned_from, start, begins):
            pinned.append((refined, start))
        elif not warnings or begins <= was + 0.02:
            return refined
    # The acoustic model may hear the other voice at the stretch's start as the line's first word, which
    # then reaches back to the stretch's start; the words after it are heard alone and lie where they are
    # said. The first word goes back before the second by the length the engine gives it at the speaker's
    # pace over their other lines (the pace of the line's few other words is no guide: one short word said
    # 1.5 times eSpeak's length put the line 210 ms early).
    for refined, start in pinned:
        placed = _first_word_as_spoken(refined, utterance, request, pace, start, was + 0.02)
        if placed is not None:
            return placed
    return aligned


def _moves_with(aligned_from, start: float, begins: float) -> bool:
    """Whether a line that begins at `begins` in the stretch from `start` begins STRETCH_SHIFT earlier too
    (at least half of it) when the stretch does."""
    if start <= 0.0:
        return False
    earlier = aligned_from(max(start - STRETCH_SHIFT, 0.0))
    return earlier is not None and begins - min(p.start for p in earlier[0].phones) > STRETCH_SHIFT / 2


def _first_word_as_spoken(
    timeline: Timeline,
    utterance: Utterance,
    request: SceneRequest,
    pace: float,
    earliest: float,
    latest: float,
) -> Timeline | None:
    """The timeline with its first word (and the pause after it) as long as the engine says them, times the
    speaker's pace; None where the line has one word, or the first word would begin outside
    earliest..latest."""
    words = timeline.words
    if len(words) < 2:
        return None
    own = _own_timeline(utterance, request).words
    begins = words[1].start - (own[1].start - own[0].start) * pace
    if not earliest <= begins <= latest:
        return None
    return timeline.remapped((words[0].start, words[1].start), (begins, words[1].start))
