"""A scene's speech: every line spoken in its speaker's voice, or found in the recordings, on one timeline.

Where each line comes from:

- synthesis: each line is spoken alone in its speaker's voice, and the lines are laid one after another
  with conversational gaps (conversation.toml [turns]; Stivers et al. 2009: about 200 ms between turns),
  the markup's BREAK where it gives one, the usual gap within one speaker's turn, an overlap where the line
  is marked so. A gap runs from the last phone of the line before to the first phone of the next.
- one recording of the whole scene: the whole script (each line in its speaker's voice, with usual gaps) is
  aligned to it as one take (speech/recording.py's align_recording, through synthesize_timeline), and each
  line's words keep the times the take gives them;
- one recording per speaker: each a track of the scene (it starts where the scene starts, silent while the
  others speak), aligned to that speaker's lines in order;
- one recording per line: each aligned to its own line, then laid out as synthesised lines are;
- a Papagayo project with one voice per speaker (as the scene's own export writes it): each voice times
  that speaker's lines, its sound the scene's.

Each line's timeline is on the scene's timeline; a speaker's timeline holds only their own lines, so their
mouth is at rest while the others speak.
"""

from __future__ import annotations

import math
import tempfile
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..base.errors import LipSyncError
from ..base.model import EmotionSpan, Pause, SpokenWord, Timeline, Utterance
from ..speech import Synthesis, synthesize_timeline, write_wav
from ..speech.audio import read_audio, resampled_pcm
from ..speech.cue_timing import timeline_from_cues
from ..speech.cues import CueSource
from ..speech.cues.papagayo_pgo import read_pgo_voices, rest_between, spoken_words
from ..speech.decoders import RECORDING_KINDS, RECORDING_SUFFIXES
from ..speech.timing import build_timeline, letter_durations
from ..text.normalize import normalize
from ..text.script import Script, ScriptLine, speaker_key
from ..text.utterance import assemble_utterance
from .cast import Cast, spoken_by
from .tables import Turns, conversation_table

HEARD_DB = -35.0  # a line's audio this far under its loud end is silence
MIN_TURN_SILENCE = 0.3  # seconds of silence in a speaker's track that may part two of their turns
SILENCE_WEIGHT = 0.2  # how much a longer silence is preferred as the end of a speaker's turn
STRETCH_MARGIN = 0.3  # seconds of silence kept around a turn's stretch of a speaker's track
TAIL = 0.5  # seconds of the scene after its last phone (the last listener still reacting)
READY = 0.3  # an overlapping line starts at least this long after the line it overlaps began
STRETCH_SHIFT = 0.1  # seconds an overlapping line's stretch is begun earlier to see whether the line moves


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
    script: Script
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
) -> SceneSpeech:
    """Every line of the script spoken (or found in the recordings) on the scene's timeline."""
    sources = sources or SceneSources()
    speaker_recordings = {role.key: role.recording for role in cast.roles if role.recording is not None}
    speaker_recordings |= {speaker_key(k): Path(v) for k, v in (sources.speaker_recordings or {}).items()}
    given = [
        name
        for name, used in (
            ("a recording of the whole scene", sources.scene_recording is not None),
            ("recordings per speaker", bool(speaker_recordings)),
            ("recordings per line", bool(sources.line_recordings)),
            ("a cue file", sources.cues is not None),
        )
        if used
    ]
    if len(given) > 1:
        raise LipSyncError(f"The scene is given {' and '.join(given)}; give only one of them.")
    if given and timing == "table":
        raise LipSyncError(
            "Table timing uses no speech, so it cannot follow a recording; choose phone or word."
        )
    utterances = [line_utterance(script, line, cast, rate) for line in script.lines]
    addressees = script.addressees()
    rng = np.random.default_rng([seed, 31])
    if sources.cues is not None:
        return _from_papagayo(script, cast, utterances, addressees, sources.cues, rate)
    if sources.scene_recording is not None:
        return _from_scene_recording(
            script, cast, utterances, addressees, timing, engine, sources.scene_recording, rate
        )
    if speaker_recordings:
        return _from_speaker_recordings(
            script, cast, utterances, addressees, timing, engine, speaker_recordings, rate
        )
    if sources.line_recordings and len(sources.line_recordings) != len(script.lines):
        raise LipSyncError(
            f"The script has {len(script.lines)} lines and {len(sources.line_recordings)} line recordings "
            "were given: give one recording per line, in the order of the lines."
        )
    speeches = [
        synthesize_timeline(
            utterance,
            timing,
            recording=sources.line_recordings[index] if sources.line_recordings else None,
            engine=engine,
        )
        for index, utterance in enumerate(utterances)
    ]
    return _laid_out(script, cast, utterances, addressees, speeches, rng, timing)


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


