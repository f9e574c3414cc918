"""A user's own recording of the text: read it, find the text's letters in it, warp the events.

The recording is read, mixed to mono and resampled (audio.py) while the text is synthesised in a thread
of its own, in chunks of sentences, so a take of any length needs only what is heard in it in memory,
not the synthetic audio. Both are heard by the acoustic model (acoustic/: a network trained on people's
speech and eSpeak NG's), frame by frame, as posteriors of the Turkish letters and silence; where the speech
detector hears speech in the recording, silence is made unlikely (voice_activity.py). Whether a recorded
frame matches a sound of the text then no longer depends on how much the voice sounds like eSpeak's.

Two passes. Dynamic time warping (dtw.py) of what is heard in the recording against what is heard in the
synthetic speech, padded by silence (noise, a breath or a click before the first word is matched to
silence), finds the text in the recording as a whole; a person pauses where the text has no comma and
skips pauses it has, so the DTW may hold any word boundary through a recorded pause and any synthetic
pause against the recording (_pauses). Then each letter is placed where the network hears it: forced
alignment of the text's letters, a pause possible between any two words (letter_warp.py; a long take
within reach of the DTW path). The warp joins each letter's synthetic span to its recorded one, so
every phone eSpeak spoke lands where its letter is heard (timewarp.py).

How much less likely the text's letters are than what the network hears gives every word and phrase a
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
from .acoustic.features import recogniser_features, speech_stretch
from .acoustic.labels import CLASS_INDEX, SILENCE
from .acoustic.network import load_network
from .align import phone_letter_spans
from .audio import MAX_OUTPUT_RATE, clipping, read_audio, resample, resampled_pcm
from .base import PhoneEvent, SpeechEngine, Synthesis, WordEvent
from .dtw import Pauses, coarse_dtw_path, dtw_path
from .features import ANALYSIS_RATE, HOP, frame_count
from .judgement import Fit, PhraseMatch, judge
from .letter_warp import letter_warp
from .speech_detector import detect_speech
from .timewarp import TimeWarp, warp_synthesis
from .voice_activity import above_floor, clean_speech_frames, runs, speech_frames, under_speech

# Frames (100 ms) of the WebRTC-based mask below which a person's short word may be all it missed: Silero's
# detector (trained on people) decides then.
LEAST_SPEECH_FRAMES = 10
MAX_LENGTH_RATIO = 4.0  # recordings with this many times more or less speech than the synthetic are refused
LENGTH_SLACK = 3.0  # seconds of speech beyond that ratio a recording may have or lack (syllables drawn out)
CHUNK_LETTERS = 3_000  # about 5 minutes of speech synthesised at a time (split at sentences)
SENTENCE_PAUSE = 0.3  # seconds: a word after a pause this long may start a chunk
PADDING_FRAMES = 50  # silence added around the synthetic speech beyond the recording's own lead and tail
# The DTW's features are the square roots of the posteriors times HEARD_SCALE: two frames heard alike
# are 0 apart, frames heard as different classes 3.5 (2.5 x the Hellinger distance's sqrt(2)). On the tune
# part's lists of eight read with pauses, scales of 1, 2.5 and 4 gave item onsets p90 of 1,343, 224 and
# 179 ms with the DTW alone (its costs below were set for distances of 1-3 a frame).
HEARD_SCALE = 2.5
SILENCE_IN_SPEECH = 0.05  # silence's posterior is this many times smaller where a voice is detected
SPEECH_EDGE_FRAMES = 5  # the letters' alignment trusts the detector's speech this far inside its runs
# Added to silence's score where the letters are placed (acoustic/forced.py): on the tune part's lists of
# eight, with no bias an item the network heard as silence was left out (onsets p90 1,343 ms), at -3
# some still were (p90 82, max 1,752 ms), at -8 none (p90 20 ms).
SPEAKER_SILENCE_BIAS = -8.0
# Where a pause may hold quiet speech (a voice in the background, a room's tail), silence gains this much:
# at 2.0 the network of the fourth round (scripts/train_recogniser.py), hearing a background talker's
# vowel in a hesitation as the next word's, started that word 100 ms early in half of eSpeak NG's
# renditions of the take (tests/core/test_speech_recording_person.py); at 3.0 in none of ten. The tune
# part's lists of eight as before (onsets 10 / 56 / 129 ms); the report part's p90 69 -> 74 ms: a quiet s
# that starts an item is taken for a pause the more (docs/developer/measured/people.md).
QUIET_SILENCE_BIAS = 3.0
# A sound dying away (a room's tail after a word, a vowel's end) keeps no silence bias: from where the level
# falls past FADING_DB under the speaker's loud frames until it rises RISING_DB from the lowest it reached
# (the next sound's onset). The speech detector calls a reverberant room's tail speech, and the bias then
# drew the first letter of the word after a comma's pause into the tail (tuning takes, m5 voice in a 0.4 s
# room: 150-190 ms early). Synthetic held-out takes: reverberant room max 215 -> 97 ms, misplaced 7 -> 5;
# live room 195 -> 182, 5 -> 4 (held-out voices: 209 -> 74, 6 -> 4); people's figures as before but a take.
FADING_DB = 15.0
RISING_DB = 3.0
# A run of the detector's speech starts where the word does, not at the first of its frames the network
# hears as silence (LEADING_SILENCE_SURE or surer) this far under the speaker (LEADING_QUIET_DB): a noise
# gate or an edit opening on the room, a microphone's handling noise or a breath before a voiced onset,
# which WebRTC's detector takes for speech where it rises out of digital silence. On the report part's
# lists of eight read with pauses (French syllables whose clips open on 150-500 ms of room 35 dB under
# the vowel), item onsets 16 / 74 / 271 -> 13 / 47 / 271 ms; the tune part's 10 / 56 / 129 either way
# (at 0.8: max 157); LEADING_QUIET_DB of 20-30 dB gives p90 48-52.
LEADING_SILENCE_SURE = 0.9
LEADING_QUIET_DB = 25.0
ORDER_FRAMES = 3_000  # the text's order is tested on the first 30 seconds of a long take
# Cost of a DTW step that stretches one signal (in units of the feature distance, 0-3.5 a frame): keeps
# the path near the diagonal where the distances do not decide.
STEP_PENALTY = 2.0
PAUSE_COST = 1.0  # per frame of a pause one signal makes and the other does not
BOUNDARY_SLACK = 1  # frames either side of a synthetic word onset where a recorded pause may be held
# A stretch of recorded silence, or of "speech" this close to the noise floor (150 ms), is a pause: a voice
# in the background or a room's tail fills it, and the voice activity detector takes that for speech.
FLOOR_PAUSE_DB = 10.0
FLOOR_PAUSE_FRAMES = 15
# "Speech" this far under the speaker's loud frames for 200 ms may be a pause too (a voice in the
# background in a quiet take), or the speaker's own quiet sounds (a slow voice's "ülm" in a reverberant
# room): holding a word boundary through it costs FAR_UNDER_HOLD_COST a frame, which only a stretch
# that matches nothing of the text is worth. (Person's takes, held-out voices: a hesitation filled so
# was keyed 665 ms early, a comma's pause 178 ms, before this; at PAUSE_COST a reverberant take's
# quiet word start was held as a pause, 323 ms late. With the acoustic model placing the letters, a
# comma's pause of 200-300 ms that a voice in the background or a room's tail fills drew the next word
# into it at 300 ms: tuning takes misplaced, talker 22 -> 8, live room 6 -> 1 of 120 at 200 ms; 150 ms
# put a quiet item of a people's list into a pause, 1.9 s late.)
UNDER_SPEECH_PAUSE_DB = 15.0
UNDER_SPEECH_PAUSE_FRAMES = 20
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
    # The synthetic rendition is made and heard in a thread of its own while the recording is heard:
    # eSpeak NG and numpy's matrix products release the interpreter, so on two cores the two overlap.
    with ThreadPoolExecutor(max_workers=1) as pool:
        rendition = pool.submit(_synthetic_analysis, utterance, engine)
        # The user's audio is kept at its own rate (up to 48 kHz) as 16-bit PCM, the float copy dropped.
        output_rate = min(native_rate, MAX_OUTPUT_RATE)
        output = resampled_pcm(native, native_rate, output_rate)
        clipped = clipping(native)
        del native
        recorded = resample(output, output_rate, ANALYSIS_RATE, 1 / 32768)
        frames = frame_count(recorded.size)
        recorded_speech, recorded_loudness, recorded_under_speech, log_posteriors = _heard_around_speech(
            path, recorded, frames
        )
        recorded_speech = _from_first_sound(recorded_speech, log_posteriors, recorded_under_speech)
        y = heard_features(_speech_not_silence(log_posteriors, recorded_speech))
        del recorded
        reference, x, synthetic_speech = rendition.result()
    _check_lengths(path, recorded_speech, synthetic_speech)
    spoken = np.flatnonzero(recorded_speech)
    lead = int(spoken[0]) + PADDING_FRAMES
    tail = len(recorded_speech) - int(spoken[-1]) + PADDING_FRAMES
    x = np.concatenate((_silence(lead, x.shape[1]), x, _silence(tail, x.shape[1])))
    synthetic_speech = np.pad(synthetic_speech, (lead, tail))
    order_ratio = _order_ratio(x, synthetic_speech, y)
    word_onsets = _word_onsets(reference)
    pauses = _pauses(
        word_onsets, lead, synthetic_speech, recorded_speech, recorded_loudness, recorded_under_speech
    )
    path_x, path_y = coarse_dtw_path(x, y, step_penalty=STEP_PENALTY, pauses=pauses)
    # Silence, or a stretch a voice in the background or a room's tail may fill: the speaker may pause.
    recorded_pause = np.isfinite(pauses.y_hold_cost)
    duration = output.size / output_rate
    synthetic_starts, synthetic_ends, _ = phone_letter_spans(
        utterance,
        Synthesis(output[:0], output_rate, reference.phone_events, reference.word_events, ""),
        engine,
    )
    letters = letter_warp(
        utterance,
        synthetic_starts,
        synthetic_ends,
        log_posteriors,
        _silence_bias(recorded_speech, recorded_pause, recorded_under_speech),
        load_network(),
        path_x,
        path_y,
        lead,
        duration,
    )
    if letters is None:
        raise AudioError(
            f"recording {path} is too short for the text's letters, so it cannot read this text; check that "
            "the recording and the text belong together"
        )
    synthesis = warp_synthesis(
        Synthesis(output, output_rate, reference.phone_events, reference.word_events, "recording"),
        letters.warp,
        output,
    )
    # What a pause holds (a voice in the background, a room's tail) is not the speaker's: not judged.
    judged = recorded_speech & ~recorded_pause
    fit = Fit(
        path_x,
        path_y,
        letters.mismatch,
        letters.heard_letters,
        letters.frame_words,
        synthetic_speech,
        judged,
        recorded_under_speech,
        lead,
        order_ratio,
    )
    phrases, warnings = judge(utterance, reference.phone_events, letters.warp, fit, path, clipped)
    return RecordingAlignment(letters.warp, synthesis, phrases, warnings)


def _heard_around_speech(
    path: Path, recorded: np.ndarray, frames: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The recording's speech frames, dB above its floor, dB under its speech and log posteriors, each
    measured on the stretch around its speech (acoustic.features.speech_stretch); beyond it, silence at
    the floor."""
    speech = _checked_speech(path, recorded, speech_frames(recorded, frames))
    first, stop = speech_stretch(speech)
    if (first, stop) != (0, frames):
        recorded = recorded[first * HOP : stop * HOP if stop < frames else recorded.size]
        speech = _checked_speech(path, recorded, speech_frames(recorded, stop - first))
    around = (first, frames - stop)
    under = under_speech(recorded, stop - first)
    return (
        np.pad(speech, around),
        np.pad(above_floor(recorded, stop - first), around),
        np.pad(under, around, constant_values=under.max()),
        _silence_around(heard_log_posteriors(recorded, stop - first), *around),
    )


