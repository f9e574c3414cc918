"""The judgement's rules on a take's fit built frame by frame: another text refused, a list of foreign
syllables read with its own text warned."""

import numpy as np
import pytest

from turkish_lipsync.core.base.errors import AudioError
from turkish_lipsync.core.speech.base import PhoneEvent
from turkish_lipsync.core.speech.judgement import Fit, judge
from turkish_lipsync.core.speech.timewarp import TimeWarp
from turkish_lipsync.core.text.utterance import build_utterance

LIST = "pi, tu, ba, ne, rje, ko, no, si"
WORD_FRAMES, GAP_FRAMES = 30, 10  # each item 0.3 s, 0.1 s of pause after it (10 ms frames)


def judged(word_mismatch: list[float], order_ratio: float, text: str = LIST, gap_frames: int = GAP_FRAMES):
    """judge() on a take of `text` (eight words) whose words fit their letters with these mismatches, each
    word 0.3 s and a pause of gap_frames after it."""
    utterance = build_utterance(text)
    step = WORD_FRAMES + gap_frames
    frames = step * len(utterance.words)
    frame_words = np.full(frames, -1)
    mismatch = np.zeros(frames)
    for index, value in enumerate(word_mismatch):
        frame_words[index * step : index * step + WORD_FRAMES] = index
        mismatch[index * step : index * step + WORD_FRAMES] = value
    spoken = frame_words >= 0
    events = tuple(
        PhoneEvent(index * step / 100, (index * step + WORD_FRAMES) / 100, "a", index)
        for index in range(len(utterance.words))
    )
    fit = Fit(
        path_x=np.arange(frames),
        path_y=np.arange(frames),
        mismatch=mismatch,
        heard_letters=spoken,
        frame_words=frame_words,
        synthetic_speech=spoken,
        recorded_speech=spoken,
        recorded_under_speech=np.where(spoken, 0.0, 40.0),
        lead=0,
        order_ratio=order_ratio,
    )
    warp = TimeWarp(
        synthetic=np.array([0.0, frames / 100]),
        recorded=np.array([0.0, frames / 100]),
        recording_duration=frames / 100,
    )
    return judge(utterance, events, warp, fit, "take.wav")


def test_a_take_fitting_as_another_text_does_is_refused():
    with pytest.raises(AudioError, match="does not read this text"):
        judged([1.95] * 8, order_ratio=0.95)


def test_a_list_whose_best_items_fit_closely_is_warned_not_refused():
    """The same fit as a whole and the same order, but three items fit their letters closely (a list of
    foreign syllables, some spelt far from what is said): the text is read, loosely."""
    _, warnings = judged([0.2] * 3 + [3.0] * 5, order_ratio=0.95)
    assert any("fits this text only loosely" in warning for warning in warnings)


def test_a_close_take_is_clean():
    assert judged([0.3] * 8, order_ratio=0.7)[1] == ()


def test_a_list_is_allowed_a_looser_fit_than_a_sentence():
    """Items read one by one are found between their pauses: the same fit warns a sentence, not a list."""
    fit = [1.4] * 8
    assert judged(fit, order_ratio=0.85)[1] == ()
    sentence = judged(fit, order_ratio=0.85, text="pi tu ba ne rje ko no si")[1]
    assert any("fits this text only loosely" in warning for warning in sentence)


def test_a_list_written_without_commas_is_a_list_where_it_is_read_item_by_item():
    """A list typed with spaces only, read with a clear pause after each item, is judged as the list it is."""
    fit, unpunctuated = [1.4] * 8, "pi tu ba ne rje ko no si"
    assert judged(fit, order_ratio=0.85, text=unpunctuated, gap_frames=40)[1] == ()
    run_on = judged(fit, order_ratio=0.85, text=unpunctuated, gap_frames=10)[1]  # pauses of a sentence
    assert any("fits this text only loosely" in warning for warning in run_on)
