"""Each line spoken alone in its speaker's voice (or aligned to its own recording), and the lines laid one
after another with conversational gaps (conversation.toml [turns]; Stivers et al. 2009: about 200 ms between
turns), the markup's BREAK where it gives one, the usual gap within one speaker's turn, an overlap where the
line is marked so. A gap runs from the last phone of the line before to the first phone of the next."""

from __future__ import annotations

import math

import numpy as np

from ...base.errors import LipSyncError
from ...speech import synthesize_timeline
from ...speech.audio import levels_under_loud
from ...text.script import Script
from ..speech import HEARD_DB, TAIL, SceneLine, SceneSpeech, SoundPiece
from ..tables import Turns, conversation_table
from .base import SCENE_SOURCES, SceneRequest, SceneSource

READY = 0.3  # an overlapping line starts at least this long after the line it overlaps began


@SCENE_SOURCES.register
class SpokenLines(SceneSource):
    name = "spoken lines"
    given_as = "recordings per line"
    priority = 0

    def claims(self, request: SceneRequest) -> bool:
        return True

    def speak(self, request: SceneRequest) -> SceneSpeech:
        recordings = request.line_recordings
        if recordings and len(recordings) != len(request.script.lines):
            raise LipSyncError(
                f"The script has {len(request.script.lines)} lines and {len(recordings)} line recordings "
                "were given: give one recording per line, in the order of the lines."
            )
        speeches = [
            synthesize_timeline(
                utterance,
                request.timing,
                recording=recordings[index] if recordings else None,
                engine=request.engine,
                aligner=request.aligner,
            )
            for index, utterance in enumerate(request.utterances)
        ]
        return laid_out(request, speeches)


def line_starts(
    script: Script, firsts: list[float], lasts: list[float], rng: np.random.Generator, turns: Turns
) -> list[float]:
    """Where each line's audio starts on the scene so that its first phone (firsts: seconds into its own
    audio) follows the last phone before it (lasts, likewise) by a conversational gap, a BREAK, the pause
    within one speaker's turn, or overlaps it as marked."""
    starts: list[float] = []
    first_at: list[float] = []
    last_at: list[float] = []
    for index, line in enumerate(script.lines):
        if index == 0:
            first = (line.pause_before or 0.0) + firsts[0]
        elif line.overlaps:
            overlap = line.overlap if line.overlap is not None else turns.overlap
            first = max(last_at[-1] - overlap, first_at[-1] + READY)
        else:
            if line.pause_before is not None:
                gap = line.pause_before
            elif line.speaker == script.lines[index - 1].speaker:
                gap = turns.same_speaker_gap
            else:
                drawn = math.exp(math.log(turns.gap_median) + turns.gap_spread * float(rng.standard_normal()))
                gap = min(max(drawn, turns.gap_min), turns.gap_max)
            first = max(last_at) + gap
        start = max(0.0, first - firsts[index])
        starts.append(start)
        first_at.append(start + firsts[index])
        last_at.append(start + lasts[index])
    return starts


def laid_out(request: SceneRequest, speeches: list) -> SceneSpeech:
    """The lines' speeches one after another on the scene's timeline (line_starts)."""
    script, cast = request.script, request.cast
    spans = [heard_span(speech) for speech in speeches]
    firsts = [first for first, _ in spans]
    lasts = [last for _, last in spans]
    starts = line_starts(script, firsts, lasts, request.rng(), conversation_table().turns)
    duration = max(start + last for start, last in zip(starts, lasts, strict=True)) + TAIL
    duration = max(
        [duration]
        + [
            start + s.synthesis.duration
            for start, s in zip(starts, speeches, strict=True)
            if s.synthesis is not None
        ]
    )
    lines, pieces, warnings = [], [], []
    addressees = request.addressees
    for index, (line, utterance, speech, start) in enumerate(
        zip(script.lines, request.utterances, speeches, starts, strict=True)
    ):
        lines.append(
            SceneLine(
                index, line.speaker, addressees[index], speech.timeline.shifted(start, duration), utterance
            )
        )
        if speech.synthesis is not None:
            name = f"{cast.role(line.speaker).name} {index + 1}"
            pieces.append(SoundPiece(name, line.speaker, start, speech.synthesis, index))
        warnings += [f"Line {index + 1} ({cast.role(line.speaker).name}): {w}" for w in speech.warnings]
    timing = speeches[0].timeline.timing if speeches else request.timing
    return SceneSpeech(script, cast, tuple(lines), tuple(pieces), duration, timing, tuple(warnings))


def heard_span(speech) -> tuple[float, float]:
    """Where a line is heard in its own audio: from its first phone (or the first sound, if earlier) to its
    last phone (or the last sound, if later); gaps are what a listener hears between voices."""
    first = min(p.start for p in speech.timeline.phones)
    last = max(p.end for p in speech.timeline.phones)
    audio = speech.synthesis
    if audio is None or not audio.samples.size:
        return first, last
    hop = max(1, audio.sample_rate // 100)
    heard = np.flatnonzero(levels_under_loud(audio.samples, hop) > HEARD_DB)
    if not heard.size:
        return first, last
    return min(first, heard[0] * hop / audio.sample_rate), max(
        last, (heard[-1] + 1) * hop / audio.sample_rate
    )