def heard_log_posteriors(samples: np.ndarray, frames: int) -> np.ndarray:
    """What the acoustic model hears in each of `frames` 10 ms frames of 16 kHz samples: the log of its
    class posteriors (frames x classes, float32). The square roots of the posteriors are the DTW's
    features: the Euclidean distance between two frames is then the Hellinger distance between what is
    heard in them."""
    heard = load_network().log_posteriors(recogniser_features(samples))
    return _silence_around(heard[:frames], 0, max(0, frames - len(heard)))


def _silence_around(log_posteriors: np.ndarray, before: int, after: int) -> np.ndarray:
    """The log posteriors with `before` and `after` frames in which only silence is heard around them."""
    heard = np.pad(log_posteriors, ((before, after), (0, 0)), constant_values=-69.0)
    heard[:before, CLASS_INDEX[SILENCE]] = 0.0
    heard[len(heard) - after :, CLASS_INDEX[SILENCE]] = 0.0
    return heard


def _silence_bias(
    recorded_speech: np.ndarray, recorded_pause: np.ndarray, recorded_under_speech: np.ndarray
) -> np.ndarray:
    """What the speech detector adds to silence's score in each recorded frame, for placing the letters:
    SPEAKER_SILENCE_BIAS well inside the speaker's speech but where a sound dies away, QUIET_SILENCE_BIAS
    where speech so quiet or so near the noise floor that a pause may hold it (a voice in the background,
    a room's tail)."""
    bias = np.where(recorded_speech & recorded_pause, QUIET_SILENCE_BIAS, 0.0)
    speaking = _inner(recorded_speech & ~recorded_pause, SPEECH_EDGE_FRAMES)
    bias[speaking & ~fading(recorded_under_speech)] = SPEAKER_SILENCE_BIAS
    return bias


