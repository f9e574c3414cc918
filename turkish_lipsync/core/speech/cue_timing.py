"""Timing made elsewhere (Rhubarb cues, a Papagayo project) as the timing source of our Turkish visemes.

The visemes still come from our analysis of the Turkish text; the file only says when the mouth changes.
The method, per stretch of speech:

1. Stretches: the file's speech runs (cues between rests, X) are paired in order with the text's phrases
   (words between pauses). Where the counts differ, the shortest rests are bridged or the phrases with the
   shortest pauses joined until they agree. A Papagayo project whose words match ours pairs word by word.
2. Within a stretch, letters and cues are aligned in order by dynamic programming: each letter starts at a
   cue or shares one with its neighbour, each cue is covered by at least one letter. A step costs 0 where the
   letter's own Rhubarb shape (shapekeys/rhubarb_shapes.toml) is the cue's shape and 1 otherwise (2 against a
   rest), plus the distance between where the letter falls by the thesis's mean durations (Table 5.4) and
   where the cue falls in the stretch, so equal shapes do not pull letters far from their expected place.
3. A letter that starts a cue starts at the cue's start; letters sharing a cue split it in proportion to
   their mean durations; each letter ends where the next begins, the last one where the stretch ends.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..base.errors import TextError
from ..base.model import Timeline, Utterance
from ..text.utterance import build_utterance
from .audio import read_audio, to_pcm16
from .base import Synthesis
from .cues import CueFileError, CueSource, MouthCue, read_cue_file
from .cues.shapes import REST, shape_for_viseme
from .timeline import Speech
from .timing import build_timeline, letter_durations

CUE_TIMING = "cues"
_MISMATCH = 1.0
_REST_MISMATCH = 2.0
_PLACE_WEIGHT = 2.0  # cost of a whole stretch's distance from the expected place
CUES_PER_LETTER = 3.0  # more mouth changes than this per letter is not a reading of the text
LENGTH_FACTOR = 4.0  # the file's speech this many times longer or shorter than the text's is warned
_MAX_CELLS = 4_000_000  # letters x cues of one stretch (about 50 MB of alignment tables)


def timeline_from_cues(utterance: Utterance, source: CueSource) -> tuple[Timeline, tuple[str, ...]]:
    """The utterance timed by the file's cues (see the module's docstring); returns the warnings too."""
    warnings = list(source.warnings)
    durations = letter_durations(utterance)
    if source.word_cues and len(source.word_cues) == len(utterance.words):
        letter_groups = [range(w.first_letter, w.first_letter + w.letter_count) for w in utterance.words]
        cue_groups = [cues for _, cues in source.word_cues]
    else:
        if source.word_cues:
            warnings.append(
                f"{source.path} has {len(source.word_cues)} words and the text {len(utterance.words)}; "
                "its timing is matched by its pauses instead of word by word."
            )
        letter_groups, cue_groups = _pair_stretches(utterance, _speech_runs(source.cues))
    starts = np.empty(len(utterance.letters))
    ends = np.empty(len(utterance.letters))
    for letters, cues in zip(letter_groups, cue_groups, strict=True):
        if not cues:
            continue
        shapes = [shape_for_viseme(utterance.letters[i].viseme) for i in letters]
        group_starts = _align(shapes, durations[letters.start : letters.stop], cues)
        starts[letters.start : letters.stop] = group_starts
        ends[letters.start : letters.stop] = np.append(group_starts[1:], cues[-1].end)
    empty = [index for index, cues in enumerate(cue_groups) if not cues]
    for index in empty:  # words without phonemes: spoken where the neighbours leave room
        letters = letter_groups[index]
        at = ends[letters.start - 1] if letters.start else 0.0
        starts[letters.start : letters.stop] = at
        ends[letters.start : letters.stop] = at
    if empty:
        warnings.append(f"{source.path}: {len(empty)} word(s) have no phonemes and get no mouth motion.")
    duration = max(source.duration, float(ends.max(initial=0.0)))
    return build_timeline(utterance, starts, ends, duration, CUE_TIMING), tuple(warnings)


def speech_from_cues(
    source: str, cue_path: Path | str, recording: Path | str | None = None, fps: float = 24.0
) -> tuple[Utterance, Speech]:
    """The utterance and its speech timed by a cue file: the text is the source, else the file's own text;
    the audio is the recording, else the sound file the cue file names (beside it), else none."""
    cue_source = read_cue_file(cue_path, fps)
    text = source if source.strip() else cue_source.text
    if not text.strip():
        raise TextError(
            f"{cue_source.path} holds no text (Rhubarb files never do): "
            "give the Turkish text it was made from"
        )
    utterance = build_utterance(text)
    _check_cues_fit_the_text(utterance, cue_source)
    timeline, warnings = timeline_from_cues(utterance, cue_source)
    warnings += _length_warnings(utterance, cue_source)
    audio = Path(recording) if recording is not None else None
    if audio is None and cue_source.sound_file:
        named = cue_source.path.parent / cue_source.sound_file
        if named.is_file():
            audio = named
        else:
            warnings += (
                f"{cue_source.path} names the sound {cue_source.sound_file}, which is not there: "
                "the animation has no audio; give the recording as well.",
            )
    synthesis = None
    if audio is not None:
        samples, rate = read_audio(audio)
        synthesis = Synthesis(to_pcm16(samples), rate, (), (), "recording")
    return utterance, Speech(timeline, synthesis, warnings)


def _check_cues_fit_the_text(utterance: Utterance, source: CueSource) -> None:
    """A cue file of far more mouth changes than the text has letters is another text's (or the text is a
    small part of the recording): refused, where aligning them would spread each letter over seconds."""
    spoken = sum(1 for cue in source.cues if cue.shape != REST)
    letters = len(utterance.letters)
    if spoken > CUES_PER_LETTER * letters + 20:
        raise CueFileError(
            f"{source.path} holds {spoken:,} mouth changes for a text of {letters:,} letters (a reading has "
            f"fewer changes than letters): give the text the file was made from, or the cue file of this text"
        )


def _length_warnings(utterance: Utterance, source: CueSource) -> tuple[str, ...]:
    """A cue file much longer or shorter than the text would take to say: each letter is stretched."""
    expected = float(letter_durations(utterance).sum()) + sum(word.pause_before for word in utterance.words)
    spoken = sum(cue.end - cue.start for cue in source.cues if cue.shape != REST)
    if expected <= 0 or not (1 / LENGTH_FACTOR <= spoken / expected <= LENGTH_FACTOR):
        return (
            f"{source.path} speaks for {spoken:.1f} s, and the text takes about {expected:.1f} s to say: "
            "each letter is stretched to fit; check that the file is the cue file of this text.",
        )
    return ()


def _speech_runs(cues: tuple[MouthCue, ...]) -> list[list[MouthCue]]:
    """Maximal runs of non-rest cues, each with the rests inside it kept (none at first)."""
    runs: list[list[MouthCue]] = []
    previous_rest = True
    for cue in cues:
        if cue.shape == REST or cue.end - cue.start <= 0:
            previous_rest = previous_rest or cue.shape == REST
            continue
        if previous_rest or not runs:
            runs.append([])
        runs[-1].append(cue)
        previous_rest = False
    return runs


def _pair_stretches(
    utterance: Utterance, runs: list[list[MouthCue]]
) -> tuple[list[range], list[list[MouthCue]]]:
    """Phrases of letters paired with speech runs, joining runs or phrases until their counts agree."""
    if not runs:
        raise CueFileError("the timing file has no speech (every cue is a rest, X)")
    phrases: list[range] = []
    pauses: list[float] = []  # the pause before each phrase but the first
    for word in utterance.words:
        letters = range(word.first_letter, word.first_letter + word.letter_count)
        if phrases and word.pause_before <= 0:
            phrases[-1] = range(phrases[-1].start, letters.stop)
        else:
            if phrases:
                pauses.append(word.pause_before)
            phrases.append(letters)
    if len(runs) > len(
        phrases
    ):  # bridge the file's shortest rests (bridging one leaves the others as they are)
        gaps = np.array([runs[i + 1][0].start - runs[i][-1].end for i in range(len(runs) - 1)])
        bridged = set(np.argsort(gaps, kind="stable")[: len(runs) - len(phrases)].tolist())
        joined: list[list[MouthCue]] = [list(runs[0])]
        for i in range(1, len(runs)):
            if i - 1 in bridged:
                rest = MouthCue(runs[i - 1][-1].end, runs[i][0].start, REST)
                joined[-1].extend(([rest] if rest.end > rest.start else []) + runs[i])
            else:
                joined.append(list(runs[i]))
        runs = joined
    if len(phrases) > len(runs):  # join the text's phrases with the shortest pauses between them
        joins = set(np.argsort(np.array(pauses), kind="stable")[: len(phrases) - len(runs)].tolist())
        merged = [phrases[0]]
        for i in range(1, len(phrases)):
            if i - 1 in joins:
                merged[-1] = range(merged[-1].start, phrases[i].stop)
            else:
                merged.append(phrases[i])
        phrases = merged
    return phrases, runs


def _align(
    shapes: list[str], durations: np.ndarray, cues: list[MouthCue] | tuple[MouthCue, ...]
) -> np.ndarray:
    """Start times of the letters in one stretch (module docstring, steps 2-3)."""
    letter_count, cue_count = len(shapes), len(cues)
    if letter_count * cue_count > _MAX_CELLS:
        raise CueFileError(
            f"{letter_count} letters of the text meet {cue_count} cues without a pause of the text between "
            "them: put punctuation where the speaker pauses, so text and cue file pair up piece by piece"
        )
    cue_starts = np.array([cue.start for cue in cues])
    cue_ends = np.array([cue.end for cue in cues])
    span = max(cue_ends[-1] - cue_starts[0], 1e-9)
    cue_place = ((cue_starts + cue_ends) / 2 - cue_starts[0]) / span
    total = max(float(durations.sum()), 1e-9)
    letter_place = (np.cumsum(durations) - durations / 2) / total
    cue_shapes = np.array([cue.shape for cue in cues])
    cost = np.where(np.array(shapes)[:, None] == cue_shapes[None, :], 0.0, _MISMATCH)
    cost[:, cue_shapes == REST] = _REST_MISMATCH
    cost += _PLACE_WEIGHT * np.abs(letter_place[:, None] - cue_place[None, :])
    # total[i, j]: best path with letter i covering cue j last. A letter enters row i at cue k, from letter
    # i-1 ending at cue k-1 (a fresh cue) or at cue k (a shared one), then covers cues k..j.
    best = np.full((letter_count, cue_count), np.inf)
    entry = np.zeros((letter_count, cue_count), dtype=np.int32)
    shared = np.zeros((letter_count, cue_count), dtype=bool)
    running = np.cumsum(cost[0])
    best[0] = running
    for i in range(1, letter_count):
        fresh = np.concatenate(([np.inf], best[i - 1, :-1]))
        stay = best[i - 1]
        arrive = np.minimum(fresh, stay)
        prefix = np.cumsum(cost[i])
        before = np.concatenate(([0.0], prefix[:-1]))
        candidate = arrive - before
        cheapest = np.minimum.accumulate(candidate)
        positions = np.arange(cue_count)
        is_new = candidate <= cheapest
        entry[i] = np.maximum.accumulate(np.where(is_new, positions, 0))
        best[i] = prefix + cheapest
        shared[i] = stay < fresh
    # Walk back from the last letter covering the last cue.
    first_cue = np.zeros(letter_count, dtype=np.int64)
    shares = np.zeros(letter_count, dtype=bool)
    j = cue_count - 1
    for i in range(letter_count - 1, 0, -1):
        k = int(entry[i, j])
        first_cue[i] = k
        shares[i] = bool(shared[i, k])
        j = k if shares[i] else k - 1
    first_cue[0] = 0
    return _letter_starts(first_cue, shares, durations, cue_starts, cue_ends)


def _letter_starts(
    first_cue: np.ndarray,
    shares: np.ndarray,
    durations: np.ndarray,
    cue_starts: np.ndarray,
    cue_ends: np.ndarray,
) -> np.ndarray:
    """Start of each letter: its first cue's start, or, inside a cue shared with the letters before it,
    the cue split among all the letters on it by their mean durations."""
    starts = cue_starts[first_cue].astype(np.float64)
    count = len(first_cue)
    i = 0
    while i < count:
        group_end = i + 1  # letters i.. that each begin inside the cue letter i ends on
        while group_end < count and shares[group_end] and first_cue[group_end] == first_cue[i + 1]:
            group_end += 1
        if group_end > i + 1:
            cue = int(first_cue[i + 1])
            weights = durations[i:group_end]
            fractions = np.cumsum(weights)[:-1] / max(float(weights.sum()), 1e-9)
            starts[i + 1 : group_end] = cue_starts[cue] + fractions * (cue_ends[cue] - cue_starts[cue])
            i = group_end - 1
        else:
            i += 1
    return starts
