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
(judgement.py). A take so judged is heard again by a second network that learnt many people's voices
(align_recording), and the hearing with fewer warnings kept. The second hearing starts from what the first
measured before its network heard anything (Listening, fit_again): the text is spoken and the take read
once.
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, replace
from pathlib import Path
from threading import Event

import numpy as np

from ..base.errors import AudioError
from ..base.model import Hesitation, Utterance
from ..text.utterance import read_aloud
from .acoustic.features import frames_of, recogniser_features, sounding_frames, speech_stretch
from .acoustic.labels import CLASS_INDEX, SILENCE
from .acoustic.network import PEOPLE_WEIGHTS_FILE, PhoneNetwork, load_network
from .align import phone_letter_spans
from .aligner_settings import DEFAULT_ALIGNER, AlignerSettings
from .audio import MAX_OUTPUT_RATE, clipping, read_audio, resample, resampled_pcm
from .base import PhoneEvent, SpeechEngine, Synthesis, WordEvent
from .dtw import Pauses, coarse_dtw_path, dtw_path
from .features import ANALYSIS_RATE, HOP, frame_count
from .judgement import Fit, PhraseMatch, judge, pauses_read_as_list
from .letter_warp import LetterFit, letter_warp, spoken_hesitations
from .speech_detector import detect_speech
from .timewarp import TimeWarp, warp_synthesis
from .voice_activity import (
    above_floor,
    clean_speech_frames,
    long_runs,
    runs,
    speech_frames,
    under_speech,
)


@dataclass(frozen=True, eq=False)
class RecordingAlignment:
    """The warp to recorded time, the recording with the warped events, how well it fits the text, and the
    hesitations said aloud in its pauses."""

    warp: TimeWarp
    synthesis: Synthesis
    phrases: tuple[PhraseMatch, ...]
    warnings: tuple[str, ...]
    hesitations: tuple[Hesitation, ...]


@dataclass(frozen=True, eq=False)
class RecordingFit:
    """A take aligned to its text, not yet judged: the synthetic phones, the warp to recorded time, the
    recording with the warped events, how its frames fit the text, its name and its clipping."""

    phone_events: tuple[PhoneEvent, ...]
    warp: TimeWarp
    synthesis: Synthesis
    fit: Fit
    name: str
    clipped: str


@dataclass(frozen=True, eq=False)
class _Reference:
    """The synthetic rendition of the whole text: its events (its audio is only analysed, never kept)."""

    phone_events: tuple[PhoneEvent, ...]
    word_events: tuple[WordEvent, ...]


@dataclass(frozen=True, eq=False)
class _Rendition:
    """The synthetic rendition as the alignment needs it before a network hears it: its events, its sound
    per analysis frame (the acoustic model's input features), its speech frames, and each letter's
    synthetic start and end (seconds)."""

    reference: _Reference
    sound: np.ndarray
    speech: np.ndarray
    letter_starts: np.ndarray
    letter_ends: np.ndarray


@dataclass(frozen=True, eq=False)
class RecordedAudio:
    """A recording already in memory: mono float samples in [-1, 1], their rate, and the name messages
    give it (its file, or a line of a scene's recording)."""

    samples: np.ndarray
    sample_rate: int
    name: str


@dataclass(frozen=True, eq=False)
class _Take:
    """The user's audio (kept at its own rate up to 48 kHz as 16-bit PCM) and what is measured in it
    before a network hears it, per analysis frame: its speech, levels, and the acoustic model's input
    features on the stretch around its speech (acoustic.features.speech_stretch)."""

    name: str  # what messages call the recording
    output: np.ndarray
    output_rate: int
    clipped: str
    speech: np.ndarray  # the speech detector's
    loudness: np.ndarray  # dB above the floor
    under_speech: np.ndarray  # dB under the speaker's loud frames
    sound: np.ndarray  # the stretch's features
    stretch_frames: int
    around: tuple[int, int]  # frames before and after the stretch
    silenced: np.ndarray | None = None  # frames heard as silence whatever the network hears (_without)


@dataclass(frozen=True, eq=False)
class Listening:
    """A take and its text's rendition as measured before a network hears them: what a second hearing
    by another network starts from (fit_again), so the text is not spoken nor the take read twice."""

    rendition: _Rendition
    take: _Take


@dataclass(frozen=True, eq=False)
class _HeardRecording:
    """The take and what a network hears in it, per analysis frame."""

    take: _Take
    speech: np.ndarray  # the detector's, each run's leading room dropped (_from_first_sound)
    log_posteriors: np.ndarray
    features: np.ndarray  # the DTW's


@dataclass(frozen=True, eq=False)
class _TextFound:
    """The text found in the recording as a whole: the DTW's path and what it was drawn through."""

    lead: int  # synthetic frames padded before the rendition
    synthetic_speech: np.ndarray  # padded
    path_x: np.ndarray
    path_y: np.ndarray
    pause: np.ndarray  # per recorded frame: the speaker may pause here
    order_ratio: float


