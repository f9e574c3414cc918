"""Lip sync from the audio alone: the Turkish letters of a recording without its text, and their times.

The acoustic model's network (acoustic/network.py) and Whisper's encoder under a classifier
(acoustic/whisper.py) hear the audio, both with numpy alone; recogniser.py averages the two, decoder.py
finds the letter sequence (Viterbi with minimum durations and Turkish letter transitions), recogniser.py
keeps doubtful closures off the lips and groups letters into phrases, transcript.py turns them into the
Utterance and Timeline every stage after speech takes. `speech_from_audio(path)` does it all for a
recording.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from ...base.errors import AudioError
from ...base.model import Utterance
from ..acoustic.features import speech_stretch
from ..audio import MAX_OUTPUT_RATE, clipping, read_audio, resample, resampled_pcm
from ..base import Synthesis
from ..features import ANALYSIS_RATE, HOP
from ..speech_detector import detect_speech
from ..timeline import Speech
from .recogniser import Recognition, recognise
from .settings import DEFAULT_RECOGNISER, RecogniserSettings
from .transcript import RECOGNISED_TIMING, heard_timeline, heard_utterance


def speech_from_audio(
    path: Path | str, settings: RecogniserSettings = DEFAULT_RECOGNISER
) -> tuple[Utterance, Speech]:
    """The utterance heard in a recording and its speech: the timeline and the recording as its audio."""
    path = Path(path)
    native, native_rate = read_audio(path)
    output_rate = min(native_rate, MAX_OUTPUT_RATE)
    output = resampled_pcm(native, native_rate, output_rate)
    clipped = clipping(native)
    del native
    samples = resample(output, output_rate, ANALYSIS_RATE, 1 / 32768)
    peak = float(np.abs(samples).max(initial=0.0))
    if 20 * np.log10(peak + 1e-12) < settings.silent_peak_db:
        raise AudioError(f"no speech found in {path}: it is silent; give a recording of someone speaking")
    # Whether anyone speaks is decided by a detector trained on many people's speech in many languages
    # (speech_detector.py), not by how much the recogniser, which has heard few people, makes of it.
    detection = detect_speech(samples)
    if not detection.found:
        raise AudioError(
            f"no speech found in {path}: it sounds like silence, noise or music without a voice; "
            "give a recording of someone speaking Turkish, or type the text it says"
        )
    recognition = _recognised_around_speech(samples, detection.speech, settings)
    del samples
    if not recognition.phrases:
        raise AudioError(
            f"no letters heard in {path}, though someone speaks in it: too short, too quiet or too "
            "unlike Turkish for the recogniser; type the text it says instead"
        )
    utterance = heard_utterance(recognition)
    timeline = heard_timeline(utterance, recognition, output.size / output_rate, settings)
    synthesis = Synthesis(output, output_rate, (), (), "recording")
    return utterance, Speech(timeline, synthesis, _warnings(path, recognition, clipped, settings))


def _recognised_around_speech(
    samples: np.ndarray, speech: np.ndarray, settings: RecogniserSettings
) -> Recognition:
    """What is heard in the stretch around the detector's speech (acoustic.features.speech_stretch), timed
    in the whole take: silence beyond it would change how the same speech is heard."""
    first, stop = speech_stretch(speech)
    recognition = recognise(samples[first * HOP : stop * HOP], settings, speech[first:stop])
    offset = first * HOP / ANALYSIS_RATE
    return Recognition(
        tuple(
            tuple(replace(letter, start=letter.start + offset, end=letter.end + offset) for letter in phrase)
            for phrase in recognition.phrases
        ),
        recognition.confidence,
    )


def _warnings(
    path: Path, recognition: Recognition, clipped: str, settings: RecogniserSettings
) -> tuple[str, ...]:
    """The low-confidence warning, with the take's clipping (audio.clipping) as the likelier cause."""
    if recognition.confidence >= settings.doubtful_confidence:
        return ()
    causes = (
        f"{clipped}; it may also not be Turkish"
        if clipped
        else "it may not be Turkish, be noisy or reverberant, or be a voice unlike those the recogniser "
        "learnt from"
    )
    return (
        f"the speech in {path} was recognised with low confidence ({recognition.confidence:.0%}; eSpeak "
        f"NG's Turkish gives {settings.doubtful_confidence:.0%} or more, recordings of people less): "
        f"{causes}; the mouth follows what was heard, but give the text it says for exact lip sync",
    )


__all__ = ["RECOGNISED_TIMING", "Recognition", "RecogniserSettings", "recognise", "speech_from_audio"]
