"""A voiceless stop's closure: eSpeak NG reports the stop at its burst, the silence before belongs to it.

The engine's side (the silence measured in its audio) is tested in test_speech.py on real speech; here, the
closure carried through a recording's time warp and given back to recognised stops.
"""

import numpy as np

from turkish_lipsync.core.speech.base import PhoneEvent, Synthesis
from turkish_lipsync.core.speech.recognition.recogniser import HeardLetter, Recognition
from turkish_lipsync.core.speech.recognition.settings import DEFAULT_RECOGNISER
from turkish_lipsync.core.speech.recognition.transcript import heard_timeline, heard_utterance
from turkish_lipsync.core.speech.timewarp import (
    CLOSURE_STRETCH,
    JUMP,
    LONGEST_CLOSURE,
    TimeWarp,
    warp_synthesis,
    with_closures,
)


def synthesis(*events: PhoneEvent) -> Synthesis:
    return Synthesis(np.zeros(16000, np.int16), 16000, events, (), "espeak")


def test_a_stop_takes_its_closure_from_the_end_of_the_phone_before():
    vowel = PhoneEvent(0.10, 0.30, "a", 0)
    stop = PhoneEvent(0.30, 0.40, "p", 0, closure=0.04)
    moved = with_closures(synthesis(vowel, stop)).phone_events
    assert moved[0].end == moved[1].start == 0.26
    assert moved[1].closure == 0.0 and moved[1].end == 0.40
    # Never further back than the start of the phone before.
    short = with_closures(synthesis(PhoneEvent(0.28, 0.30, "a", 0), stop)).phone_events
    assert short[1].start == 0.28


def test_a_recorded_closure_stretches_with_the_phone_before_but_not_over_a_pause():
    vowel = PhoneEvent(0.10, 0.30, "a", 0)
    stop = PhoneEvent(0.30, 0.40, "p", 1, closure=0.04)
    # The recording speaks the vowel twice as slowly and pauses 0.5 s before the stop's word: the warp
    # jumps over the pause between the vowel's end and the stop's burst.
    warp = TimeWarp(
        synthetic=np.array([0.10, 0.30 - JUMP, 0.30, 0.40]),
        recorded=np.array([0.20, 0.60, 1.10, 1.20]),
        recording_duration=2.0,
    )
    warped = warp_synthesis(synthesis(vowel, stop), warp, np.zeros(32000, np.int16)).phone_events
    assert np.isclose(warped[1].start, 1.10)
    assert np.isclose(warped[1].closure, 0.08, atol=1e-4)  # twice as long, the pause not in it
    placed = with_closures(synthesis(*warped)).phone_events
    assert np.isclose(placed[1].start, 1.02, atol=1e-4) and np.isclose(placed[0].end, 0.60, atol=1e-4)
    # A phone before that swallowed a hesitation: its share is bounded.
    slow = TimeWarp(np.array([0.10, 0.30]), np.array([0.20, 2.20]), 3.0)
    stretched = warp_synthesis(synthesis(vowel, stop), slow, np.zeros(48000, np.int16)).phone_events
    assert np.isclose(stretched[1].closure, min(CLOSURE_STRETCH * 0.04, LONGEST_CLOSURE))


def test_a_recognised_stop_gets_its_closure_back_from_the_letter_before_it_in_its_phrase():
    def letter(name, start, end):
        return HeardLetter(name, start, end, 0.9)

    recognition = Recognition(
        (
            (letter("a", 0.10, 0.40), letter("p", 0.40, 0.50), letter("ı", 0.50, 0.60)),
            (letter("t", 1.00, 1.10), letter("a", 1.10, 1.16), letter("k", 1.16, 1.20)),
        ),
        0.9,
    )
    timeline = heard_timeline(heard_utterance(recognition), recognition, 2.0)
    starts = {(phone.word_index, phone.letter): phone.start for phone in timeline.phones}
    assert np.isclose(starts[(0, "p")], 0.40 - DEFAULT_RECOGNISER.closure_share * 0.30)
    assert np.isclose(timeline.phones[0].end, starts[(0, "p")])
    assert np.isclose(starts[(1, "k")], 1.16 - DEFAULT_RECOGNISER.closure_share * 0.06)
    assert starts[(1, "t")] == 1.00  # a phrase's first letter: after a pause, the stop starts the sound
    assert starts[(0, "ı")] == 0.50  # a vowel keeps its start
