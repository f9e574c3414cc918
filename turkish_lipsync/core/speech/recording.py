"""A user's own recording of the text: read it, align the synthetic rendition to it, warp the events.

The recording is read (WAV through the stdlib, FLAC/OGG and float WAV through soundfile), mixed to
mono and resampled (soxr). The text is synthesised in chunks of sentences, so a take of any length
needs only its features in memory, not the synthetic audio. Both signals become speaker- and
room-normalised cepstra (features.py), the recording's speech is found by voice activity detection
(voice_activity.py), and the two are matched by dynamic time warping (dtw.py) with the synthetic
speech padded by silence, so noise, a breath or a click before the first word is matched to silence
instead of being taken for speech. The recording's vocal tract length is searched over a few warps.
Only matches of speech with speech become knots of the warp; pauses are crossed linearly.

How far each synthetic word lies from what the recording says there gives every word and phrase a
confidence: a recording of other words is refused, a word left out or added is named in a warning.
"""

from __future__ import annotations

import struct
import wave
from collections.abc import Iterator
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..base.errors import AudioError
from ..base.model import Utterance
from .base import PhoneEvent, SpeechEngine, Synthesis, WordEvent
from .dtw import dtw_path
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
)
from .voice_activity import runs, speech_frames

MAX_LENGTH_RATIO = 3.0  # recordings this many times longer or shorter than the synthetic speech are refused
CHUNK_LETTERS = 3_000  # about 5 minutes of speech synthesised at a time (split at sentences)
SENTENCE_PAUSE = 0.3  # seconds: a word after a pause this long may start a chunk
PADDING_FRAMES = 50  # silence added around the synthetic speech beyond the recording's own lead and tail
VOCAL_TRACT_WARPS = (0.84, 0.9, 0.95, 1.0, 1.05, 1.1, 1.16)
WARP_SEARCH_FRAMES = 6_000  # the warp is chosen on the first minute of a long take
# Cost of a DTW step that stretches one signal (in units of the feature distance, 1-3 per frame between
# two voices saying the same thing): keeps the path near the diagonal where the distances do not decide.
STEP_PENALTY = 2.0


@dataclass(frozen=True, eq=False)
class TimeWarp:
    """Synthetic time (seconds) to recording time: piecewise linear through matched frame times."""

    synthetic: np.ndarray  # increasing knot times in the synthetic speech
    recorded: np.ndarray  # non-decreasing knot times in the recording
    recording_duration: float

    def __call__(self, times: np.ndarray | float) -> np.ndarray:
        times = np.asarray(times, dtype=np.float64)
        warped = np.interp(times, self.synthetic, self.recorded)
        # Outside the speech the two signals run at the same speed (silence before and after).
        before = times < self.synthetic[0]
        after = times > self.synthetic[-1]
        warped = np.where(before, self.recorded[0] - (self.synthetic[0] - times), warped)
        warped = np.where(after, self.recorded[-1] + (times - self.synthetic[-1]), warped)
        return np.clip(warped, 0.0, self.recording_duration)


MAX_OUTPUT_RATE = 48_000  # the recording's own rate is kept up to this
READ_BLOCK_FRAMES = 1 << 20  # frames read and mixed to mono at a time: a long take is never held in stereo


def read_audio(path: str | Path) -> tuple[np.ndarray, int]:
    """Mono float32 samples in [-1, 1] and the sample rate of a WAV, FLAC or OGG file (read in blocks)."""
    path = Path(path)
    if not path.is_file():
        raise AudioError(f"recording {path} does not exist; give the path of a WAV, FLAC or OGG file")
    mono, rate = None, 0
    if path.suffix.lower() == ".wav":
        try:
            mono, rate = _read_pcm_wav(path)
        except (wave.Error, EOFError, ValueError, RuntimeError, struct.error):
            mono = None  # not plain PCM (float, extensible, ...) or damaged: soundfile may still read it
        except OSError as error:
            raise AudioError(
                f"cannot open the recording {path} ({error}); check the file's permissions"
            ) from None
    if mono is None:
        mono, rate = _read_with_soundfile(path)
    if mono.size == 0 or rate <= 0:
        raise AudioError(f"recording {path} holds no audio; record the text again")
    if not np.isfinite(mono).all():
        raise AudioError(
            f"recording {path} contains invalid samples (NaN or infinite); export it again as WAV"
        )
    return mono, rate