def synthesize_reference(
    utterance: Utterance, engine: SpeechEngine, settings: AlignerSettings, abandoned: Event
) -> tuple[_Reference, np.ndarray]:
    """The text spoken chunk by chunk (sentences up to chunk_letters letters), only its 16 kHz copy kept;
    _Abandoned is raised before the next chunk once `abandoned` is set (nobody waits for the rest)."""
    pieces: list[np.ndarray] = []
    phones: list[PhoneEvent] = []
    words: list[WordEvent] = []
    offset = 0.0
    for part, first_word in _chunks(utterance, settings):
        if abandoned.is_set():
            raise _Abandoned
        spoken = engine.synthesize(part)
        pieces.append(resample(spoken.samples, spoken.sample_rate, ANALYSIS_RATE, 1 / 32768))
        phones.extend(event.moved(offset, first_word) for event in spoken.phone_events)
        words.extend(event.moved(offset, first_word) for event in spoken.word_events)
        offset += spoken.duration
    analysis = np.concatenate(pieces) if pieces else np.zeros(0, np.float32)
    return _Reference(tuple(phones), tuple(words)), analysis


class _Abandoned(Exception):
    """The rendition was stopped: the recording it was for could not be read or heard."""


def _chunks(utterance: Utterance, settings: AlignerSettings) -> list[tuple[Utterance, int]]:
    """Pieces of the utterance (each with its first word's index), cut at sentence pauses past chunk_letters.

    The pause between two pieces moves to the end of the first, so the voice ends it as a sentence.
    """
    words = utterance.words
    bounds = [0]
    letters = 0
    for index, word in enumerate(words):
        if index and letters >= settings.chunk_letters and word.pause_before >= settings.sentence_pause:
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


def align_recording(
    utterance: Utterance,
    recording: str | Path | RecordedAudio,
    engine: SpeechEngine,
    settings: AlignerSettings = DEFAULT_ALIGNER,
) -> RecordingAlignment:
    """Align the synthetic rendition of the utterance to the user's recording of it (a file, or samples
    already read), and judge the fit; see the module text.

    A take the shipped network fits loosely (warned) or hears as another text (refused) is heard again by
    the network that learnt many people's voices too (acoustic/network.py's PEOPLE_WEIGHTS_FILE; the
    aligner's `second_hearing`), and the better of the two fits is kept: the one with fewer warnings, the
    first where they tie. The take is refused only where both hearings refuse it. The text is aligned as a
    person reads it aloud (text.utterance.read_aloud: a line break a pause, as a comma); a take warned or
    refused that reads its text as a list where the text runs on (judgement.pauses_read_as_list) is
    aligned again with a pause before each item, and the alignment with fewer warnings kept. Before that, a
    take whose letters were drawn into music with no voice at its start or end (_not_voice) is aligned
    again with the music heard as silence, and that alignment kept unless it alone is refused. A take
    still warned that does not read its text as a list is aligned again with its pauses free to hold a
    hesitation said aloud ("ııı": AlignerSettings.hesitation_sounds), and the alignment with fewer
    warnings kept; so is a take that fits with no warning but seems to draw a hesitation's length of
    vowel into a word beside an unmarked pause (letter_warp's `hesitation_drawn_in`), and that alignment
    kept where it fits as well without one."""
    utterance = read_aloud(utterance)
    hesitating, settings = settings, without_hesitations(settings)
    fitted, take, kept = _heard(utterance, recording, engine, settings)
    not_voice = _not_voice(take, fitted, settings)
    if not_voice is not None:
        # Letters put in long sound with no voice in it (music, a tone), which they fit as another text's
        # would: aligned again with that sound heard as silence (a howl or a song the detector does not
        # know is a voice fits its letters, and keeps them).
        try:
            again = _heard(utterance, _without(take, not_voice), engine, settings)
        except AudioError:  # a take that cannot be fitted without the music keeps the first alignment
            pass
        else:
            if isinstance(kept, AudioError) or isinstance(again[2], RecordingAlignment):
                fitted, take, kept = again
    # The words a hesitation said aloud seems drawn into (letter_warp's _hesitation_drawn_in).
    drawn_in = np.flatnonzero(fitted.fit.hesitation_drawn_in >= hesitating.hesitation_frames)
    if isinstance(kept, AudioError) or kept.warnings:
        # A list typed with no commas, read item by item: aligned again as read, a pause before each item
        # (the take as the first alignment read and measured it).
        pauses = pauses_read_as_list(utterance, fitted.phone_events, fitted.warp, settings)
        if pauses:
            try:  # an alignment as read that fails outright counts as refused: the first is kept
                again = _heard(read_aloud(utterance, pauses), take, engine, settings)[2]
            except AudioError as refusal:
                again = refusal
            kept = _fewer_warnings(kept, again)
        elif hesitating.hesitation_sounds and isinstance(kept, RecordingAlignment):
            # Words drawn into a hesitation said aloud fit it loosely and leave the text's sounds
            # elsewhere unheard: the take aligned again with pauses that may hold one. Not every take,
            # nor a list: an item, or a word said slowly, may be held as long, and its vowel heard as
            # another.
            again = _hesitated(utterance, take, engine, hesitating)[1]
            # A word moves by no more than a hesitation lasts (music between two lines taken for one, a
            # word drawn far into it, is a looser fit than the warning).
            longest = hesitating.hesitation_longest_frames * HOP / ANALYSIS_RATE
            if (
                isinstance(again, RecordingAlignment)
                and max(_moves(kept, again).values(), default=0) > longest
            ):
                again = AudioError("a word moved further than a hesitation lasts")
            kept = _fewer_warnings(kept, again)
    elif (
        hesitating.hesitation_sounds
        and drawn_in.size
        and not pauses_read_as_list(utterance, fitted.phone_events, fitted.warp, settings)
    ):
        # A hesitation said aloud seemingly drawn into a word beside a pause the text does not mark,
        # though the fit draws no warning: a vowel heard as long as one in a consonant at the word's edge
        # ("eee" into the b of "balkonda"), or a vowel inside the word held that long (into the e of
        # "gelmeden"). Aligned again with pauses that may hold one, and kept where that fits as well,
        # draws no word in further than the first did, moves no word but those and their neighbours (a
        # long take's music or noise taken for a hesitation elsewhere moves others), and squeezes no word
        # to its letters' shortest (a word's own drawn-out sound taken for a hesitation before it). Not a
        # list read item by item: an item's held vowel is its own (the people's lists typed with spaces).
        hesitated, again = _hesitated(utterance, take, engine, hesitating)
        if (
            isinstance(again, RecordingAlignment)
            and not again.warnings
            and not np.any(
                (hesitated.fit.hesitation_drawn_in >= hesitating.hesitation_frames)
                & (hesitated.fit.hesitation_drawn_in > fitted.fit.hesitation_drawn_in)
            )
            and _moved_beside(kept, again, drawn_in)
            and not np.any(_squeezed(hesitated.fit, utterance) & ~_squeezed(fitted.fit, utterance))
        ):
            kept = again
    if isinstance(kept, AudioError):
        raise kept
    return kept