def fading(under_speech_db: np.ndarray) -> np.ndarray:
    """The frames of a sound dying away (see FADING_DB), given how far each lies under the loud frames."""
    level = -np.asarray(under_speech_db, np.float64)
    below = level <= -FADING_DB
    found = np.zeros(level.size, bool)
    starts = np.flatnonzero(below[1:] & ~below[:-1]) + 1  # the level falls past FADING_DB here
    for start, end in zip(starts, np.append(starts[1:], level.size), strict=False):
        after = level[start:end]  # a fade ends before the level can fall past FADING_DB again
        rising = (after >= np.minimum.accumulate(after) + RISING_DB) | ~below[start:end]
        found[start : start + (int(np.argmax(rising)) if rising.any() else after.size)] = True
    return found


def _from_first_sound(
    speech: np.ndarray, log_posteriors: np.ndarray, under_speech_db: np.ndarray
) -> np.ndarray:
    """The speech frames with each run's leading frames of room dropped (see LEADING_SILENCE_SURE); a run
    that is room throughout is left whole: whether it is speech is the detector's call."""
    room = (log_posteriors[:, CLASS_INDEX[SILENCE]] >= np.log(LEADING_SILENCE_SURE)) & (
        under_speech_db >= LEADING_QUIET_DB
    )
    trimmed = speech.copy()
    for start, stop in runs(speech):
        leading = room[start:stop]
        if not leading.all():
            trimmed[start : start + int(np.argmin(leading))] = False
    return trimmed


