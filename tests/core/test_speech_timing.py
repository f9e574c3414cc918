import numpy as np
import pytest

from turkish_lipsync.core.speech.timing import duration_table, letter_durations, table_timeline
from turkish_lipsync.core.text.utterance import build_utterance


def durations_ms(text):
    return dict(enumerate(np.round(letter_durations(build_utterance(text)) * 1000, 3)))


def test_table_5_4_durations_for_merhaba():
    # m 68, e 50, r 55, h 58, a 55, b 66, a 55 ms: the thesis's "Duration that we used".
    assert list(durations_ms("merhaba").values()) == [68, 50, 55, 58, 55, 66, 55]


def test_soft_g_lengthens_the_vowel_before_it():
    durations = durations_ms("dağ")
    assert durations[1] == 92  # AG*: the a of dağ is the lengthened a
    assert durations[2] == duration_table().soft_g_after_vowel * 1000


def test_double_consonants_last_longer_than_one_and_shorter_than_two():
    anne = durations_ms("anne")
    ane = durations_ms("ane")
    assert ane[1] < anne[1] + anne[2] < 2 * ane[1]
    assert anne[1] == anne[2]


def test_speaking_rate_scales_every_duration():
    normal = letter_durations(build_utterance("kalem"))
    fast = letter_durations(build_utterance('<PROS RATE="+100%">kalem</PROS>'))
    np.testing.assert_allclose(fast, normal / 2)


def test_table_timeline_is_contiguous_inside_words_and_pauses_at_punctuation():
    timeline = table_timeline(build_utterance("Merhaba, benim adım Erdem."))
    phones = timeline.phones
    assert len(phones) == 21
    for word in timeline.words:
        inside = [p for p in phones if p.word_index == word.index]
        for before, after in zip(inside, inside[1:], strict=False):
            assert after.start == pytest.approx(before.end)
    gap_after_comma = timeline.words[1].start - timeline.words[0].end
    gap_between_words = timeline.words[2].start - timeline.words[1].end
    assert gap_after_comma > gap_between_words >= 0
    assert timeline.duration > phones[-1].end  # the sentence-final pause


def test_break_adds_its_silence():
    plain = table_timeline(build_utterance("bir iki"))
    broken = table_timeline(build_utterance('bir <BREAK MSECS="500"/> iki'))
    extra = (broken.words[1].start - broken.words[0].end) - (plain.words[1].start - plain.words[0].end)
    assert extra == pytest.approx(0.5, abs=1e-6)


def test_emotion_spans_cover_their_words_and_merge_consecutive_words():
    timeline = table_timeline(build_utterance("<HAPPY>çok güzel</HAPPY> bir <SAD WEIGHT='0.5'>gün</SAD>"))
    happy, sad = timeline.emotions
    assert (happy.emotion, happy.start, happy.end) == (
        "happy",
        timeline.words[0].start,
        timeline.words[1].end,
    )
    assert (sad.emotion, sad.weight) == ("sad", 0.5)
    assert sad.start == timeline.words[3].start