# ---------------------------------------------------------------- lines laid out one after another


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


def _laid_out(script, cast, utterances, addressees, speeches, rng, timing: str) -> SceneSpeech:
    spans = [_heard_span(speech) for speech in speeches]
    firsts = [first for first, _ in spans]
    lasts = [last for _, last in spans]
    starts = line_starts(script, firsts, lasts, rng, conversation_table().turns)
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
    for index, (line, utterance, speech, start) in enumerate(
        zip(script.lines, utterances, speeches, starts, strict=True)
    ):
        lines.append(
            SceneLine(
                index,
                line.speaker,
                addressees[index],
                speech.timeline.shifted(start, duration),
                utterance,
            )
        )
        if speech.synthesis is not None:
            name = f"{cast.role(line.speaker).name} {index + 1}"
            pieces.append(SoundPiece(name, line.speaker, start, speech.synthesis, index))
        warnings += [f"Line {index + 1} ({cast.role(line.speaker).name}): {w}" for w in speech.warnings]
    return SceneSpeech(
        script, cast, tuple(lines), tuple(pieces), duration, _label(speeches, timing), tuple(warnings)
    )


def _heard_span(speech) -> tuple[float, float]:
    """Where a line is heard in its own audio: from its first phone (or the first sound, if earlier) to its
    last phone (or the last sound, if later); gaps are what a listener hears between voices."""
    first = min(p.start for p in speech.timeline.phones)
    last = max(p.end for p in speech.timeline.phones)
    audio = speech.synthesis
    if audio is None or not audio.samples.size:
        return first, last
    hop = max(1, audio.sample_rate // 100)
    count = audio.samples.size // hop
    power = (audio.samples[: count * hop].astype(np.float64).reshape(count, hop) ** 2).mean(axis=1)
    level = 10 * np.log10(np.maximum(power, 1e-12) / max(float(np.percentile(power, 95)), 1e-12))
    heard = np.flatnonzero(level > HEARD_DB)
    if not heard.size:
        return first, last
    return min(first, heard[0] * hop / audio.sample_rate), max(
        last, (heard[-1] + 1) * hop / audio.sample_rate
    )


def _label(speeches, timing: str) -> str:
    return speeches[0].timeline.timing if speeches else timing


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
    """The timeline of several lines spoken as one utterance, as one timeline per line (same times)."""
    phones = sorted(timeline.phones, key=lambda phone: phone.letter_index)
    starts = np.array([phone.start for phone in phones])
    ends = np.array([phone.end for phone in phones])
    result, first = [], 0
    for utterance in utterances:
        count = len(utterance.letters)
        result.append(
            build_timeline(
                utterance,
                starts[first : first + count],
                ends[first : first + count],
                duration,
                timeline.timing,
            )
        )
        first += count
    return result


def _from_scene_recording(
    script, cast, utterances, addressees, timing, engine, path: Path, rate
) -> SceneSpeech:
    whole = scene_utterance(script, cast, rate=rate)
    speech = synthesize_timeline(whole, timing, recording=path, engine=engine)
    duration = speech.synthesis.duration
    timelines = split_timeline(speech.timeline, utterances, duration)
    for index, line in enumerate(script.lines):
        if line.overlaps and index:
            others = [
                i
                for i, other in enumerate(script.lines)
                if other.speaker == line.speaker and not other.overlaps and timelines[i].phones
            ]
            timelines[index] = _overlapping(
                speech.synthesis,
                timelines[index - 1],
                timelines[index],
                utterances[index],
                line,
                timing,
                engine,
                _pace([timelines[i] for i in others], [utterances[i] for i in others], timing, engine),
            )
    lines = tuple(
        SceneLine(index, line.speaker, addressees[index], timelines[index], utterances[index])
        for index, line in enumerate(script.lines)
    )
    piece = SoundPiece("scene", None, 0.0, speech.synthesis)
    return SceneSpeech(script, cast, lines, (piece,), duration, speech.timeline.timing, speech.warnings)


def _pace(timelines: list[Timeline], utterances: list[Utterance], timing, engine) -> float:
    """How long a speaker takes over their lines as the take has them, against the engine's (1: none)."""
    taken = sum(_span(timeline) for timeline in timelines)
    own = sum(_span(synthesize_timeline(u, timing, engine=engine).timeline) for u in utterances)
    return taken / own if taken > 0 and own > 0 else 1.0


def _span(timeline: Timeline) -> float:
    return max(p.end for p in timeline.phones) - min(p.start for p in timeline.phones)


def _overlapping(
    take: Synthesis, before: Timeline, aligned: Timeline, utterance, line, timing, engine, pace: float
) -> Timeline:
    """A line marked as overlapping, aligned again on its own: one take of the scene is aligned one voice
    after another, which puts it after the line it overlaps. Aligned to the stretch of the take from a little
    more than the marked overlap before the other line's end to its own end, where its words are the only
    ones that can match; kept as it was where that finds nothing clear."""
    overlap = line.overlap if line.overlap is not None else conversation_table().turns.overlap
    other_end = max(phone.end for phone in before.phones)
    own_end = max(phone.end for phone in aligned.phones)
    was = min(phone.start for phone in aligned.phones)
    pinned = []
    with tempfile.TemporaryDirectory() as folder:

        def aligned_from(start: float) -> tuple[Timeline, tuple[str, ...]] | None:
            first, last = int(start * take.sample_rate), int((own_end + 0.3) * take.sample_rate)
            stretch = Synthesis(take.samples[first:last], take.sample_rate, (), (), "recording")
            path = write_wav(Path(folder) / "line.wav", stretch)
            try:
                found = synthesize_timeline(utterance, timing, recording=path, engine=engine)
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
            # begins with the stretch itself, or moves with it when the stretch begins earlier, took the
            # other voice for its first word (below); a line heard where it is said stays where it is.
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
        placed = _first_word_as_spoken(refined, utterance, timing, engine, pace, start, was + 0.02)
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
    timeline: Timeline, utterance, timing, engine, pace: float, earliest: float, latest: float
) -> Timeline | None:
    """The timeline with its first word (and the pause after it) as long as the engine says them, times the
    speaker's pace; None where the line has one word, or the first word would begin outside
    earliest..latest."""
    words = timeline.words
    if len(words) < 2:
        return None
    own = synthesize_timeline(utterance, timing, engine=engine).timeline.words
    begins = words[1].start - (own[1].start - own[0].start) * pace
    if not earliest <= begins <= latest:
        return None
    return timeline.remapped((words[0].start, words[1].start), (begins, words[1].start))


