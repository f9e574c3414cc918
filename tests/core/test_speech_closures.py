"""A voiceless stop's closure: eSpeak NG reports the stop at its burst, the silence before belongs to it.

The engine's side (the silence measured in its audio) is tested in test_speech.py on real speech; here, the
closure carried through a recording's time warp and given back to recognised stops.
"""

import numpy as np
import pytest

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


def test_a_recorded_closure_stretches_with_the_phone_before():
    vowel = PhoneEvent(0.10, 0.30, "a", 0)
    stop = PhoneEvent(0.30, 0.40, "p", 0, closure=0.04)
    # The recording speaks the vowel and the stop twice as slowly, with no pause between them.
    warp = TimeWarp(np.array([0.10, 0.30, 0.40]), np.array([0.20, 0.60, 0.80]), recording_duration=2.0)
    warped = warp_synthesis(synthesis(vowel, stop), warp, np.zeros(32000, np.int16)).phone_events
    assert np.isclose(warped[1].start, 0.60) and np.isclose(warped[1].closure, 0.08, atol=1e-4)
    placed = with_closures(synthesis(*warped)).phone_events
    assert np.isclose(placed[1].start, 0.52, atol=1e-4) and np.isclose(placed[0].end, 0.52, atol=1e-4)
    # A phone before that swallowed a hesitation said aloud (0.2 s of eSpeak NG's vowel recorded as 2 s): the
    # closure keeps the stop's own pace, not the vowel's.
    slow = TimeWarp(np.array([0.10, 0.30]), np.array([0.20, 2.20]), 3.0)
    stretched = warp_synthesis(synthesis(vowel, stop), slow, np.zeros(48000, np.int16)).phone_events
    assert np.isclose(stretched[1].closure, 0.04)
    # However slow the stop's word, never longer than a person's closures go.
    slower = TimeWarp(np.array([0.10, 0.30, 0.40]), np.array([0.20, 2.20, 3.20]), 4.0)
    longest = warp_synthesis(synthesis(vowel, stop), slower, np.zeros(64000, np.int16)).phone_events
    assert np.isclose(longest[1].closure, min(CLOSURE_STRETCH * 0.04, LONGEST_CLOSURE))


@pytest.mark.parametrize(("vowel_stretch", "closure"), [(1.0, 0.04), (2.0, 0.08), (8.0, 0.06)])
def test_a_closure_after_a_vowel_drawn_out_past_a_persons_closures_keeps_the_stops_pace(
    vowel_stretch, closure
):
    """The vowel before a stop stretched as the stop's closure: twice as long, twice the closure. Drawn out
    past what a person's closures are (holding a hesitation said aloud the alignment took for its own), the
    closure is as much longer than eSpeak NG's as the stop's word is. It used to be as long as a person's
    closures go, 0.15 s: a "t" after "bahçede eee" keyed 90 ms early."""
    vowel = PhoneEvent(0.10, 0.30, "a", 0)
    stop = PhoneEvent(0.30, 0.40, "p", 1, closure=0.04)
    after = PhoneEvent(0.40, 0.50, "a", 1)
    # The stop's word is spoken 1.5 times as slowly, 0.5 s after the vowel ends: the warp jumps over the
    # pause between the vowel's end and the stop's burst.
    vowel_end = 0.20 + 0.20 * vowel_stretch
    warp = TimeWarp(
        synthetic=np.array([0.10, 0.30 - JUMP, 0.30, 0.50]),
        recorded=np.array([0.20, vowel_end, vowel_end + 0.50, vowel_end + 0.80]),
        recording_duration=5.0,
    )
    events = synthesis(vowel, stop, after)
    warped = warp_synthesis(events, warp, np.zeros(80000, np.int16)).phone_events
    assert np.isclose(warped[1].start, vowel_end + 0.50)
    assert np.isclose(warped[1].closure, closure, atol=1e-4)  # the pause not in it
    placed = with_closures(synthesis(*warped)).phone_events
    assert np.isclose(placed[1].start, vowel_end + 0.50 - closure, atol=1e-4)
    assert np.isclose(placed[0].end, vowel_end, atol=1e-4)
    # Never longer than a pause it lies in.
    brief = TimeWarp(warp.synthetic, np.array([0.20, 1.80, 1.83, 2.13]), 5.0)
    assert np.isclose(warp_synthesis(events, brief, np.zeros(80000, np.int16)).phone_events[1].closure, 0.03)


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