MOVED_SECONDS = 0.1  # a word's onset moved by more than this between two alignments has moved
SQUEEZED_FRAMES = 3  # a word given fewer frames than this per letter is squeezed to its letters' shortest


def _squeezed(fit: Fit, utterance: Utterance) -> np.ndarray:
    """Per word, whether the alignment gives it fewer than SQUEEZED_FRAMES frames a letter: a second
    alignment that squeezes a word so took its own sound for a hesitation (a list's "lyu" said "ljooo",
    its o held in the pause before it and the word 60 ms long)."""
    frames = np.bincount(fit.frame_words[fit.frame_words >= 0], minlength=len(utterance.words))
    letters = np.array([word.letter_count for word in utterance.words])
    return frames < SQUEEZED_FRAMES * letters


def _moves(first: RecordingAlignment, again: RecordingAlignment) -> dict[int, float]:
    """Per word, how far (seconds) the second alignment moves its start from where the first put it."""
    before = {event.word_index: event.start for event in first.synthesis.word_events}
    return {
        event.word_index: abs(event.start - before.get(event.word_index, event.start))
        for event in again.synthesis.word_events
    }


def _moved_beside(first: RecordingAlignment, again: RecordingAlignment, words: np.ndarray) -> bool:
    """Whether every word the second alignment moves from where the first put it is one of `words` or
    next to one."""
    return all(
        moved <= MOVED_SECONDS or bool(np.any(np.abs(words - index) <= 1))
        for index, moved in _moves(first, again).items()
    )


def _hesitated(
    utterance: Utterance, take: _Take, engine: SpeechEngine, settings: AlignerSettings
) -> tuple[RecordingFit | None, RecordingAlignment | AudioError]:
    """The take aligned again with pauses free to hold a hesitation said aloud: the shipped network's fit
    and the alignment kept after the second hearing, or a refusal (as one where the hesitations are not
    held as a person's: none, or many short ones, a looser fit of another text's sounds)."""
    try:
        hesitated, _, again = _heard(utterance, take, engine, settings)
    except AudioError as refusal:
        return None, refusal
    # The hesitations as the shipped network's hearing holds them (the alignment kept may be the second
    # hearing's).
    if not _held_hesitations(hesitated.fit, len(utterance.words), settings):
        return hesitated, AudioError("no hesitation held")
    return hesitated, again