def _read_pcm_wav(path: Path) -> tuple[np.ndarray, int]:
    with wave.open(str(path), "rb") as handle:
        channels, width, rate = handle.getnchannels(), handle.getsampwidth(), handle.getframerate()
        if width not in (1, 2, 3, 4):
            raise ValueError(f"unsupported sample width {width}")
        mono = np.empty(handle.getnframes(), np.float32)
        filled = 0
        while filled < mono.size:
            data = handle.readframes(READ_BLOCK_FRAMES)
            frames = len(data) // (width * channels)
            if frames == 0:
                break
            samples = _pcm_to_float(data[: frames * width * channels], width).reshape(frames, channels)
            mono[filled : filled + frames] = samples.mean(axis=1)
            filled += frames
    return mono[:filled], rate


def _pcm_to_float(data: bytes, width: int) -> np.ndarray:
    if width == 1:
        return (np.frombuffer(data, np.uint8).astype(np.float32) - 128) / 128
    if width == 2:
        return np.frombuffer(data, "<i2").astype(np.float32) / 32768
    if width == 3:
        raw = np.frombuffer(data, np.uint8).reshape(-1, 3).astype(np.int32)
        value = raw[:, 0] | (raw[:, 1] << 8) | (raw[:, 2] << 16)
        return (np.where(value >= 1 << 23, value - (1 << 24), value) / float(1 << 23)).astype(np.float32)
    return (np.frombuffer(data, "<i4") / float(1 << 31)).astype(np.float32)


def _read_with_soundfile(path: Path) -> tuple[np.ndarray, int]:
    try:
        import soundfile
    except ImportError:
        raise AudioError(
            f"cannot read {path}: FLAC, OGG and float WAV need the Python package soundfile "
            "(`pip install soundfile`); or export the recording as 16-bit PCM WAV"
        ) from None
    try:
        with soundfile.SoundFile(str(path)) as handle:
            blocks = [
                block.mean(axis=1, dtype=np.float32)
                for block in handle.blocks(READ_BLOCK_FRAMES, dtype="float32", always_2d=True)
            ]
            rate = handle.samplerate
    except Exception as error:  # soundfile raises its own error types, varying by version
        raise AudioError(
            f"cannot read the recording {path} ({error}); export it as a WAV, FLAC or OGG file"
        ) from None
    return (np.concatenate(blocks) if blocks else np.zeros(0, np.float32)), int(rate)


@dataclass(frozen=True)
class PhraseMatch:
    """A phrase of the text (words between pauses) as found in the recording, with how sure the match is."""

    first_word: int
    word_count: int
    start: float  # seconds in the recording
    end: float
    confidence: float  # 0 (the recording says something else here) .. 1 (a close match)


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
    # The user's audio is kept at its own rate (up to 48 kHz) as 16-bit PCM, the float copy dropped at once.
    output_rate = min(native_rate, MAX_OUTPUT_RATE)
    output = resampled_pcm(native, native_rate, output_rate)
    del native
    recorded = resample(output, output_rate, ANALYSIS_RATE, 1 / 32768)
    # A telephone-quality recording has nothing above its Nyquist frequency: describe both up to there.
    top_hertz = min(TOP_HERTZ, 0.45 * native_rate)
    recorded_speech = speech_frames(recorded, frame_count(recorded.size))
    reference, analysis = synthesize_reference(utterance, engine)
    synthetic_energies = mel_energies(analysis, top_hertz=top_hertz)
    synthetic_speech = speech_frames(analysis, len(synthetic_energies))
    del analysis
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
    path_x, path_y = dtw_path(x, y, step_penalty=STEP_PENALTY)
    distances = np.sqrt(((x[path_x] - y[path_y]) ** 2).sum(axis=1))
    warp = _warp_from_path(path_x, path_y, synthetic_speech, recorded_speech, lead, output.size / output_rate)
    synthesis = warp_synthesis(
        Synthesis(output, output_rate, reference.phone_events, reference.word_events, "recording"),
        warp,
        output,
    )
    fit = _Fit(
        path_x,
        path_y,
        distances,
        synthetic_speech,
        recorded_speech,
        lead,
        order_ratio,
    )
    phrases, warnings = _judge(utterance, reference, warp, fit, path)
    return RecordingAlignment(warp, synthesis, phrases, warnings)


