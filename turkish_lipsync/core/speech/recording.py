"""A user's own recording of the text: read it, align the synthetic rendition to it, warp the events.

The recording is read, mixed to mono and resampled (audio.py) while the text is synthesised in a thread
of its own, in chunks of sentences, so a take of any length needs only its features in memory, not the
synthetic audio. Both signals become speaker- and room-normalised cepstra (features.py), a live room's
late reverberation taken out of the recording first (reverberation.py); the recording's speech is
found by voice activity detection (voice_activity.py), and the two are matched by dynamic time warping
(dtw.py) with the synthetic speech padded by silence, so noise, a breath or a click before the first
word is matched to silence instead of being taken for speech. The recording's vocal tract length is
searched over a few warps. A person pauses where the text has no comma and skips pauses it has: the
DTW may hold any word boundary through a recorded pause and any synthetic pause against the recording
(_pauses). Only matches of speech with speech become knots of the warp (timewarp.py); pauses both make
are crossed linearly, a pause only the recording makes is put before the word after it.

How well each synthetic frame's match ranks among the text's sounds gives every word and phrase a
confidence: a recording of another text is refused, a word left out or added is named in a warning
(judgement.py).
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..base.errors import AudioError
from ..base.model import Utterance
from .audio import MAX_OUTPUT_RATE, read_audio, resample, resampled_pcm
from .base import PhoneEvent, SpeechEngine, Synthesis, WordEvent
from .dtw import Pauses, dtw_path
from .features import (
    ANALYSIS_RATE,
    HOP,
    TOP_HERTZ,
    WINDOW,
    band_levels,
    cepstra,
    common_floor,
    frame_count,
    mel_energies,
    mel_filters,
    power_spectra,
)
from .judgement import Fit, PhraseMatch, judge, match_ranks
from .reverberation import dereverberate, estimate_rt60
from .speech_detector import detect_speech
from .timewarp import TimeWarp, warp_from_path, warp_synthesis
from .voice_activity import above_floor, clean_speech_frames, runs, speech_frames, under_speech

# Frames (100 ms) of the WebRTC-based mask below which a person's short word may be all it missed: Silero's
# detector (trained on people) decides then.
LEAST_SPEECH_FRAMES = 10
MAX_LENGTH_RATIO = 3.0  # recordings this many times longer or shorter than the synthetic speech are refused
CHUNK_LETTERS = 3_000  # about 5 minutes of speech synthesised at a time (split at sentences)
SENTENCE_PAUSE = 0.3  # seconds: a word after a pause this long may start a chunk
PADDING_FRAMES = 50  # silence added around the synthetic speech beyond the recording's own lead and tail
# Recording frequency axis stretched by these (a higher voice needs more): eSpeak's voice is a man's; a
# woman's formants lie 15-20 % higher, a child's more.
VOCAL_TRACT_WARPS = (0.8, 0.84, 0.9, 0.95, 1.0, 1.05, 1.1, 1.16, 1.22, 1.28, 1.34, 1.4)
WARP_SEARCH_FRAMES = 3_000  # the warp is chosen on the first 30 seconds of a long take
# Cost of a DTW step that stretches one signal (in units of the feature distance, 1-3 per frame between
# two voices saying the same thing): keeps the path near the diagonal where the distances do not decide.
STEP_PENALTY = 2.0
PAUSE_COST = 1.0  # per frame of a pause one signal makes and the other does not
BOUNDARY_SLACK = 1  # frames either side of a synthetic word onset where a recorded pause may be held
# A stretch of recorded silence, or of "speech" this close to the noise floor (150 ms), is a pause: a voice
# in the background or a room's tail fills it, and the voice activity detector takes that for speech.
FLOOR_PAUSE_DB = 10.0
FLOOR_PAUSE_FRAMES = 15
# "Speech" this far under the speaker's loud frames for 300 ms may be a pause too (a voice in the
# background in a quiet take), or the speaker's own quiet sounds (a slow voice's "ülm" in a reverberant
# room): holding a word boundary through it costs FAR_UNDER_HOLD_COST a frame, which only a stretch
# that matches nothing of the text is worth. (Person's takes, held-out voices: a hesitation filled so
# was keyed 665 ms early, a comma's pause 178 ms, before this; at PAUSE_COST a reverberant take's
# quiet word start was held as a pause, 323 ms late.)
UNDER_SPEECH_PAUSE_DB = 15.0
UNDER_SPEECH_PAUSE_FRAMES = 30
FAR_UNDER_HOLD_COST = 12.0


@dataclass(frozen=True, eq=False)
class RecordingAlignment:
    """The warp to recorded time, the recording with the warped events, and how well it fits the text."""

    warp: TimeWarp
    synthesis: Synthesis
    phrases: tuple[PhraseMatch, ...]
    warnings: tuple[str, ...]


@dataclass(frozen=True, eq=False)
class _Reference:
    """The synthetic rendition of the whole text: its events (its audio is only analysed, never kept)."""

    phone_events: tuple[PhoneEvent, ...]
    word_events: tuple[WordEvent, ...]


def synthesize_reference(utterance: Utterance, engine: SpeechEngine) -> tuple[_Reference, np.ndarray]:
    """The text spoken chunk by chunk (sentences up to CHUNK_LETTERS letters), only its 16 kHz copy kept."""
    pieces: list[np.ndarray] = []
    phones: list[PhoneEvent] = []
    words: list[WordEvent] = []
    offset = 0.0
    for part, first_word in _chunks(utterance):
        spoken = engine.synthesize(part)
        pieces.append(resample(spoken.samples, spoken.sample_rate, ANALYSIS_RATE, 1 / 32768))
        phones.extend(
            replace(
                event,
                start=event.start + offset,
                end=event.end + offset,
                word_index=event.word_index + first_word,
            )
            for event in spoken.phone_events
        )
        words.extend(
            replace(event, start=event.start + offset, word_index=event.word_index + first_word)
            for event in spoken.word_events
        )
        offset += spoken.duration
    analysis = np.concatenate(pieces) if pieces else np.zeros(0, np.float32)
    return _Reference(tuple(phones), tuple(words)), analysis


def _chunks(utterance: Utterance) -> list[tuple[Utterance, int]]:
    """Pieces of the utterance (each with its first word's index), cut at sentence pauses past CHUNK_LETTERS.

    The pause between two pieces moves to the end of the first, so the voice ends it as a sentence.
    """
    words = utterance.words
    bounds = [0]
    letters = 0
    for index, word in enumerate(words):
        if index and letters >= CHUNK_LETTERS and word.pause_before >= SENTENCE_PAUSE:
            bounds.append(index)
            letters = 0
        letters += word.letter_count
    bounds.append(len(words))
    pieces = []
    for first, stop in zip(bounds[:-1], bounds[1:], strict=True):
        part_words = list(words[first:stop])
        if first:
            part_words[0] = replace(part_words[0], pause_before=0.0)
        final = words[stop].pause_before if stop < len(words) else utterance.final_pause
        pieces.append((replace(utterance, words=tuple(part_words), final_pause=final), first))
    if len(pieces) == 1:
        return [(utterance, 0)]
    return pieces


def align_recording(utterance: Utterance, path: str | Path, engine: SpeechEngine) -> RecordingAlignment:
    """Align the synthetic rendition of the utterance to the user's recording of it; see the module text."""
    path = Path(path)
    native, native_rate = read_audio(path)
    # A telephone-quality recording has nothing above its Nyquist frequency: describe both up to there.
    top_hertz = min(TOP_HERTZ, 0.45 * native_rate)
    # The synthetic rendition is made in a thread of its own while the recording is analysed: eSpeak NG
    # releases the interpreter while it speaks, so on two cores the two overlap.
    with ThreadPoolExecutor(max_workers=1) as pool:
        rendition = pool.submit(_synthetic_analysis, utterance, engine, top_hertz)
        # The user's audio is kept at its own rate (up to 48 kHz) as 16-bit PCM, the float copy dropped.
        output_rate = min(native_rate, MAX_OUTPUT_RATE)
        output = resampled_pcm(native, native_rate, output_rate)
        del native
        recorded = resample(output, output_rate, ANALYSIS_RATE, 1 / 32768)
        recorded_speech = _checked_speech(path, recorded, speech_frames(recorded, frame_count(recorded.size)))
        recorded_loudness = above_floor(recorded, len(recorded_speech))
        recorded_under_speech = under_speech(recorded, len(recorded_speech))
        reference, synthetic_energies, synthetic_speech = rendition.result()
    _check_lengths(path, recorded_speech, synthetic_speech)
    spoken = np.flatnonzero(recorded_speech)
    lead = int(spoken[0]) + PADDING_FRAMES
    tail = len(recorded_speech) - int(spoken[-1]) + PADDING_FRAMES
    synthetic_energies = np.pad(synthetic_energies, ((lead, tail), (0, 0)))
    synthetic_speech = np.pad(synthetic_speech, (lead, tail))
    x, y, order_ratio = _best_warped_features(
        synthetic_energies, synthetic_speech, recorded, recorded_speech, top_hertz
    )
    del recorded
    word_onsets = _word_onsets(reference)
    pauses = _pauses(
        word_onsets, lead, synthetic_speech, recorded_speech, recorded_loudness, recorded_under_speech
    )
    path_x, path_y = dtw_path(x, y, step_penalty=STEP_PENALTY, pauses=pauses)
    recorded_pause = np.isfinite(pauses.y_hold_cost)
    duration = output.size / output_rate
    warp = warp_from_path(
        path_x, path_y, synthetic_speech, recorded_speech, recorded_pause, lead, duration, word_onsets
    )
    synthesis = warp_synthesis(
        Synthesis(output, output_rate, reference.phone_events, reference.word_events, "recording"),
        warp,
        output,
    )
    # What a pause holds (a voice in the background, a room's tail) is not the speaker's: not judged.
    judged = recorded_speech & ~recorded_pause
    ranks = match_ranks(x, y, path_x, path_y, synthetic_speech, judged)
    fit = Fit(path_x, path_y, ranks, synthetic_speech, judged, recorded_under_speech, lead, order_ratio)
    phrases, warnings = judge(utterance, reference.phone_events, warp, fit, path)
    return RecordingAlignment(warp, synthesis, phrases, warnings)


def _synthetic_analysis(
    utterance: Utterance, engine: SpeechEngine, top_hertz: float
) -> tuple[_Reference, np.ndarray, np.ndarray]:
    """The synthetic rendition's events, mel energies and speech frames (its audio dropped)."""
    reference, analysis = synthesize_reference(utterance, engine)
    energies = mel_energies(analysis, top_hertz=top_hertz)
    return reference, energies, clean_speech_frames(analysis, len(energies))


def _word_onsets(reference: _Reference) -> np.ndarray:
    """Synthetic start (seconds) of each word's first phone, in order."""
    firsts: dict[int, float] = {}
    for event in reference.phone_events:
        firsts[event.word_index] = min(event.start, firsts.get(event.word_index, np.inf))
    return np.array(sorted(firsts.values()))


def _pauses(
    word_onsets: np.ndarray,
    lead: int,
    synthetic_speech: np.ndarray,
    recorded_speech: np.ndarray,
    recorded_loudness: np.ndarray,
    recorded_under_speech: np.ndarray,
) -> Pauses:
    """Where the recording may pause though the synthetic speech does not: at any word boundary.

    A person hesitates between words where the text has no comma, and leaves out pauses it has: the
    DTW may hold a synthetic word boundary through a recorded pause, and a synthetic pause against
    any recorded frame, at PAUSE_COST a frame. With a voice in the background or in a live room a
    pause is not silent: a long enough stretch close to the recording's noise floor (which a steady
    background voice is part of), or far under the speaker's own loud frames (a background voice in a
    quiet take, a room's tail), is a pause too.
    """
    box = np.ones(5) / 5
    free = ~synthetic_speech
    boundaries = lead + np.round(word_onsets[1:] * ANALYSIS_RATE / HOP).astype(np.int64)
    for offset in range(-BOUNDARY_SLACK, BOUNDARY_SLACK + 1):
        free[np.clip(boundaries + offset, 0, free.size - 1)] = True
    near_floor = ~recorded_speech | (np.convolve(recorded_loudness, box, "same") < FLOOR_PAUSE_DB)
    # Only the detector's "speech" counts here: a silence joined to the quiet start of the word after it
    # would take that start for a pause.
    far_under = recorded_speech & (np.convolve(recorded_under_speech, box, "same") > UNDER_SPEECH_PAUSE_DB)
    hold = np.full(recorded_speech.size, np.inf)
    for quiet, shortest, cost in (
        (far_under, UNDER_SPEECH_PAUSE_FRAMES, FAR_UNDER_HOLD_COST),
        (near_floor, FLOOR_PAUSE_FRAMES, PAUSE_COST),
    ):
        for start, stop in runs(quiet):
            if stop - start >= shortest:
                hold[start:stop] = cost
    hold[~recorded_speech] = PAUSE_COST
    return Pauses(free, ~synthetic_speech, hold, PAUSE_COST)


def _checked_speech(path: Path, recorded: np.ndarray, speech: np.ndarray) -> np.ndarray:
    """The recording's speech frames; where the WebRTC-based mask holds less than a short word, those of
    the detector trained on people (speech_detector.py), and the take is silent only if it finds none."""
    if np.count_nonzero(speech) >= LEAST_SPEECH_FRAMES:
        return speech
    detection = detect_speech(recorded, speech.size)
    if not detection.found:
        raise AudioError(f"recording {path} is silent (no speech found); record the text again")
    return detection.speech


def _check_lengths(path: Path, recorded_speech: np.ndarray, synthetic_speech: np.ndarray) -> None:
    recorded_frames = np.flatnonzero(recorded_speech)
    synthetic_frames = np.flatnonzero(synthetic_speech)
    if synthetic_frames.size == 0:
        raise AudioError("the synthetic speech is silent, so there is nothing to align the recording to")
    recorded_span = recorded_frames[-1] - recorded_frames[0] + 1
    synthetic_span = synthetic_frames[-1] - synthetic_frames[0] + 1
    ratio = recorded_span / synthetic_span
    if not 1 / MAX_LENGTH_RATIO <= ratio <= MAX_LENGTH_RATIO:
        seconds = HOP / ANALYSIS_RATE
        raise AudioError(
            f"recording {path} has {recorded_span * seconds:.1f} s of speech but the text "
            f"takes about {synthetic_span * seconds:.1f} s to say (more than "
            f"{MAX_LENGTH_RATIO:g} times apart); check that the recording reads exactly this text"
        )


def _best_warped_features(
    synthetic: np.ndarray,
    synthetic_speech: np.ndarray,
    recorded: np.ndarray,
    recorded_speech: np.ndarray,
    top_hertz: float,
) -> tuple[np.ndarray, np.ndarray, float]:
    """Cepstra of both with a common noise floor, the recording's at the vocal-tract warp that fits best.

    The warps are tried on the first 30 seconds at a quarter of the frame rate (its spectra computed
    once); the one whose DTW path is cheapest per step wins (another speaker's formants sit higher or
    lower than eSpeak's). Also returns that cost over the cost of the text's sounds in reverse order:
    near 1 when the recording says something else, whatever the voice.
    """
    synthetic_levels = band_levels(synthetic, synthetic_speech)
    rt60 = estimate_rt60(recorded)
    excerpt = slice(0, WARP_SEARCH_FRAMES)
    power = np.concatenate(
        [block for _, block in power_spectra(recorded[: WARP_SEARCH_FRAMES * HOP + WINDOW])]
    )
    power = power[:WARP_SEARCH_FRAMES]

    def features(energies: np.ndarray, speech: np.ndarray, synthetic_part: np.ndarray, synthetic_part_speech):
        recorded_levels = band_levels(energies, speech)
        floor = common_floor(synthetic_levels, recorded_levels)
        x = cepstra(synthetic_part, synthetic_levels[0], floor, synthetic_part_speech)
        return x, cepstra(energies, recorded_levels[0], floor, speech)

    def cost(index: int) -> float:
        if index not in costs:
            energies = dereverberate(power @ mel_filters(VOCAL_TRACT_WARPS[index], top_hertz).T, rt60)
            tried[index] = features(
                energies,
                recorded_speech[excerpt][: len(energies)],
                synthetic[excerpt],
                synthetic_speech[excerpt],
            )
            costs[index] = _coarse_cost(*tried[index])
        return costs[index]

    costs: dict[int, float] = {}
    tried: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    # The cost is not smooth in the warp (a high voice's harmonics cross the filters): every third
    # warp first, then the neighbours of the best.
    best = min(range(0, len(VOCAL_TRACT_WARPS), 3), key=cost)
    best = min(
        (index for index in (best - 1, best, best + 1) if 0 <= index < len(VOCAL_TRACT_WARPS)), key=cost
    )
    # The same sounds in the wrong order: what the cost would be if the recording said something else.
    excerpt_x, excerpt_y = tried[best]
    order_ratio = costs[best] / _coarse_cost(
        _reversed_speech(excerpt_x, synthetic_speech[excerpt]), excerpt_y
    )
    energies = dereverberate(mel_energies(recorded, VOCAL_TRACT_WARPS[best], top_hertz), rt60)
    x, y = features(energies, recorded_speech, synthetic, synthetic_speech)
    return x, y, order_ratio


def _coarse_cost(x: np.ndarray, y: np.ndarray) -> float:
    """Mean distance per step of the DTW path between the starts of x and y at a quarter frame rate."""
    coarse_x, coarse_y = x[:WARP_SEARCH_FRAMES:4], y[:WARP_SEARCH_FRAMES:4]
    path_x, path_y = dtw_path(coarse_x, coarse_y, step_penalty=STEP_PENALTY)
    return float(np.sqrt(((coarse_x[path_x] - coarse_y[path_y]) ** 2).sum(axis=1)).mean())


def _reversed_speech(x: np.ndarray, speech: np.ndarray) -> np.ndarray:
    """x with its speech frames in reverse order and its silences in place."""
    reversed_x = x.copy()
    frames = np.flatnonzero(speech)
    reversed_x[frames] = x[frames[::-1]]
    return reversed_x
