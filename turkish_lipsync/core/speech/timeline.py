"""The Timeline of an utterance in each timing mode: phone (default), word (the thesis), table, recording."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..base.errors import LipSyncError, TextError
from ..base.model import Timeline, Utterance
from .align import phone_letter_spans, word_letter_spans
from .aligner_settings import DEFAULT_ALIGNER, AlignerSettings
from .base import Synthesis, get_engine
from .recording import RecordedAudio, align_recording
from .timewarp import with_closures
from .timing import build_timeline, table_timeline

TIMINGS = ("phone", "word", "table", "recording")


@dataclass(frozen=True, eq=False)
class Speech:
    """A timeline, the audio it belongs to (None for table timing) and what the user must hear about it."""

    timeline: Timeline
    synthesis: Synthesis | None
    warnings: tuple[str, ...] = ()


# The synthetic audio of one utterance is held in memory (about 160 MB an hour, with its working copies
# several times that): longer texts are refused before the engine starts rather than exhausting memory.
# A recording's script is exempt: its synthetic rendition is made and dropped chunk by chunk.
MAX_SPOKEN_LETTERS = 60_000  # about 90 minutes of speech
# Said wherever a recording is given with table timing (the panel disables Generate with it too).
TABLE_CANNOT_FOLLOW_RECORDING = (
    "Table timing uses no speech, so it cannot follow a recording: choose Phone or Word timing"
)


def check_timing_follows(timing: str, recording_given: bool) -> None:
    """Refuse table timing for a recording: it uses no speech, so there is nothing to align."""
    if timing == "table" and recording_given:
        raise LipSyncError(TABLE_CANNOT_FOLLOW_RECORDING)


def synthesize_timeline(
    utterance: Utterance,
    timing: str = "phone",
    *,
    recording: Path | str | RecordedAudio | None = None,
    engine: str = "espeak",
    aligner: AlignerSettings = DEFAULT_ALIGNER,
) -> Speech:
    """Speak the utterance and time every letter: the timeline, the audio it belongs to, warnings.

    timing: "phone" keys each letter on the phone the engine spoke for it; "word" is the thesis's method
    (word-start events, Table 5.4 durations inside words); "table" needs no engine and returns no audio.
    With a recording, the synthetic speech is aligned to it and the timeline follows the recording
    (timing "recording"; "word" then places the thesis's durations after the recording's word starts);
    the returned Synthesis then holds the recording's samples. `aligner`: the alignment's settings.
    """
    if timing not in TIMINGS:
        raise LipSyncError(f"unknown timing {timing!r}; choose one of: {', '.join(TIMINGS)}")
    if timing == "table":
        check_timing_follows(timing, recording is not None)
        return Speech(table_timeline(utterance), None)
    if timing == "recording" and recording is None:
        raise LipSyncError("recording timing needs a recording: give the audio file of the text read aloud")
    if recording is None and len(utterance.letters) > MAX_SPOKEN_LETTERS:
        raise TextError(
            f"the text has {len(utterance.letters):,} letters to speak, more than the {MAX_SPOKEN_LETTERS:,} "
            "(about 90 minutes of speech) one utterance may hold: split it into several texts, or use table "
            "timing, which needs no audio"
        )
    speech_engine = get_engine(engine)
    label, warnings, hesitations = timing, (), ()
    if recording is None:
        synthesis = speech_engine.synthesize(utterance)
    else:  # synthesised in chunks: a take of any length, its script past MAX_SPOKEN_LETTERS included
        alignment = align_recording(utterance, recording, speech_engine, aligner)
        synthesis, warnings, label = alignment.synthesis, alignment.warnings, "recording"
        hesitations = alignment.hesitations
    if timing == "word":
        starts, ends = word_letter_spans(utterance, synthesis)
    else:
        starts, ends, synthesis = phone_letter_spans(utterance, with_closures(synthesis), speech_engine)
    onsets = tuple(event.start for event in synthesis.phone_events)
    timeline = build_timeline(utterance, starts, ends, synthesis.duration, label, onsets, hesitations)
    return Speech(timeline, synthesis, warnings)