def resampled_pcm(samples: np.ndarray, source_rate: int, target_rate: int) -> np.ndarray:
    """16-bit PCM at the target rate, made block by block (a long take has no float copy to spare)."""
    return np.concatenate(
        [
            np.clip(np.round(block * 32767), -32768, 32767).astype(np.int16)
            for block in _resampled_blocks(samples, source_rate, target_rate)
        ]
        or [np.zeros(0, np.int16)]
    )


def resample(samples: np.ndarray, source_rate: int, target_rate: int, scale: float = 1.0) -> np.ndarray:
    """float32 samples (times scale) at the target rate: soxr's band-limited resampling, block by block."""
    blocks = list(_resampled_blocks(samples, source_rate, target_rate, scale))
    return np.concatenate(blocks) if blocks else np.zeros(0, np.float32)


def _resampled_blocks(
    samples: np.ndarray, source_rate: int, target_rate: int, scale: float = 1.0
) -> Iterator[np.ndarray]:
    """float32 blocks of the samples (times scale) resampled by one soxr stream."""
    import soxr

    stream = (
        soxr.ResampleStream(source_rate, target_rate, 1, dtype="float32")
        if source_rate != target_rate
        else None
    )
    for begin in range(0, samples.size, READ_BLOCK_FRAMES):
        block = samples[begin : begin + READ_BLOCK_FRAMES].astype(np.float32) * np.float32(scale)
        if stream is None:
            yield block
        else:
            yield stream.resample_chunk(block, last=begin + READ_BLOCK_FRAMES >= samples.size)


