"""A person's take of the text: tempo changing inside a phrase, a hesitation where no comma is, a live
room, a voice in the background, another vocal tract, and all of these at once.

The takes are made here from eSpeak NG's own speech (another variant for the speaker, JSML rate changes
for the tempo) and the measuring script's rooms and hesitations (lab/kit/takes.py); the truth is the
variant's own word onsets, moved with the take.
"""

import numpy as np
import pytest

from lab.kit import takes
from tests.core.test_speech_recording import OTHER_TEXT, other_voice, write_pcm_wav
from turkish_lipsync.core.base.errors import AudioError
from turkish_lipsync.core.motion.natural import viseme_weights
from turkish_lipsync.core.speech import synthesize_timeline
from turkish_lipsync.core.speech.audio import resample
from turkish_lipsync.core.speech.recording import fading
from turkish_lipsync.core.text.utterance import build_utterance

RATE = takes.RATE
# OTHER_TEXT read in three pieces at their own tempo: slow, fast, a little slow (no pause between them).
PIECES = (
    ("Annem sabahları erkenden kalkar", -25),
    ("ve bütün aileye kahvaltı hazırlar.", 35),
    ("Toplantı saat üçte başlayacak, lütfen geç kalmayın.", -10),
)
TALKER_TEXT = "Kütüphaneden aldığım kitabı iki hafta içinde geri vermem gerekiyor."


def take_of(text, variant="tr+m3", pitch=-15, rate=-10) -> takes.Take:
    voice, timeline = other_voice(text, variant, pitch, rate)
    utterance = build_utterance(text)
    return takes.Take(
        voice.astype(np.float64),
        words=np.array([word.start for word in timeline.words]),
        letters=np.array([phone.start for phone in timeline.phones]),
        commas=np.array([word.pause_before > 0 for word in utterance.words]),
    )


def changing_tempo() -> takes.Take:
    """OTHER_TEXT with the tempo changing inside its first sentence (JSML rates per piece)."""
    text = " ".join(f'<PROS RATE="{rate:+d}%">{piece}</PROS>' for piece, rate in PIECES)
    return take_of(text, rate=0)


def written(take: takes.Take, path):
    """The take as a 16-bit WAV at `path`, its peak at 0.8 of full scale."""
    return write_pcm_wav(path, 0.8 * take.samples / np.abs(take.samples).max(), RATE)


def said_aloud(clean: takes.Take, sound: str, shortest=0.7, longest=1.0, before=()) -> takes.Take:
    """The take with one or two hesitations (or one before each word `before`) holding the voice's own
    `sound` ("eeeeee"), 0.05 s of silence either side."""
    said, _ = other_voice(sound, "tr+m3", -15, -10)
    return takes.hesitate(clean, np.random.default_rng(5), shortest, longest, said.astype(np.float64), before)


def aligned(take: takes.Take, tmp_path, text=OTHER_TEXT):
    path = written(take, tmp_path / "take.wav")
    speech = synthesize_timeline(build_utterance(text), recording=path)
    return speech, np.abs(np.array([word.start for word in speech.timeline.words]) - take.words)


def quiet_room(take: takes.Take, snr=40, seed=1) -> takes.Take:
    return takes.add_noise(takes.padded(take, 0.5), snr, "white", np.random.default_rng(seed))


def another_tract(take: takes.Take, semitones=3.0) -> takes.Take:
    """Pitch and formants raised by resampling (played faster as well): a shorter vocal tract."""
    factor = 2 ** (semitones / 12)
    samples = resample(take.samples.astype(np.float32), int(RATE * factor), RATE).astype(np.float64)
    return takes.replace(take, samples=samples, words=take.words / factor, letters=take.letters / factor)


def in_a_live_room(take: takes.Take, seed=2) -> takes.Take:
    """RT60 0.3 s, direct sound as loud as the reverberation (0 dB DRR), as in a furnished living room."""
    return takes.reverberate(
        takes.padded(take, 0.5), takes.room_response(0.3, 0.0, np.random.default_rng(seed))
    )


def with_a_talker(take: takes.Take, below_db=18.0, seed=3) -> takes.Take:
    talker, _ = other_voice(TALKER_TEXT, "tr+m2", -5, 5)
    return takes.background_talker(take, talker.astype(np.float64), below_db, np.random.default_rng(seed))


def test_tempo_that_changes_inside_a_phrase_is_followed(tmp_path):
    speech, error = aligned(quiet_room(changing_tempo()), tmp_path)
    assert np.median(error) < 0.020 and np.percentile(error, 90) < 0.050 and error.max() < 0.100
    assert speech.warnings == ()


def hesitating() -> tuple[takes.Take, np.ndarray]:
    """A take of OTHER_TEXT with hesitations of 0.6-0.8 s, and the words that come after one."""
    clean = take_of(OTHER_TEXT)
    take = takes.hesitate(clean, np.random.default_rng(5), shortest=0.6, longest=0.8)
    return take, np.flatnonzero(np.diff(take.words) - np.diff(clean.words) > 0.5) + 1