def _inner(speech: np.ndarray, edge: int) -> np.ndarray:
    """The speech frames at least `edge` frames inside their run: the detector's runs reach into the
    silence around them (and bridge a stop's closure), where a pause may well lie."""
    inner = speech.copy()
    for shift in range(1, edge + 1):
        inner[shift:] &= speech[:-shift]
        inner[:-shift] &= speech[shift:]
    return inner


def _speech_not_silence(log_posteriors: np.ndarray, speech: np.ndarray) -> np.ndarray:
    """The posteriors with silence made SILENCE_IN_SPEECH times less likely where the speech detector
    hears speech: the network, unsure of a voice unlike any it learnt from, hears silence sooner than
    a wrong letter, and the DTW would then hold the text's pauses against the speaker's words."""
    adjusted = log_posteriors.copy()
    adjusted[speech, CLASS_INDEX[SILENCE]] += np.log(SILENCE_IN_SPEECH)
    adjusted -= np.log(np.exp(adjusted).sum(axis=1, keepdims=True))
    return adjusted


def heard_features(log_posteriors: np.ndarray) -> np.ndarray:
    """The DTW's features: the square roots of the posteriors, scaled by HEARD_SCALE."""
    return (HEARD_SCALE * np.sqrt(np.exp(log_posteriors))).astype(np.float32)