def _check_lengths(path: Path, recorded_speech: np.ndarray, synthetic_speech: np.ndarray) -> None:
    recorded_frames = np.flatnonzero(recorded_speech)
    synthetic_frames = np.flatnonzero(synthetic_speech)
    if recorded_frames.size < 10:
        raise AudioError(f"recording {path} is silent (no speech found); record the text again")
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

    Each warp is tried on the first minute at a quarter of the frame rate; the one whose DTW path is
    cheapest per step wins (another speaker's formants sit higher or lower than eSpeak's). Also returns
    that cost over the cost of the text's sounds in reverse order: near 1 when the recording says
    something else, whatever the voice.
    """
    synthetic_levels = band_levels(synthetic, synthetic_speech)
    best = None
    for warp in VOCAL_TRACT_WARPS:
        energies = mel_energies(recorded, warp, top_hertz)
        recorded_levels = band_levels(energies, recorded_speech)
        floor = common_floor(synthetic_levels, recorded_levels)
        x = cepstra(synthetic, synthetic_levels[0], floor, synthetic_speech)
        y = cepstra(energies, recorded_levels[0], floor, recorded_speech)
        cost = _coarse_cost(x, y)
        if best is None or cost < best[0]:
            best = (cost, x, y)
    cost, x, y = best
    # The same sounds in the wrong order: what the cost would be if the recording said something else.
    return x, y, cost / _coarse_cost(_reversed_speech(x, synthetic_speech), y)


def _coarse_cost(x: np.ndarray, y: np.ndarray) -> float:
    """Mean distance per step of the DTW path between the first minutes of x and y at a quarter frame rate."""
    coarse_x, coarse_y = x[:WARP_SEARCH_FRAMES:4], y[:WARP_SEARCH_FRAMES:4]
    path_x, path_y = dtw_path(coarse_x, coarse_y, step_penalty=STEP_PENALTY)
    return float(np.sqrt(((coarse_x[path_x] - coarse_y[path_y]) ** 2).sum(axis=1)).mean())


def _reversed_speech(x: np.ndarray, speech: np.ndarray) -> np.ndarray:
    """x with its speech frames in reverse order and its silences in place."""
    reversed_x = x.copy()
    frames = np.flatnonzero(speech)
    reversed_x[frames] = x[frames[::-1]]
    return reversed_x


def _frame_seconds(frames: np.ndarray | float, lead: int = 0) -> np.ndarray:
    """Centre time (seconds) of analysis frames, `lead` padding frames before time zero."""
    return ((np.asarray(frames, dtype=np.float64) - lead) * HOP + WINDOW / 2) / ANALYSIS_RATE


def _warp_from_path(
    path_x: np.ndarray,
    path_y: np.ndarray,
    synthetic_speech: np.ndarray,
    recorded_speech: np.ndarray,
    lead: int,
    recording_duration: float,
) -> TimeWarp:
    """Knots where speech meets speech, each synthetic frame at the mean recording frame matched to it.

    Silence matches silence at no cost, so the path through a pause is arbitrary: pauses are crossed
    linearly between the last and first words around them.
    """
    both = synthetic_speech[path_x] & recorded_speech[path_y]
    if both.sum() < 2:
        both[:] = True
    frames = len(synthetic_speech)
    weights = np.bincount(path_x[both], minlength=frames)
    knots = np.flatnonzero(weights)
    matched = np.bincount(path_x[both], weights=path_y[both], minlength=frames)[knots] / weights[knots]
    knots = np.concatenate(([path_x[0]], knots, [path_x[-1]]))
    matched = np.maximum.accumulate(np.concatenate(([path_y[0]], matched, [path_y[-1]])))
    unique = np.concatenate(([True], np.diff(knots) > 0))
    return TimeWarp(
        synthetic=_frame_seconds(knots[unique], lead),
        recorded=_frame_seconds(matched[unique]),
        recording_duration=recording_duration,
    )


@dataclass(frozen=True, eq=False)
class _Fit:
    """The DTW path and the feature distance along it, for judging how well the recording says the text."""

    path_x: np.ndarray
    path_y: np.ndarray
    distances: np.ndarray
    synthetic_speech: np.ndarray
    recorded_speech: np.ndarray
    lead: int
    order_ratio: float  # the path's cost over the cost with the text's sounds in reverse order


# Mean feature distance (normalised cepstra and slopes) along the path. Measured with scripts/
# measure_recordings.py on the tuning sentences: the same text in other voices, noise and codecs 1.1-2.9 per
# sentence, in a reverberant room 3.1-3.9, another text 4.1-4.8; the path's cost over that of the text's
# sounds reversed 0.5-0.81 for the same text, 0.85-1.0 for another. A voice further from eSpeak's raises
# every word's distance, so words are judged against the recording's own median word too.
MATCHED_DISTANCE = 1.5  # a phrase this close has confidence 1
UNMATCHED_DISTANCE = 4.0  # ... and this far, 0
# The whole recording this far off, and its order no better than this: it reads another text.
OTHER_TEXT_DISTANCE = 3.95
OTHER_TEXT_ORDER_RATIO = 0.83
# Either beyond these (above all the same text's clean or noisy takes, below the reverberant ones): a warning.
DOUBTFUL_DISTANCE = 3.4
DOUBTFUL_ORDER_RATIO = 0.78
UNMATCHED_WORD_DISTANCE = 4.4  # one word this far off, and
UNMATCHED_WORD_RATIO = 1.7  # this many times the median word's distance, is not in the recording
SQUEEZED = 0.25  # a word given less than this share of the recording's pace is missing
# A word stretched this much beyond the recording's pace, and matched loosely, has company: words the text
# does not have were said next to it (a speaker's own lengthening of a word matches closely).
STRETCHED = 1.7
STRETCHED_DISTANCE = 3.6
STRETCHED_WORD_RATIO = 1.4
EXTRA_SPEECH_FRAMES = 35  # a stretch of recorded speech this long (350 ms) matched to no synthetic speech
MOST_WARNINGS = 10  # a take with more places of doubt gets the first ones and a count of the rest
OTHER_TEXT_SHARE = 0.5  # more than this share of the words unmatched: the recording reads another text


def _word_frames(utterance: Utterance, reference: _Reference, lead: int) -> np.ndarray:
    """Each word's first and last synthetic frame (padded indices); -1 for a word the engine did not voice."""
    spans = np.full((len(utterance.words), 2), -1, np.int64)
    for event in reference.phone_events:
        first = lead + int(event.start * ANALYSIS_RATE / HOP)
        last = lead + int(np.ceil(event.end * ANALYSIS_RATE / HOP))
        span = spans[event.word_index]
        span[0] = first if span[0] < 0 else min(span[0], first)
        span[1] = max(span[1], last)
    return spans