def test_a_hesitation_where_the_text_has_no_comma_keeps_the_next_word_after_it(tmp_path):
    take, held = hesitating()
    assert held.size >= 1 and not take.commas[held].any()  # hesitations where the text has no pause
    speech, error = aligned(quiet_room(take), tmp_path)
    assert error[held].max() < 0.050  # the word after the hesitation starts when it is said, not before
    assert np.median(error) < 0.020 and error.max() < 0.100
    assert speech.warnings == ()


@pytest.mark.parametrize("sound", ["ıııııı", "eeeeee"])
def test_a_hesitation_said_aloud_draws_no_word_into_it(tmp_path, sound):
    """A person's "ııı" or "eee" between two words is a pause, not a stretch of the words around it: the
    word after it used to start in it or before it, up to a second early, and the take was warned. The
    mouth says it: the timeline holds it, and the face shapes its vowel through it (it rested)."""
    clean = take_of(OTHER_TEXT)
    take = said_aloud(clean, sound)
    held = np.flatnonzero(np.diff(take.words) - np.diff(clean.words) > 0.5) + 1
    assert held.size >= 1
    taken = quiet_room(take)
    speech, error = aligned(taken, tmp_path)
    assert error[held].max() < 0.050  # the word after the hesitation starts when it is said
    assert np.median(error) < 0.020 and error.max() < 0.100
    assert speech.warnings == ()
    timeline = speech.timeline
    assert {h.sound for h in timeline.hesitations} == {sound[0]}
    # One in each pause that holds one, over most of its held sound (0.1 s of it silent margins).
    for word in held:
        within = [h for h in timeline.hesitations if taken.words[word] - 1.1 < h.start < taken.words[word]]
        assert (
            sum(h.end - h.start for h in within)
            > np.diff(take.words)[word - 1] - np.diff(clean.words)[word - 1] - 0.3
        )
    assert len(timeline.hesitations) <= 2 * held.size
    fps = 25
    visemes, weights, _ = viseme_weights(timeline, fps, int(timeline.duration * fps) + 1)
    for hesitation in timeline.hesitations:
        middle = round((hesitation.start + hesitation.end) / 2 * fps)
        assert visemes[weights[middle].argmax()] == hesitation.viseme


def test_a_live_room_is_aligned_without_a_warning(tmp_path):
    speech, error = aligned(
        takes.add_noise(in_a_live_room(take_of(OTHER_TEXT)), 50, "white", np.random.default_rng(4)), tmp_path
    )
    assert np.median(error) < 0.020 and np.percentile(error, 90) < 0.050 and error.max() < 0.150
    assert speech.warnings == ()


COMMA_TEXT = "Bilgisayarım çok yavaşladı, sanırım yeni bir tane almam gerekecek."


@pytest.mark.parametrize("seed", [0, 3])
def test_the_word_after_a_comma_is_not_keyed_into_the_rooms_tail(tmp_path, seed):
    """In a reverberant room the speech detector takes the tail of "yavaşladı" for speech: the first
    letter of "sanırım" used to be drawn into it, 150-190 ms early."""
    voice, timeline = other_voice(COMMA_TEXT, "tr+m5", -30, 15)
    take = takes.Take(
        voice.astype(np.float64),
        words=np.array([word.start for word in timeline.words]),
        letters=np.zeros(0),
        commas=np.array([word.pause_before > 0 for word in build_utterance(COMMA_TEXT).words]),
    )
    rng = np.random.default_rng(seed)
    room = takes.reverberate(takes.padded(take, 0.3), takes.plain_room_response(0.5, rng))
    speech, error = aligned(takes.add_noise(room, 40, "white", rng), tmp_path, text=COMMA_TEXT)
    assert error[3] < 0.050 and error.max() < 0.100
    assert speech.warnings == ()


def test_a_sound_dying_away_is_told_from_the_next_ones_onset():
    """Levels under the speaker's loud frames (dB): a word, its tail falling past 30 dB (a wobble of half a
    dB is still the tail), the next word's rise; a word, its fall to the floor, a quiet sound rising out
    of it (not a fade, nor its own end); a last word fading out."""
    word_and_tail, next_word = [0, 2, 8, 14, 16, 20, 25, 30, 31, 30.5], [27, 20, 10, 0]
    to_the_floor, quiet_sound, last_word = [18, 26, 35, 35], [24, 22, 24, 30], [0, 12, 18, 24]
    under = word_and_tail + next_word + to_the_floor + quiet_sound + last_word
    assert np.flatnonzero(fading(np.array(under))).tolist() == [4, 5, 6, 7, 8, 9, 14, 15, 16, 17, 24, 25]
    assert not fading(np.array([0, 3, 6, 9, 12, 9, 3, 0])).any()  # never 15 dB under: nothing dies away
    assert not fading(np.array([20, 25, 30, 25])).any()  # under from the start: no fall past the mark


def test_a_voice_in_the_background_is_not_followed(tmp_path):
    speech, error = aligned(quiet_room(with_a_talker(take_of(OTHER_TEXT)), snr=30), tmp_path)
    assert np.median(error) < 0.020 and np.percentile(error, 90) < 0.050 and error.max() < 0.100
    assert speech.warnings == ()