def _silence(frames: int, classes: int) -> np.ndarray:
    """Features of frames in which nothing but silence is heard."""
    heard = np.zeros((frames, classes), np.float32)
    heard[:, CLASS_INDEX[SILENCE]] = HEARD_SCALE
    return heard


def _synthetic_analysis(
    utterance: Utterance, engine: SpeechEngine
) -> tuple[_Reference, np.ndarray, np.ndarray]:
    """The synthetic rendition's events, what is heard in it and its speech frames (its audio dropped)."""
    reference, analysis = synthesize_reference(utterance, engine)
    frames = frame_count(analysis.size)
    heard = heard_features(heard_log_posteriors(analysis, frames))
    return reference, heard, clean_speech_frames(analysis, frames)


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
    # Speech, not span: a list read with long pauses has no more speech than the text. A short text may
    # be said far slower than eSpeak says it (a word alone, drawn out), so the ratio has a slack.
    recorded_seconds = recorded_frames.size * HOP / ANALYSIS_RATE
    synthetic_seconds = synthetic_frames.size * HOP / ANALYSIS_RATE
    if not (
        synthetic_seconds / MAX_LENGTH_RATIO - LENGTH_SLACK
        <= recorded_seconds
        <= synthetic_seconds * MAX_LENGTH_RATIO + LENGTH_SLACK
    ):
        raise AudioError(
            f"recording {path} has {recorded_seconds:.1f} s of speech but the text takes about "
            f"{synthetic_seconds:.1f} s to say (more than {MAX_LENGTH_RATIO:g} times apart); check that the "
            "recording reads exactly this text"
        )


def _order_ratio(x: np.ndarray, synthetic_speech: np.ndarray, y: np.ndarray) -> float:
    """The DTW cost of the first 30 seconds over the cost with the text's sounds in reverse order: near 1
    when the recording says something else, whatever the voice."""
    excerpt = slice(0, ORDER_FRAMES)
    return _coarse_cost(x[excerpt], y[excerpt]) / _coarse_cost(
        _reversed_speech(x[excerpt], synthetic_speech[excerpt]), y[excerpt]
    )


def _coarse_cost(x: np.ndarray, y: np.ndarray) -> float:
    """Mean distance per step of the DTW path between the starts of x and y at a quarter frame rate."""
    coarse_x, coarse_y = x[::4], y[::4]
    path_x, path_y = dtw_path(coarse_x, coarse_y, step_penalty=STEP_PENALTY)
    return float(np.sqrt(((coarse_x[path_x] - coarse_y[path_y]) ** 2).sum(axis=1)).mean())


def _reversed_speech(x: np.ndarray, speech: np.ndarray) -> np.ndarray:
    """x with its speech frames in reverse order and its silences in place."""
    reversed_x = x.copy()
    frames = np.flatnonzero(speech)
    reversed_x[frames] = x[frames[::-1]]
    return reversed_x