def _judge(
    utterance: Utterance, reference: _Reference, warp: TimeWarp, fit: _Fit, path: Path
) -> tuple[tuple[PhraseMatch, ...], tuple[str, ...]]:
    """A confidence per phrase; warnings naming the words where recording and text part."""
    frames = len(fit.synthetic_speech)
    spoken = fit.synthetic_speech[fit.path_x]
    per_frame_count = np.bincount(fit.path_x[spoken], minlength=frames)
    per_frame_sum = np.bincount(fit.path_x[spoken], weights=fit.distances[spoken], minlength=frames)
    spans = _word_frames(utterance, reference, fit.lead)
    word_distance = np.full(len(utterance.words), np.nan)
    pace = np.full(len(utterance.words), np.nan)  # recorded length / synthetic length
    for index, (first, last) in enumerate(spans):
        if first < 0:
            continue
        count = per_frame_count[first : last + 1].sum()
        word_distance[index] = per_frame_sum[first : last + 1].sum() / count if count else UNMATCHED_DISTANCE
        synthetic = _frame_seconds(np.array([first, last]), fit.lead)
        recorded = warp(synthetic)
        pace[index] = (recorded[1] - recorded[0]) / max(synthetic[1] - synthetic[0], 1e-3)
    pace /= np.nanmedian(pace)
    typical = np.nanmedian(word_distance)
    unmatched = (word_distance > max(UNMATCHED_WORD_DISTANCE, UNMATCHED_WORD_RATIO * typical)) | (
        pace < SQUEEZED
    )
    loose = word_distance > max(STRETCHED_DISTANCE, STRETCHED_WORD_RATIO * typical)
    crowded = (pace > STRETCHED) & loose & ~unmatched
    phrases = _phrases(utterance, warp, spans, fit, word_distance, per_frame_count, per_frame_sum)
    texts = [word.text for word in utterance.words]
    distance = float(fit.distances[spoken].mean())
    if fit.order_ratio > OTHER_TEXT_ORDER_RATIO and (
        distance > OTHER_TEXT_DISTANCE or unmatched.mean() > OTHER_TEXT_SHARE
    ):
        unheard = np.flatnonzero(unmatched | (word_distance > OTHER_TEXT_DISTANCE))
        raise AudioError(
            f"recording {path} does not read this text: {_word_list(texts, unheard)} "
            f"({unheard.size} of its {len(texts)} words) are not heard in it; check that the recording "
            "and the text belong together"
        )
    warnings = [
        "the recording fits this text only loosely (it may read another text, or be very noisy or "
        "reverberant); check that it reads this text: the face follows it as well as it can"
    ] * (fit.order_ratio > DOUBTFUL_ORDER_RATIO or distance > DOUBTFUL_DISTANCE)
    warnings += [
        f"the recording seems not to say {_word_list(texts, run)} (word {run[0] + 1} of the text); "
        "check the recording there: the face is timed on the rest"
        for run in _consecutive(np.flatnonzero(unmatched))
    ]
    stalls = _stalls(fit, spans)
    for before, after, seconds in stalls:
        warnings.append(
            f"the recording says something the text does not between {texts[before]!r} and "
            f"{texts[after]!r} (at {seconds:.1f} s); the face keeps to the text's words there"
        )
    named = {index for before, after, _ in stalls for index in (before, after)}
    warnings.extend(
        f"the recording says something the text does not around {texts[index]!r} (word {index + 1} of the "
        f"text, at {float(warp(_frame_seconds(spans[index, 0], fit.lead))):.1f} s); the face keeps to the "
        "text's words there"
        for index in np.flatnonzero(crowded)
        if index not in named
    )
    if len(warnings) > MOST_WARNINGS:
        more = len(warnings) - MOST_WARNINGS + 1
        warnings[MOST_WARNINGS - 1 :] = [f"and {more} more places where the recording and the text part"]
    return phrases, tuple(warnings)