def test_a_hesitation_filled_by_a_voice_in_the_background_is_held(tmp_path):
    """The voice activity detector hears the other voice in the pause: the pause is told by its level."""
    take, held = hesitating()
    assert held.size >= 1
    speech, error = aligned(quiet_room(with_a_talker(take, seed=4), snr=60), tmp_path)
    assert error[held].max() < 0.050  # the word after the hesitation starts when it is said
    assert np.median(error) < 0.020 and error.max() < 0.100
    assert speech.warnings == ()


def test_a_shorter_vocal_tract_is_aligned(tmp_path):
    speech, error = aligned(quiet_room(another_tract(take_of(OTHER_TEXT, "tr+f3", 20, -10))), tmp_path)
    assert np.median(error) < 0.020 and np.percentile(error, 90) < 0.050 and error.max() < 0.100
    assert speech.warnings == ()


def person(seed=7) -> takes.Take:
    """All of it at once: changing tempo, another tract, a hesitation, a live room, a talker, 25 dB SNR."""
    rng = np.random.default_rng(seed)
    take = takes.hesitate(another_tract(changing_tempo(), 2.0), rng)
    return takes.add_noise(with_a_talker(in_a_live_room(take)), 25, "pink", rng)


def test_a_persons_take_is_aligned_and_not_refused(tmp_path):
    speech, error = aligned(person(), tmp_path)
    assert np.median(error) < 0.030 and np.percentile(error, 90) < 0.070 and error.max() < 0.200
    assert speech.warnings == ()


def test_a_persons_take_of_another_text_is_still_refused(tmp_path):
    other = "Kardeşim dün akşam bana uzun bir mektup yazdı. Sonbaharda yapraklar sararır ve ağaçlardan düşer."
    with pytest.raises(AudioError, match="does not read this text"):
        aligned(person(), tmp_path, text=other)


@pytest.mark.parametrize(
    ("text", "word"),
    [
        ("Akşamları balkonda oturup yıldızları izlemeyi severim.", 1),
        ("Hasta olduğum için bugün işe gidemedim.", 3),
    ],
)
def test_an_eee_drawn_into_the_next_words_first_consonant_is_taken_out_of_it(tmp_path, text, word):
    """ "Akşamları eee balkonda": the first alignment, which fits with no warning, draws the "eee" into the
    b of "balkonda" (the lips closed for 0.8 s, the word 0.75 s early); a vowel heard so long in a
    consonant has the take aligned again with pauses that may hold a hesitation, and the word starts
    when it is said."""
    take = said_aloud(take_of(text), "eeeeee", 0.8, 0.8, before=(word,))
    speech, error = aligned(quiet_room(take), tmp_path, text)
    assert error[word] < 0.050 and error.max() < 0.100 and speech.warnings == ()
    assert [h.sound for h in speech.timeline.hesitations] == ["e"]
    b = next(phone for phone in speech.timeline.phones if phone.word_index == word)
    assert b.letter == "b" and b.end - b.start < 0.2


def test_an_eee_drawn_into_a_vowel_inside_the_next_word_is_taken_out_of_it(tmp_path):
    """ "... kuruluşunu eee öğrendik": the first alignment, which fits with no warning, draws the "eee" into
    the e inside "öğrendik" (its ö and r a frame or two at the hesitation's start, the word 0.77 s early);
    a vowel inside a word beside an unmarked pause held for a hesitation's length has the take aligned
    again, with the pause free to hold the e (the r parts it from the word's e), and the word starts when
    it is said."""
    text = "Tarih dersinde Osmanlı İmparatorluğu'nun kuruluşunu öğrendik."
    take = said_aloud(take_of(text), "eeeeee", 0.8, 0.8, before=(5,))
    speech, error = aligned(quiet_room(take), tmp_path, text)
    assert error[5] < 0.050 and error.max() < 0.100 and speech.warnings == ()
    assert [h.sound for h in speech.timeline.hesitations] == ["e"]
    e = [phone for phone in speech.timeline.phones if phone.word_index == 5 and phone.letter == "e"]
    assert len(e) == 1 and e[0].end - e[0].start < 0.3


def test_a_stop_after_a_hesitation_said_aloud_starts_at_its_closure(tmp_path):
    """ "Çocuklar bahçede eee top ...": the e "bahçede" ends on holds the hesitation (as its own, drawn out),
    and the closure of the t after it was measured on that e's stretch, 0.15 s: "top" keyed 0.1 s early.
    Now a closure after a vowel drawn out past a person's closures keeps the stop's word's pace."""
    text = "Çocuklar bahçede top oynarken komşunun kedisi ağaca tırmandı."
    take = said_aloud(take_of(text), "eeeeee", 0.8, 0.8, before=(2,))
    speech, error = aligned(quiet_room(take), tmp_path, text)
    assert error[2] < 0.030 and error.max() < 0.100 and speech.warnings == ()
