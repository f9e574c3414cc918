"""The Timeline's own operations: every time it holds moved together, timelines joined into one."""

import pytest

from turkish_lipsync.core.base.model import EmotionSpan, Hesitation, Phone, Timeline, WordSpan


def line(start: float, text: str = "ab", timing: str = "phone") -> Timeline:
    """A two-letter word from `start`, 0.1 s a letter, with an emotion, an emphasis, engine onsets and an
    "ııı" said after it."""
    phones = tuple(
        Phone(start + 0.1 * n, start + 0.1 * (n + 1), n, letter, text, 0, "a")
        for n, letter in enumerate(text)
    )
    return Timeline(
        phones=phones,
        words=(WordSpan(start, start + 0.2, 0, text),),
        emotions=(EmotionSpan(start, start + 0.2, "happy", 1.0),),
        emphases=((start, start + 0.2),),
        duration=start + 0.5,
        timing=timing,
        engine_onsets=(start, start + 0.1),
        hesitations=(Hesitation(start + 0.25, start + 0.45, "ı", "I"),),
    )


def every_time(timeline: Timeline) -> list[float]:
    times = [t for p in timeline.phones for t in (p.start, p.end)]
    times += [t for w in timeline.words for t in (w.start, w.end)]
    times += [t for e in timeline.emotions for t in (e.start, e.end)]
    times += [t for span in timeline.emphases for t in span]
    times += [t for h in timeline.hesitations for t in (h.start, h.end)]
    return times + list(timeline.engine_onsets)


def test_shifted_moves_every_time_and_takes_the_new_duration():
    original = line(0.0)
    moved = original.shifted(2.0, 10.0)
    assert every_time(moved) == pytest.approx([t + 2.0 for t in every_time(original)])
    assert moved.duration == 10.0 and moved.timing == "phone"
    assert [p.letter for p in moved.phones] == ["a", "b"] and moved.words[0].text == "ab"


def test_remapped_moves_only_what_lies_between_the_knots():
    original = line(1.0)  # times 1.0 .. 1.2
    remapped = original.remapped((1.0, 1.1), (0.8, 1.1))  # 1.0 -> 0.8, 1.05 -> 0.95, 1.1 stays
    assert [p.start for p in remapped.phones] == pytest.approx([0.8, 1.1])
    assert [p.end for p in remapped.phones] == pytest.approx([1.1, 1.2])  # 1.2 lies past the knots: kept
    assert remapped.engine_onsets == pytest.approx((0.8, 1.1))
    assert remapped.duration == original.duration


def test_retimed_maps_every_time_by_any_function():
    original = line(0.5)
    doubled = original.retimed(lambda time: 2 * time)
    assert every_time(doubled) == pytest.approx([2 * t for t in every_time(original)])


def test_joined_numbers_words_and_letters_on_and_keeps_the_first_timing():
    first, second = line(0.0, "ab", "recording"), line(1.0, "cde", "phone")
    joined = Timeline.joined([first, second], 3.0)
    assert [(p.letter, p.letter_index, p.word_index) for p in joined.phones] == [
        ("a", 0, 0),
        ("b", 1, 0),
        ("c", 2, 1),
        ("d", 3, 1),
        ("e", 4, 1),
    ]
    assert [w.index for w in joined.words] == [0, 1]
    assert len(joined.emotions) == 2 and len(joined.emphases) == 2
    assert joined.engine_onsets == (0.0, 0.1, 1.0, 1.1)
    assert [h.start for h in joined.hesitations] == [0.25, 1.25]
    assert joined.duration == 3.0 and joined.timing == "recording"
    assert Timeline.joined([first], 1.0, timing="scene").timing == "scene"
    assert Timeline.joined([], 1.0).phones == ()