def _phrases(
    utterance: Utterance,
    warp: TimeWarp,
    spans: np.ndarray,
    fit: _Fit,
    word_distance: np.ndarray,
    per_frame_count: np.ndarray,
    per_frame_sum: np.ndarray,
) -> tuple[PhraseMatch, ...]:
    """Words between pauses, each phrase with its place in the recording and its confidence."""
    starts = [index for index, word in enumerate(utterance.words) if index == 0 or word.pause_before > 0]
    phrases = []
    for first, stop in zip(starts, [*starts[1:], len(utterance.words)], strict=True):
        voiced = [index for index in range(first, stop) if spans[index, 0] >= 0]
        if not voiced:
            continue
        begin, end = spans[voiced[0], 0], spans[voiced[-1], 1]
        count = per_frame_count[begin : end + 1].sum()
        distance = per_frame_sum[begin : end + 1].sum() / count if count else UNMATCHED_DISTANCE
        confidence = (UNMATCHED_DISTANCE - distance) / (UNMATCHED_DISTANCE - MATCHED_DISTANCE)
        recorded = warp(_frame_seconds(np.array([begin, end]), fit.lead))
        phrases.append(
            PhraseMatch(
                first, stop - first, float(recorded[0]), float(recorded[1]), float(np.clip(confidence, 0, 1))
            )
        )
    return tuple(phrases)


def _stalls(fit: _Fit, spans: np.ndarray) -> list[tuple[int, int, float]]:
    """Recorded speech the synthetic speech does not advance through, between two words of the text.

    Each as (word before, word after, seconds into the recording). Before the first word or after the
    last, a breath or a noise is as likely as a word, so those are left alone.
    """
    recorded_frames = len(fit.recorded_speech)
    window = EXTRA_SPEECH_FRAMES
    if recorded_frames <= window:
        return []
    matched = np.zeros(recorded_frames, np.int64)
    matched[fit.path_y] = fit.path_x  # the path is monotone: the last synthetic frame matched to each
    progress = np.cumsum(fit.synthetic_speech)[matched]  # synthetic speech frames passed
    speech_share = np.convolve(fit.recorded_speech, np.ones(window), "valid")[:-1] / window
    advance = progress[window:] - progress[:-window]
    stalled = (advance <= window // 8) & (speech_share >= 0.8)
    firsts = spans[:, 0]
    found = []
    for start, _ in runs(stalled):
        at = matched[start + window // 2]
        before = np.flatnonzero((firsts >= 0) & (firsts <= at))
        after = np.flatnonzero(firsts > at)
        if before.size and after.size:
            found.append((int(before[-1]), int(after[0]), float(_frame_seconds(start + window // 2))))
    return found


def _consecutive(indices: np.ndarray) -> list[np.ndarray]:
    if indices.size == 0:
        return []
    return np.split(indices, np.flatnonzero(np.diff(indices) > 1) + 1)


def _word_list(texts: list[str], indices: np.ndarray, shown: int = 6) -> str:
    names = [repr(texts[index]) for index in indices[:shown]]
    more = f" and {indices.size - shown} more" if indices.size > shown else ""
    return ", ".join(names) + more


def warp_synthesis(synthesis: Synthesis, warp: TimeWarp, samples: np.ndarray) -> Synthesis:
    """The synthesis's events moved onto the recording's time, holding the recording's samples."""
    phones = synthesis.phone_events
    starts = warp(np.array([event.start for event in phones]))
    ends = warp(np.array([event.end for event in phones]))
    words = synthesis.word_events
    word_starts = warp(np.array([event.start for event in words]))
    return Synthesis(
        samples=samples,
        sample_rate=synthesis.sample_rate,
        phone_events=tuple(
            replace(event, start=float(start), end=float(end))
            for event, start, end in zip(phones, starts, ends, strict=True)
        ),
        word_events=tuple(
            replace(event, start=float(start)) for event, start in zip(words, word_starts, strict=True)
        ),
        engine="recording",
    )
