"""The judgement's rules on a take's fit built frame by frame: another text refused, a list of foreign
syllables read with its own text warned."""

import numpy as np
import pytest

from turkish_lipsync.core.base.errors import AudioError
from turkish_lipsync.core.speech.base import PhoneEvent
from turkish_lipsync.core.speech.judgement import Fit, judge, pauses_read_as_list
from turkish_lipsync.core.speech.timewarp import TimeWarp
from turkish_lipsync.core.text.utterance import build_utterance, read_aloud

LIST = "pi, tu, ba, ne, rje, ko, no, si"
WORD_FRAMES, GAP_FRAMES = 30, 10  # each item 0.3 s, 0.1 s of pause after it (10 ms frames)


def judged(word_mismatch: list[float], order_ratio: float, text: str = LIST, gap_frames: int = GAP_FRAMES):
    """judge() on a take of `text` (eight words) whose words fit their letters with these mismatches, each
    word 0.3 s and a pause of gap_frames after it."""
    return judge(*take_of(word_mismatch, order_ratio, text, gap_frames), "take.wav")


def take_of(word_mismatch: list[float], order_ratio: float, text: str, gap_frames: int | list[int]):
    """(utterance, phone events, warp, fit) of such a take (gap_frames: one for all words, or each word's)."""
    utterance = build_utterance(text)
    gaps = gap_frames if isinstance(gap_frames, list) else [gap_frames] * len(utterance.words)
    starts = np.concatenate(([0], np.cumsum([WORD_FRAMES + gap for gap in gaps])))
    frames = int(starts[-1])
    frame_words = np.full(frames, -1)
    mismatch = np.zeros(frames)
    for index, value in enumerate(word_mismatch):
        frame_words[starts[index] : starts[index] + WORD_FRAMES] = index
        mismatch[starts[index] : starts[index] + WORD_FRAMES] = value
    spoken = frame_words >= 0
    events = tuple(
        PhoneEvent(starts[index] / 100, (starts[index] + WORD_FRAMES) / 100, "a", index)
        for index in range(len(utterance.words))
    )
    fit = Fit(
        path_x=np.arange(frames),
        path_y=np.arange(frames),
        mismatch=mismatch,
        heard_letters=spoken,
        frame_words=frame_words,
        hesitations=np.full(frames, -1),  # no hesitation said aloud
        synthetic_speech=spoken,
        recorded_speech=spoken,
        recorded_under_speech=np.where(spoken, 0.0, 40.0),
        lead=0,
        order_ratio=order_ratio,
        hesitation_drawn_in=np.zeros(len(utterance.words), np.int64),
    )
    warp = TimeWarp(
        synthetic=np.array([0.0, frames / 100]),
        recorded=np.array([0.0, frames / 100]),
        recording_duration=frames / 100,
    )
    return utterance, events, warp, fit


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


def test_a_list_typed_without_commas_and_read_item_by_item_is_read_aloud_with_its_pauses():
    """The recording aligner aligns such a take again with a pause before each item (recording.py)."""
    unpunctuated = "pi tu ba ne rje ko no si"
    utterance, events, warp, _ = take_of([0.3] * 8, 0.7, unpunctuated, gap_frames=40)
    pauses = pauses_read_as_list(utterance, events, warp)
    assert pauses == set(range(1, 8))
    as_read = read_aloud(utterance, pauses)
    assert [word.pause_before for word in as_read.words] == [
        word.pause_before for word in build_utterance(LIST).words
    ]
    # Read as a sentence is (pauses of 0.1 s), or a list its commas already pause: nothing to add.
    assert pauses_read_as_list(*take_of([0.3] * 8, 0.7, unpunctuated, gap_frames=10)[:3]) == set()
    assert pauses_read_as_list(*take_of([0.3] * 8, 0.7, LIST, gap_frames=40)[:3]) == set()
    # Pauses that leave a phrase of three words make no list: a sentence read with a few hesitations.
    hesitant = [40, 40, 40, 40, 40, 10, 10, 40]  # no pause after "ko" and "no"
    assert pauses_read_as_list(*take_of([0.3] * 8, 0.7, unpunctuated, gap_frames=hesitant)[:3]) == set()
    two_words = [40, 40, 40, 40, 40, 10, 40, 40]  # "ko no" one item
    assert pauses_read_as_list(*take_of([0.3] * 8, 0.7, unpunctuated, gap_frames=two_words)[:3]) == {
        1,
        2,
        3,
        4,
        5,
        7,
    }