def _from_speaker_recordings(
    script, cast, utterances, addressees, timing, engine, recordings, rate
) -> SceneSpeech:
    """Each speaker's track of the scene: where it speaks, one turn of theirs a stretch (split at its longest
    silences, since the others' lines leave long ones), each turn aligned to its own stretch."""
    missing = [role.name for role in cast.roles if role.key not in recordings]
    if missing:
        raise LipSyncError(
            f"Recordings per speaker were given, but none for {', '.join(missing)}: give every speaker a "
            "recording (their track of the scene), or one recording of the whole scene."
        )
    timelines: dict[int, Timeline] = {}
    pieces, warnings = [], []
    duration = 0.0
    with tempfile.TemporaryDirectory() as folder:
        for role in cast.roles:
            samples, sample_rate = read_audio(recordings[role.key])
            pcm = np.clip(np.round(samples * 32767), -32768, 32767).astype(np.int16)
            track = Synthesis(pcm, sample_rate, (), (), "recording")
            duration = max(duration, track.duration)
            turns = _turns_of(script, role.key)
            expected = [_expected_length([utterances[i] for i in turn]) for turn in turns]
            stretches = _stretches(pcm, sample_rate, expected)
            if stretches is None:  # no clear silence between its turns: the track aligned as one take
                turns, stretches = [[i for turn in turns for i in turn]], [(0.0, track.duration)]
            for number, (turn, (start, end)) in enumerate(zip(turns, stretches, strict=True)):
                first, last = int(start * sample_rate), int(np.ceil(end * sample_rate))
                path = Path(folder) / f"{role.key}-{number}.wav"
                write_wav(path, Synthesis(pcm[first:last], sample_rate, (), (), "recording"))
                speech = synthesize_timeline(
                    scene_utterance(script, cast, turn, rate), timing, recording=path, engine=engine
                )
                warnings += [f"{role.name}'s recording near {start:.1f} s: {w}" for w in speech.warnings]
                parts = split_timeline(speech.timeline, [utterances[i] for i in turn], duration)
                for index, part in zip(turn, parts, strict=True):
                    timelines[index] = part.shifted(start, duration)
            pieces.append(SoundPiece(role.name, role.key, 0.0, track))
    lines = tuple(
        SceneLine(
            index,
            line.speaker,
            addressees[index],
            replace(timelines[index], duration=duration),
            utterances[index],
        )
        for index, line in enumerate(script.lines)
    )
    label = lines[0].timeline.timing if lines else timing
    return SceneSpeech(script, cast, lines, tuple(pieces), duration, label, tuple(warnings))


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
    power = (pcm[: frames * hop].astype(np.float64).reshape(frames, hop) ** 2).mean(axis=1)
    level = 10 * np.log10(np.maximum(power, 1e-12) / max(float(np.percentile(power, 95)), 1e-12))
    loud = np.flatnonzero(level > HEARD_DB)
    count = len(expected)
    if not loud.size:
        return None
    candidates = np.flatnonzero(np.diff(loud) > int(MIN_TURN_SILENCE * 100))
    if candidates.size < count - 1:
        return None
    firsts = np.concatenate([[loud[0]], loud[candidates + 1]])  # where a stretch may begin
    lasts = np.concatenate([loud[candidates] + 1, [loud[-1] + 1]])  # ... and end
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
        bounds.append((firsts[begin], lasts[end]))
        end = choice[turn][end]
    bounds.reverse()
    margin = int(STRETCH_MARGIN * 100)
    stretches = []
    for number, (first, last) in enumerate(bounds):
        before = bounds[number - 1][1] if number else 0
        after = bounds[number + 1][0] if number + 1 < count else frames
        stretches.append(
            (
                max(first - margin, (before + first) // 2) * hop / rate,
                min(last + margin, (last + after) // 2) * hop / rate,
            )
        )
    return stretches


def _expected_length(utterances: list[Utterance]) -> float:
    """Seconds the utterances take to say by the text's mean letter durations, their own pauses too."""
    return sum(
        float(letter_durations(u).sum()) + sum(word.pause_before for word in u.words[1:]) for u in utterances
    )


def _from_papagayo(script, cast, utterances, addressees, path: Path, rate) -> SceneSpeech:
    """Each voice of a Papagayo project times its speaker's lines: voices matched to speakers by name, else
    in order where the project has as many voices as the script speakers."""
    voices = read_pgo_voices(Path(path))
    by_name = {speaker_key(voice.voice_name): voice for voice in voices}
    if all(role.key in by_name for role in cast.roles):
        chosen = {role.key: by_name[role.key] for role in cast.roles}
    elif len(voices) == len(cast.roles):
        chosen = {role.key: voice for role, voice in zip(cast.roles, voices, strict=True)}
    else:
        names = ", ".join(voice.voice_name for voice in voices)
        raise LipSyncError(
            f"{path} has the voices {names}, which do not match the script's speakers "
            f"({', '.join(role.name for role in cast.roles)}): name each voice after its speaker."
        )
    timelines: dict[int, Timeline] = {}
    warnings: list[str] = []
    duration = max(voice.duration_frames / voice.fps for voice in voices)
    for role in cast.roles:
        voice = chosen[role.key]
        own = [index for index, line in enumerate(script.lines) if line.speaker == role.key]
        whole = scene_utterance(script, cast, own, rate)
        words = spoken_words(voice)
        cues = rest_between(words)
        if not cues:
            raise LipSyncError(
                f"{path}: the voice {voice.voice_name} holds no phonemes; break its words down first"
            )
        source = CueSource(
            Path(path), cues, duration, text=voice.text, sound_file=voice.sound_path, word_cues=words
        )
        timeline, found = timeline_from_cues(whole, source)
        warnings += [f"{role.name}: {w}" for w in found]
        duration = max(duration, timeline.duration)
        for index, line_timeline in zip(
            own, split_timeline(timeline, [utterances[i] for i in own], duration), strict=True
        ):
            timelines[index] = line_timeline
    lines = tuple(
        SceneLine(index, line.speaker, addressees[index], timelines[index], utterances[index])
        for index, line in enumerate(script.lines)
    )
    pieces = ()
    sound = Path(path).parent / voices[0].sound_path if voices[0].sound_path else None
    if sound is not None and sound.is_file():
        samples, rate = read_audio(sound)
        pcm = np.clip(np.round(samples * 32768), -32768, 32767).astype(np.int16)
        pieces = (SoundPiece("scene", None, 0.0, Synthesis(pcm, rate, (), (), "recording")),)
    elif voices[0].sound_path:
        warnings.append(
            f"{path} names the sound {voices[0].sound_path}, which is not there: the scene is silent."
        )
    return SceneSpeech(script, cast, lines, pieces, duration, "cues", tuple(warnings))


# ---------------------------------------------------------------- timelines


def with_faint_emotions(timeline: Timeline, heard: list[Timeline], share: float) -> Timeline:
    """A listener's timeline with the emotions of the lines it hears, at `share` of their weight."""
    faint = [EmotionSpan(e.start, e.end, e.emotion, e.weight * share) for t in heard for e in t.emotions]
    if not faint or share <= 0:
        return timeline
    return replace(timeline, emotions=tuple(sorted((*timeline.emotions, *faint), key=lambda e: e.start)))