def _held_hesitations(fit: Fit, words: int, settings: AlignerSettings) -> bool:
    """Whether an alignment's pauses hold hesitations as a person's are: at least one pause with
    hesitation_frames to hesitation_longest_frames of one (a breath or a few quiet frames may split one
    "ııı"; music between two lines is far longer), any other such pause with at least half as many (the
    rest of an "eee" may still be drawn into the word after it), and at most one such pause for every
    hesitation_words words of the text (another text's sounds left to its pauses are many and short)."""
    held = np.array(
        [np.count_nonzero(fit.hesitations[start:stop] >= 0) for start, stop in runs(fit.frame_words < 0)]
    )
    held = held[held > 0]
    most = -(-words // settings.hesitation_words)
    return (
        0 < len(held) <= most
        and bool(np.any(held >= settings.hesitation_frames))
        and bool(np.all(2 * held >= settings.hesitation_frames))
        and bool(np.all(held <= settings.hesitation_longest_frames))
    )


def without_hesitations(settings: AlignerSettings) -> AlignerSettings:
    """The settings of a take's first alignments (align_recording): no pause holds a hesitation."""
    return replace(settings, hesitation_sounds="")


def _heard(
    utterance: Utterance,
    recording: str | Path | RecordedAudio | _Take,
    engine: SpeechEngine,
    settings: AlignerSettings,
) -> tuple[RecordingFit, _Take, RecordingAlignment | AudioError]:
    """The take fitted as the shipped network hears it, the take as read and measured, and the alignment
    kept after the second hearing (or the refusal)."""
    fitted, listening = fit_recording(utterance, recording, engine, settings)
    first = judged_fit(utterance, fitted, settings)

    def heard_again() -> RecordingAlignment | AudioError:
        try:  # a take the second network cannot fit at all counts as refused by it: the first is kept
            fitted = fit_again(utterance, listening, settings, load_network(PEOPLE_WEIGHTS_FILE))
        except AudioError as refusal:
            return refusal
        return judged_fit(utterance, fitted, settings)

    return fitted, listening.take, kept_hearing(first, heard_again, settings)


def judged_fit(
    utterance: Utterance, fitted: RecordingFit, settings: AlignerSettings = DEFAULT_ALIGNER
) -> RecordingAlignment | AudioError:
    """The fitted take judged: its alignment with the judgement's warnings, or the judgement's refusal."""
    try:
        phrases, warnings = judge(
            utterance, fitted.phone_events, fitted.warp, fitted.fit, fitted.name, fitted.clipped, settings
        )
    except AudioError as refusal:
        return refusal
    hesitations = spoken_hesitations(fitted.fit.hesitations, fitted.fit.frame_words)
    return RecordingAlignment(fitted.warp, fitted.synthesis, phrases, warnings, hesitations)


def kept_hearing(
    first: RecordingAlignment | AudioError,
    second: Callable[[], RecordingAlignment | AudioError],
    settings: AlignerSettings = DEFAULT_ALIGNER,
) -> RecordingAlignment | AudioError:
    """The first hearing where it fits with no warning (or `second_hearing` is off); else the second
    hearing too (`second()`), and of the two the one with fewer warnings (a refusal counts as the most),
    the first where they tie."""
    if not settings.second_hearing or (isinstance(first, RecordingAlignment) and not first.warnings):
        return first
    return _fewer_warnings(first, second())


def _fewer_warnings(
    first: RecordingAlignment | AudioError, again: RecordingAlignment | AudioError
) -> RecordingAlignment | AudioError:
    """Of two alignments of a take, the one with fewer warnings (a refusal counts as the most), the first
    where they tie."""
    if isinstance(again, AudioError):
        return first
    if isinstance(first, AudioError) or len(again.warnings) < len(first.warnings):
        return again
    return first


def fit_recording(
    utterance: Utterance,
    recording: str | Path | RecordedAudio | _Take,
    engine: SpeechEngine,
    settings: AlignerSettings = DEFAULT_ALIGNER,
    network: PhoneNetwork | None = None,
) -> tuple[RecordingFit, Listening]:
    """The alignment before its judgement: what judgement.judge reads (a tuning run judges it again with
    other settings); heard by the shipped network unless another is given. With it, what was measured
    before the network heard the take and its rendition (fit_again starts from it). The recording: a
    file, samples already read, or a take an earlier fit read and measured (Listening.take)."""
    network = network or load_network()
    # The synthetic rendition is made and heard in a thread of its own while the recording is read and
    # heard: eSpeak NG, the decoders and numpy's matrix products release the interpreter, so on two cores
    # the two overlap. Where the recording cannot be read or heard, the rendition stops at its next chunk.
    # The letters' synthetic spans are found here while the rendition is heard there.
    abandoned, synthesized = Event(), Future()
    with ThreadPoolExecutor(max_workers=1) as pool:
        rendition = pool.submit(
            _synthetic_analysis, utterance, engine, settings, network, synthesized, abandoned
        )
        try:
            take = _read_and_measure(recording, settings)
            heard = _hear_take(take, settings, network)
        except BaseException:
            abandoned.set()
            raise
        reference = synthesized.result()
        starts, ends, _ = phone_letter_spans(
            utterance,
            Synthesis(take.output[:0], take.output_rate, reference.phone_events, reference.word_events, ""),
            engine,
        )
        sound, speech, rendition_features = rendition.result()
    listening = Listening(_Rendition(reference, sound, speech, starts, ends), take)
    return _fitted(utterance, listening.rendition, rendition_features, heard, settings, network), listening


def fit_again(
    utterance: Utterance, listening: Listening, settings: AlignerSettings, network: PhoneNetwork
) -> RecordingFit:
    """The take fitted as another network hears it, from what fit_recording measured before its network
    heard the take and the rendition: the text is not spoken, nor the take read or searched for speech,
    a second time. The rendition is heard in a thread of its own while the take is."""
    with ThreadPoolExecutor(max_workers=1) as pool:
        rendition_features = pool.submit(_heard_rendition, listening.rendition.sound, settings, network)
        heard = _hear_take(listening.take, settings, network)
        return _fitted(utterance, listening.rendition, rendition_features.result(), heard, settings, network)


def _fitted(
    utterance: Utterance,
    rendered: _Rendition,
    rendition_features: np.ndarray,
    heard: _HeardRecording,
    settings: AlignerSettings,
    network: PhoneNetwork,
) -> RecordingFit:
    """The text found in the take, its letters placed and the events warped, as the network heard both
    (rendition_features: the DTW's features of the rendition)."""
    take = heard.take
    _check_lengths(take.name, heard.speech, rendered.speech, settings)
    found = _find_text(rendered, rendition_features, heard, settings)
    letters = _place_letters(utterance, rendered, heard, found, settings, network)
    if letters is None:
        raise AudioError(
            f"recording {take.name} is too short for the text's letters, so it cannot read this text; check "
            "that the recording and the text belong together"
        )
    synthesis = warp_synthesis(
        Synthesis(
            take.output,
            take.output_rate,
            rendered.reference.phone_events,
            rendered.reference.word_events,
            "recording",
        ),
        letters.warp,
        take.output,
    )
    fit = Fit(
        found.path_x,
        found.path_y,
        letters.mismatch,
        letters.heard_letters,
        letters.frame_words,
        letters.hesitations,
        found.synthetic_speech,
        heard.speech & ~found.pause,  # what a pause holds (a background voice, a room's tail) is not judged
        take.under_speech,
        found.lead,
        found.order_ratio,
        letters.hesitation_drawn_in,
    )
    return RecordingFit(
        rendered.reference.phone_events, letters.warp, synthesis, fit, take.name, take.clipped
    )


def _place_letters(
    utterance: Utterance,
    rendered: _Rendition,
    heard: _HeardRecording,
    found: _TextFound,
    settings: AlignerSettings,
    network: PhoneNetwork,
) -> LetterFit | None:
    """Each letter where the network hears it, within reach of the DTW's path (letter_warp.py)."""
    return letter_warp(
        utterance,
        rendered.letter_starts,
        rendered.letter_ends,
        heard.log_posteriors,
        _silence_bias(heard.speech, found.pause, heard.take.under_speech, settings),
        _break_cost(heard.speech, settings),
        network,
        found.path_x,
        found.path_y,
        found.lead,
        heard.take.output.size / heard.take.output_rate,
        np.array([CLASS_INDEX[sound] for sound in settings.hesitation_sounds], np.int64),
        settings.hesitation_cost,
        settings.hesitation_frames,
    )


def _read_and_measure(recording: str | Path | RecordedAudio | _Take, settings: AlignerSettings) -> _Take:
    """The user's recording read (a file, or samples already read) and measured (_measure_take); a take
    already measured as it is."""
    if isinstance(recording, _Take):
        return recording
    if isinstance(recording, RecordedAudio):
        native, native_rate, name = recording.samples, recording.sample_rate, recording.name
    else:
        native, native_rate = read_audio(recording)
        name = str(recording)
    # The user's audio is kept at its own rate (up to 48 kHz) as 16-bit PCM; a file's float copy is
    # dropped before the hearing (the caller's samples stay theirs): a 30-minute take at 44.1 kHz holds
    # 300 MB less through it.
    output_rate = min(native_rate, MAX_OUTPUT_RATE)
    output = resampled_pcm(native, native_rate, output_rate)
    clipped = clipping(native)
    del native
    return _measure_take(output, output_rate, clipped, name, settings)


def _hear_take(take: _Take, settings: AlignerSettings, network: PhoneNetwork) -> _HeardRecording:
    """What the network hears in the take: its log posteriors (silence only beyond the stretch around its
    speech) and the DTW's features, and its speech with each run's leading room dropped."""
    log_posteriors = _silence_around(
        heard_log_posteriors(take.sound, take.stretch_frames, network), *take.around
    )
    if take.silenced is not None:
        log_posteriors[take.silenced] = _SURELY_NOT
        log_posteriors[take.silenced, CLASS_INDEX[SILENCE]] = 0.0
    speech = _from_first_sound(take.speech, log_posteriors, take.under_speech, settings)
    features = heard_features(_speech_not_silence(log_posteriors, speech, settings), settings)
    return _HeardRecording(take, speech, log_posteriors, features)


def _find_text(
    rendered: _Rendition, rendition_features: np.ndarray, heard: _HeardRecording, settings: AlignerSettings
) -> _TextFound:
    """The DTW of the synthetic rendition (padded by silence) against the recording, a pause possible at
    any word boundary and wherever the recording is silent or holds only quiet speech."""
    x, synthetic_speech = rendition_features, rendered.speech
    spoken = np.flatnonzero(heard.speech)
    lead = int(spoken[0]) + settings.padding_frames
    tail = len(heard.speech) - int(spoken[-1]) + settings.padding_frames
    x = np.concatenate((_silence(lead, x.shape[1], settings), x, _silence(tail, x.shape[1], settings)))
    synthetic_speech = np.pad(synthetic_speech, (lead, tail))
    y = heard.features
    order_ratio = _order_ratio(x, synthetic_speech, y, settings)
    pauses = _pauses(
        _word_onsets(rendered.reference), lead, synthetic_speech, heard.speech, heard.take.loudness,
        heard.take.under_speech, settings,
    )  # fmt: skip
    path_x, path_y = coarse_dtw_path(x, y, step_penalty=settings.step_penalty, pauses=pauses)
    # Silence, or a stretch a voice in the background or a room's tail may fill: the speaker may pause.
    return _TextFound(lead, synthetic_speech, path_x, path_y, np.isfinite(pauses.y_hold_cost), order_ratio)


def _measure_take(
    output: np.ndarray, output_rate: int, clipped: str, name: str, settings: AlignerSettings
) -> _Take:
    """The take (16-bit PCM) as measured before a network hears it: its speech frames, dB above its floor,
    dB under its speech and the acoustic model's input features, each measured on the stretch around its
    speech within its sound (acoustic.features.sounding_frames and speech_stretch); beyond it, silence at
    the floor."""
    recorded = resample(output, output_rate, ANALYSIS_RATE, 1 / 32768)
    frames = frame_count(recorded.size)
    sound_first, sound_stop = sounding_frames(recorded, frames)
    recorded = frames_of(recorded, sound_first, sound_stop, frames)
    sound_frames = sound_stop - sound_first
    speech = _checked_speech(name, recorded, speech_frames(recorded, sound_frames), settings)
    first, stop = speech_stretch(speech)
    if (first, stop) != (0, sound_frames):
        recorded = frames_of(recorded, first, stop, sound_frames)
        speech = _checked_speech(name, recorded, speech_frames(recorded, stop - first), settings)
    first, stop = first + sound_first, stop + sound_first
    around = (first, frames - stop)
    under = under_speech(recorded, stop - first)
    return _Take(
        name,
        output,
        output_rate,
        clipped,
        np.pad(speech, around),
        np.pad(above_floor(recorded, stop - first), around),
        np.pad(under, around, constant_values=under.max()),
        recogniser_features(recorded),
        stop - first,
        around,
    )


def heard_log_posteriors(sound: np.ndarray, frames: int, network: PhoneNetwork) -> np.ndarray:
    """What the acoustic model hears in each of `frames` 10 ms frames, given their input features
    (acoustic.features.recogniser_features): the log of its class posteriors (frames x classes, float32).
    The square roots of the posteriors are the DTW's features: the Euclidean distance between two frames
    is then the Hellinger distance between what is heard in them."""
    heard = network.log_posteriors(sound)
    return _silence_around(heard[:frames], 0, max(0, frames - len(heard)))


_SURELY_NOT = -69.0  # the log posterior of a class surely not heard (a frame heard as silence alone)


def _silence_around(log_posteriors: np.ndarray, before: int, after: int) -> np.ndarray:
    """The log posteriors with `before` and `after` frames in which only silence is heard around them."""
    heard = np.pad(log_posteriors, ((before, after), (0, 0)), constant_values=_SURELY_NOT)
    heard[:before, CLASS_INDEX[SILENCE]] = 0.0
    heard[len(heard) - after :, CLASS_INDEX[SILENCE]] = 0.0
    return heard


def _silence_bias(
    recorded_speech: np.ndarray,
    recorded_pause: np.ndarray,
    recorded_under_speech: np.ndarray,
    settings: AlignerSettings,
) -> np.ndarray:
    """What the speech detector adds to silence's score in each recorded frame, for placing the letters:
    speaker_silence_bias well inside the speaker's speech but where a sound dies away, quiet_silence_bias
    where speech so quiet or so near the noise floor that a pause may hold it (a voice in the background,
    a room's tail)."""
    bias = np.where(recorded_speech & recorded_pause, settings.quiet_silence_bias, 0.0)
    speaking = _inner(recorded_speech & ~recorded_pause, settings.speech_edge_frames)
    bias[speaking & ~fading(recorded_under_speech, settings)] = settings.speaker_silence_bias
    return bias


def _break_cost(recorded_speech: np.ndarray, settings: AlignerSettings) -> np.ndarray:
    """What a pause the text does not mark costs in each recorded frame: break_pause_cost in a break (at
    least break_frames with no speech), nothing elsewhere."""
    return np.where(long_runs(~recorded_speech, settings.break_frames), settings.break_pause_cost, 0.0)


def fading(under_speech_db: np.ndarray, settings: AlignerSettings = DEFAULT_ALIGNER) -> np.ndarray:
    """The frames of a sound dying away (see fading_db), given how far each lies under the loud frames."""
    level = -np.asarray(under_speech_db, np.float64)
    below = level <= -settings.fading_db
    found = np.zeros(level.size, bool)
    starts = np.flatnonzero(below[1:] & ~below[:-1]) + 1  # the level falls past settings.fading_db here
    for start, end in zip(starts, np.append(starts[1:], level.size), strict=False):
        after = level[start:end]  # a fade ends before the level can fall past settings.fading_db again
        rising = (after >= np.minimum.accumulate(after) + settings.rising_db) | ~below[start:end]
        found[start : start + (int(np.argmax(rising)) if rising.any() else after.size)] = True
    return found


def _from_first_sound(
    speech: np.ndarray, log_posteriors: np.ndarray, under_speech_db: np.ndarray, settings: AlignerSettings
) -> np.ndarray:
    """The speech frames with each run's leading frames of room dropped (see leading_silence_sure); a run
    that is room throughout is left whole: whether it is speech is the detector's call."""
    room = (log_posteriors[:, CLASS_INDEX[SILENCE]] >= np.log(settings.leading_silence_sure)) & (
        under_speech_db >= settings.leading_quiet_db
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


def _speech_not_silence(
    log_posteriors: np.ndarray, speech: np.ndarray, settings: AlignerSettings
) -> np.ndarray:
    """The posteriors with silence made silence_in_speech times less likely where the speech detector
    hears speech: the network, unsure of a voice unlike any it learnt from, hears silence sooner than
    a wrong letter, and the DTW would then hold the text's pauses against the speaker's words."""
    adjusted = log_posteriors.copy()
    adjusted[speech, CLASS_INDEX[SILENCE]] += np.log(settings.silence_in_speech)
    adjusted -= np.log(np.exp(adjusted).sum(axis=1, keepdims=True))
    return adjusted


def heard_features(log_posteriors: np.ndarray, settings: AlignerSettings = DEFAULT_ALIGNER) -> np.ndarray:
    """The DTW's features: the square roots of the posteriors, scaled by heard_scale."""
    return (settings.heard_scale * np.sqrt(np.exp(log_posteriors))).astype(np.float32)


def _silence(frames: int, classes: int, settings: AlignerSettings) -> np.ndarray:
    """Features of frames in which nothing but silence is heard."""
    heard = np.zeros((frames, classes), np.float32)
    heard[:, CLASS_INDEX[SILENCE]] = settings.heard_scale
    return heard


def _synthetic_analysis(
    utterance: Utterance,
    engine: SpeechEngine,
    settings: AlignerSettings,
    network: PhoneNetwork,
    synthesized: Future,
    abandoned: Event,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The synthetic rendition's sound (the acoustic model's input features) and speech frames, and the
    DTW's features of what the network hears in it (its audio dropped); its events are handed to
    `synthesized` as soon as it is spoken, before it is heard."""
    try:
        reference, analysis = synthesize_reference(utterance, engine, settings, abandoned)
    except BaseException as error:
        synthesized.set_exception(error)
        raise
    synthesized.set_result(reference)
    sound = recogniser_features(analysis)
    speech = clean_speech_frames(analysis, frame_count(analysis.size))
    del analysis
    return sound, speech, _heard_rendition(sound, settings, network)


def _heard_rendition(sound: np.ndarray, settings: AlignerSettings, network: PhoneNetwork) -> np.ndarray:
    """The DTW's features of what the network hears in the rendition's sound."""
    return heard_features(heard_log_posteriors(sound, len(sound), network), settings)


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
    settings: AlignerSettings,
) -> Pauses:
    """Where the recording may pause though the synthetic speech does not: at any word boundary.

    A person hesitates between words where the text has no comma, and leaves out pauses it has: the
    DTW may hold a synthetic word boundary through a recorded pause, and a synthetic pause against
    any recorded frame, at pause_cost a frame. With a voice in the background or in a live room a
    pause is not silent: a long enough stretch close to the recording's noise floor (which a steady
    background voice is part of), or far under the speaker's own loud frames (a background voice in a
    quiet take, a room's tail), is a pause too.
    """
    box = np.ones(5) / 5
    free = ~synthetic_speech
    boundaries = lead + np.round(word_onsets[1:] * ANALYSIS_RATE / HOP).astype(np.int64)
    for offset in range(-settings.boundary_slack, settings.boundary_slack + 1):
        free[np.clip(boundaries + offset, 0, free.size - 1)] = True
    near_floor = ~recorded_speech | (np.convolve(recorded_loudness, box, "same") < settings.floor_pause_db)
    # Only the detector's "speech" counts here: a silence joined to the quiet start of the word after it
    # would take that start for a pause.
    far_under = recorded_speech & (
        np.convolve(recorded_under_speech, box, "same") > settings.under_speech_pause_db
    )
    hold = np.full(recorded_speech.size, np.inf)
    for quiet, shortest, cost in (
        (far_under, settings.under_speech_pause_frames, settings.far_under_hold_cost),
        (near_floor, settings.floor_pause_frames, settings.pause_cost),
    ):
        hold[long_runs(quiet, shortest)] = cost
    hold[~recorded_speech] = settings.pause_cost
    return Pauses(free, ~synthetic_speech, hold, settings.pause_cost)


def _checked_speech(
    name: str, recorded: np.ndarray, speech: np.ndarray, settings: AlignerSettings
) -> np.ndarray:
    """The recording's speech frames; where the WebRTC-based mask holds less than a short word, those of
    the detector trained on people (speech_detector.py), and the take is silent only if it finds none."""
    if np.count_nonzero(speech) >= settings.least_speech_frames:
        return speech
    detection = detect_speech(recorded, speech.size)
    if not detection.found:
        raise AudioError(f"recording {name} is silent (no speech found); record the text again")
    return detection.speech


def _not_voice(take: _Take, fitted: RecordingFit, settings: AlignerSettings) -> np.ndarray | None:
    """The stretches of sound with no voice in it where the alignment put letters that fit them as another
    text's would (worse than `unmatched` on average), or None. They are looked for within
    not_voice_edge_frames of the take's start and end (a video's intro or outro, a jingle) and of any
    not_voice_frames holding suspect_frames of letters that fit worse than suspect_mismatch (music
    between two lines of a long take).
    No voice: farther than voice_reach_frames from any that Silero's detector, trained on people, hears for
    shortest_voice_frames, over at least not_voice_frames of the WebRTC-based mask's speech (music, a tone,
    a machine); a howl or a song the detector does not know for a voice fits its letters, and is kept."""
    frames, edge = take.speech.size, settings.not_voice_edge_frames
    count = min(fitted.fit.frame_words.size, frames)
    letters, mismatch = fitted.fit.frame_words[:count] >= 0, fitted.fit.mismatch[:count]
    looked = np.zeros(frames, bool)
    looked[:edge] = looked[max(0, frames - edge) :] = True
    window = settings.not_voice_frames
    badly = np.convolve(letters & (mismatch >= settings.suspect_mismatch), np.ones(window), "valid")
    for start, stop in runs(badly >= settings.suspect_frames):  # windows starting start..stop - 1
        looked[max(0, start - edge) : stop - 1 + window + edge] = True
    found = np.zeros(frames, bool)
    per_frame = take.output_rate * HOP / ANALYSIS_RATE  # output samples per frame
    for first, stop in runs(looked):
        output = take.output[round(first * per_frame) : round(stop * per_frame)]
        voice = long_runs(
            detect_speech(resample(output, take.output_rate, ANALYSIS_RATE, 1 / 32768), stop - first).speech,
            settings.shortest_voice_frames,
        )
        if not voice.any():
            continue
        for start, end in runs(_inner(~voice, settings.voice_reach_frames)):  # no voice within reach
            if np.count_nonzero(take.speech[first + start : first + end]) >= settings.not_voice_frames:
                found[first + start : first + end] = True
    inside = letters & found[:count]
    if not inside.any() or np.mean(mismatch[inside]) < settings.unmatched:
        return None
    return found


def _without(take: _Take, not_voice: np.ndarray) -> _Take:
    """The take with its stretches of no voice heard as silence: no speech, nothing heard."""
    return replace(take, speech=take.speech & ~not_voice, silenced=not_voice)


def _check_lengths(
    name: str, recorded_speech: np.ndarray, synthetic_speech: np.ndarray, settings: AlignerSettings
) -> None:
    recorded_frames = np.flatnonzero(recorded_speech)
    synthetic_frames = np.flatnonzero(synthetic_speech)
    if synthetic_frames.size == 0:
        raise AudioError("the synthetic speech is silent, so there is nothing to align the recording to")
    # Speech, not span: a list read with long pauses has no more speech than the text. A short text may
    # be said far slower than eSpeak says it (a word alone, drawn out), so the ratio has a slack.
    recorded_seconds = recorded_frames.size * HOP / ANALYSIS_RATE
    synthetic_seconds = synthetic_frames.size * HOP / ANALYSIS_RATE
    if not (
        synthetic_seconds / settings.max_length_ratio - settings.length_slack
        <= recorded_seconds
        <= synthetic_seconds * settings.max_length_ratio + settings.length_slack
    ):
        raise AudioError(
            f"recording {name} has {recorded_seconds:.1f} s of speech but the text takes about "
            f"{synthetic_seconds:.1f} s to say (more than {settings.max_length_ratio:g} times apart); check "
            "that the recording reads exactly this text"
        )


def _order_ratio(
    x: np.ndarray, synthetic_speech: np.ndarray, y: np.ndarray, settings: AlignerSettings
) -> float:
    """The DTW cost of the first 30 seconds over the cost with the text's sounds in reverse order: near 1
    when the recording says something else, whatever the voice."""
    excerpt = slice(0, settings.order_frames)
    return _coarse_cost(x[excerpt], y[excerpt], settings) / _coarse_cost(
        _reversed_speech(x[excerpt], synthetic_speech[excerpt]), y[excerpt], settings
    )


def _coarse_cost(x: np.ndarray, y: np.ndarray, settings: AlignerSettings) -> float:
    """Mean distance per step of the DTW path between the starts of x and y at a quarter frame rate."""
    coarse_x, coarse_y = x[::4], y[::4]
    path_x, path_y = dtw_path(coarse_x, coarse_y, step_penalty=settings.step_penalty)
    return float(np.sqrt(((coarse_x[path_x] - coarse_y[path_y]) ** 2).sum(axis=1)).mean())


def _reversed_speech(x: np.ndarray, speech: np.ndarray) -> np.ndarray:
    """x with its speech frames in reverse order and its silences in place."""
    reversed_x = x.copy()
    frames = np.flatnonzero(speech)
    reversed_x[frames] = x[frames[::-1]]
    return reversed_x
