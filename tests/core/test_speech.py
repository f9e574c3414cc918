"""eSpeak NG's Turkish voice, the phone-level timeline and the thesis's word timing (real engine)."""

import ctypes.util
import subprocess
import sys
import wave
from pathlib import Path

import numpy as np
import pytest

from turkish_lipsync.core.base.errors import LipSyncError, SpeechEngineError, TextError
from turkish_lipsync.core.base.model import Style
from turkish_lipsync.core.speech import (
    Synthesis,
    engine_names,
    get_engine,
    synthesize_timeline,
    write_wav,
)
from turkish_lipsync.core.speech.espeak import DEFAULT_RATE, _parameters
from turkish_lipsync.core.speech.timing import letter_durations, table_timeline
from turkish_lipsync.core.text.utterance import build_utterance

REPOSITORY = Path(__file__).resolve().parents[2]

# Held out: none of these sentences was used while building the letter-to-phone table.
HELD_OUT = (
    "Kardeşim dün akşam bana uzun bir mektup yazdı.",
    "Sonbaharda yapraklar sararır ve ağaçlardan düşer.",
    "Öğrenciler sınavdan önce kütüphanede çalıştılar.",
    "Bu yıl yaz tatilinde Karadeniz kıyılarını gezeceğiz.",
    "Saat dokuzu çeyrek geçe otobüs durağında buluşalım.",
    "Teyzemin bahçesindeki domatesler kıpkırmızı olmuş.",
    "Lütfen kapıyı kapatır mısınız, içerisi çok soğuk.",
    "Gökyüzünde bir kuş sürüsü güneye doğru uçuyordu.",
)


@pytest.fixture(scope="module")
def spoken():
    """Every held-out sentence as (utterance, timeline, synthesis) in phone timing."""
    results = []
    for text in HELD_OUT:
        utterance = build_utterance(text)
        speech = synthesize_timeline(utterance)
        timeline, synthesis = speech.timeline, speech.synthesis
        results.append((utterance, timeline, synthesis))
    return results


def test_engines_are_registered_by_name_and_made_once():
    assert "espeak" in engine_names()
    assert get_engine("espeak") is get_engine("espeak")
    with pytest.raises(SpeechEngineError, match="unknown speech engine 'festival'.*espeak"):
        get_engine("festival")


def test_a_missing_engine_says_how_to_install_it():
    if ctypes.util.find_library("espeak-ng"):
        pytest.skip("a system libespeak-ng is installed, so the engine is never missing here")
    # A fresh process (this one has the library loaded already), as if the wheel were not installed.
    program = (
        "import sys; sys.modules['espeakng_loader'] = None\n"
        "from turkish_lipsync.core.speech import synthesize_timeline\n"
        "from turkish_lipsync.core.text.utterance import build_utterance\n"
        "synthesize_timeline(build_utterance('merhaba'))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", program], cwd=REPOSITORY, capture_output=True, text=True, timeout=60
    )
    assert result.returncode != 0
    assert "SpeechEngineError" in result.stderr
    assert "pip install espeakng-loader" in result.stderr and "apt install libespeak-ng1" in result.stderr


def test_a_wrong_library_path_fails_clearly_and_a_corrected_one_works_without_a_restart(tmp_path):
    # A fresh process: the engine must not have started yet when the wrong path is chosen.
    program = (
        "import sys\n"
        "from turkish_lipsync.core.base.errors import SpeechEngineError\n"
        "from turkish_lipsync.core.speech import espeak, get_engine\n"
        "from turkish_lipsync.core.text.utterance import build_utterance\n"
        "engine = get_engine('espeak')\n"
        f"espeak.choose_library({str(tmp_path / 'libespeak-ng.so')!r})\n"
        "assert not engine.is_available()\n"
        "try:\n"
        "    engine.synthesize(build_utterance('merhaba'))\n"
        "except SpeechEngineError as error:\n"
        "    print('FAILED:', error)\n"
        "espeak.choose_library(None)\n"
        "assert engine.is_available()\n"
        "print('VERSION:', engine.version())\n"
        "print('SPOKEN:', engine.synthesize(build_utterance('merhaba')).duration > 0.2)\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", program], cwd=REPOSITORY, capture_output=True, text=True, timeout=60
    )
    assert result.returncode == 0, result.stderr
    assert "FAILED:" in result.stdout and "chosen in the preferences" in result.stdout
    assert "VERSION: eSpeak NG 1." in result.stdout and "SPOKEN: True" in result.stdout


def test_letters_stay_in_order_with_positive_spans(spoken):
    for utterance, timeline, synthesis in spoken:
        starts = np.array([phone.start for phone in timeline.phones])
        ends = np.array([phone.end for phone in timeline.phones])
        assert np.all(np.diff(starts) > 0), utterance.source
        assert np.all(ends > starts), utterance.source
        assert ends.max() <= timeline.duration == pytest.approx(synthesis.duration)
        assert timeline.timing == "phone"
        assert timeline.engine_onsets == tuple(event.start for event in synthesis.phone_events)


def test_the_engine_speaks_exactly_the_normalised_words():
    utterance = build_utterance("Dr. Ali 3 kitap ve 25 kalem aldı.")
    synthesis = synthesize_timeline(utterance).synthesis
    spoken_words = {event.word_index for event in synthesis.phone_events}
    assert spoken_words == set(range(len(utterance.words)))
    engine = get_engine("espeak")
    symbols = engine.letter_symbols()
    matched = sum(
        engine.bare_symbol(event.symbol) in symbols[utterance.letters[letter].char]
        for event in synthesis.phone_events
        for letter in event.letters[:1]
    )
    assert matched >= 0.9 * len(utterance.letters)  # "üç", "yirmi beş", "doktor" were spoken as written


@pytest.mark.parametrize(
    ("word", "dropped"),
    [("dağ", 2), ("yağmur", 2), ("soğuk", 2), ("öğle", 1)],
)
def test_a_silent_soft_g_gets_a_short_span_at_the_end_of_the_vowel_before_it(word, dropped):
    utterance = build_utterance(word)
    speech = synthesize_timeline(utterance)
    timeline, synthesis = speech.timeline, speech.synthesis
    soft_g, vowel = timeline.phones[dropped], timeline.phones[dropped - 1]
    assert soft_g.letter == "ğ"
    assert not any(dropped in event.letters for event in synthesis.phone_events)
    vowel_phone = next(event for event in synthesis.phone_events if dropped - 1 in event.letters)
    assert vowel.start == vowel_phone.start < vowel.end == soft_g.start < soft_g.end == vowel_phone.end
    assert soft_g.end - soft_g.start < vowel.end - vowel.start


@pytest.mark.parametrize("word", ["anne", "elli", "sıhhat", "tahta", "kahve", "saat", "dikkat"])
def test_geminates_and_h_between_vowels_keep_every_letter_in_order(word):
    utterance = build_utterance(word)
    timeline = synthesize_timeline(utterance).timeline
    assert "".join(phone.letter for phone in timeline.phones) == word
    for before, after in zip(timeline.phones, timeline.phones[1:], strict=False):
        assert before.start < after.start and before.end <= after.start + 1e-9
        assert after.end > after.start


def test_the_default_speaking_rate_is_espeaks_175_words_per_minute():
    assert DEFAULT_RATE == 175 and _parameters(Style()) == (175, 50, 50, 100)
    plain = synthesize_timeline(build_utterance("Yarın sabah erkenden yola çıkacağız.")).synthesis
    explicit = synthesize_timeline(
        build_utterance('<PROS RATE="175">Yarın sabah erkenden yola çıkacağız.</PROS>')
    ).synthesis
    # eSpeak NG varies a few samples between runs (its noise source), so compare timing, not samples.
    assert explicit.duration == pytest.approx(plain.duration, abs=0.005)
    onsets = [[event.start for event in synthesis.phone_events] for synthesis in (plain, explicit)]
    assert np.allclose(onsets[0], onsets[1], atol=0.002)


def test_prosody_rate_and_pitch_change_the_voice():
    text = "Yarın sabah erkenden yola çıkacağız."
    normal = synthesize_timeline(build_utterance(text)).synthesis
    slow = synthesize_timeline(build_utterance(f'<PROS RATE="-40%">{text}</PROS>')).synthesis
    high = synthesize_timeline(build_utterance(f'<PROS PITCH="+40%">{text}</PROS>')).synthesis
    assert slow.duration > 1.4 * normal.duration
    assert median_pitch(high) > 1.15 * median_pitch(normal)


def median_pitch(synthesis: Synthesis) -> float:
    """Median fundamental frequency (Hz) of the loud 40 ms frames, by autocorrelation."""
    rate = synthesis.sample_rate
    size = int(0.04 * rate)
    samples = synthesis.samples.astype(np.float64)
    frames = samples[: samples.size // size * size].reshape(-1, size)
    loud = frames[np.sqrt((frames**2).mean(axis=1)) > 0.3 * np.sqrt((frames**2).mean(axis=1)).max()]
    lags = np.arange(int(rate / 400), int(rate / 60))
    pitches = []
    for frame in loud:
        frame = frame - frame.mean()
        correlation = np.array([np.dot(frame[:-lag], frame[lag:]) for lag in lags])
        pitches.append(rate / lags[np.argmax(correlation)])
    return float(np.median(pitches))


def test_breaks_and_punctuation_are_exact_silence_between_words():
    utterance = build_utterance('<JSML>Bir <BREAK MSECS="700"/> iki, üç.</JSML>')
    speech = synthesize_timeline(utterance)
    timeline, synthesis = speech.timeline, speech.synthesis
    first, second = timeline.words[0], timeline.words[1]
    assert utterance.words[1].pause_before >= 0.7
    gap = synthesis.samples[
        int(first.end * synthesis.sample_rate) + 50 : int(second.start * synthesis.sample_rate)
    ]
    assert second.start - first.end >= 0.7
    assert np.count_nonzero(gap == 0) >= 0.7 * synthesis.sample_rate
    assert timeline.duration >= timeline.words[-1].end + utterance.final_pause - 1e-6


def test_a_voiceless_stop_begins_where_its_closure_falls_silent_not_at_its_burst():
    """eSpeak NG reports p, t, k and ç at the burst; the silence before belongs to the stop (the lips of
    the p in "kapı" are shut through it), and a stop that begins the speech after a pause keeps its burst."""
    speech = synthesize_timeline(build_utterance("Kapı açık, tepe."))
    timeline, synthesis = speech.timeline, speech.synthesis
    rate = synthesis.sample_rate
    samples = synthesis.samples.astype(np.float64)
    loud = np.sqrt(np.mean(samples**2))

    def level(start: float, stop: float) -> float:
        return float(np.sqrt(np.mean(samples[int(start * rate) : int(stop * rate)] ** 2)))

    letters = {(phone.word_index, phone.letter): phone for phone in timeline.phones}
    for word_index, letter in ((0, "p"), (1, "k"), (1, "ç")):
        phone = letters[(word_index, letter)]
        assert level(phone.start + 0.005, phone.start + 0.02) < loud / 100, letter  # its closure
        assert level(phone.start - 0.01, phone.start) > loud / 30, letter  # the vowel before, sounding
        assert timeline.phones[phone.letter_index - 1].end <= phone.start + 1e-9
    # "tepe" follows a comma's pause: its t starts the sound, at the burst.
    first = letters[(2, "t")]
    assert level(first.start - 0.02, first.start - 0.001) == 0
    assert level(first.start, first.start + 0.02) > loud / 100


def test_an_emphasised_word_is_spoken_longer():
    plain = synthesize_timeline(build_utterance("Bu kitap gerçekten güzel.")).timeline
    emphasised = synthesize_timeline(build_utterance("Bu kitap <EMP>gerçekten</EMP> güzel.")).timeline
    length = [timeline.words[2].end - timeline.words[2].start for timeline in (plain, emphasised)]
    assert length[1] > 1.05 * length[0]
    assert emphasised.emphases == ((emphasised.words[2].start, emphasised.words[2].end),)


def test_word_timing_is_the_thesis_word_start_events_with_table_durations_inside(spoken):
    for utterance, _, _ in spoken[:4]:
        speech = synthesize_timeline(utterance, "word")
        timeline, synthesis = speech.timeline, speech.synthesis
        assert timeline.timing == "word"
        durations = letter_durations(utterance)
        events = {event.word_index: event.start for event in synthesis.word_events}
        previous_end = 0.0
        for index, word in enumerate(utterance.words):
            phones = timeline.phones[word.first_letter : word.first_letter + word.letter_count]
            # The thesis waits for the word's start event (and for the previous word to finish).
            assert phones[0].start == pytest.approx(max(events[index], previous_end))
            for phone in phones:
                assert phone.end - phone.start == pytest.approx(durations[phone.letter_index])
            for before, after in zip(phones, phones[1:], strict=False):
                assert after.start == pytest.approx(before.end)
            previous_end = phones[-1].end


def test_table_timing_needs_no_engine_and_returns_no_audio():
    utterance = build_utterance("Merhaba dünya.")
    speech = synthesize_timeline(utterance, "table")
    timeline, synthesis = speech.timeline, speech.synthesis
    assert synthesis is None
    assert timeline == table_timeline(utterance)


def test_unknown_timing_and_table_with_a_recording_are_refused(tmp_path):
    utterance = build_utterance("Merhaba.")
    with pytest.raises(LipSyncError, match="unknown timing 'syllable'"):
        synthesize_timeline(utterance, "syllable")
    with pytest.raises(LipSyncError, match="Table timing .* cannot follow a recording"):
        synthesize_timeline(utterance, "table", recording=tmp_path / "me.wav")


def test_write_wav_writes_mono_16_bit_pcm(tmp_path, spoken):
    synthesis = spoken[0][2]
    path = write_wav(tmp_path / "speech.wav", synthesis)
    with wave.open(str(path), "rb") as handle:
        assert (handle.getnchannels(), handle.getsampwidth(), handle.getframerate()) == (
            1,
            2,
            synthesis.sample_rate,
        )
        samples = np.frombuffer(handle.readframes(handle.getnframes()), "<i2")
    assert np.array_equal(samples, synthesis.samples)


def test_a_phone_spoken_without_duration_gets_a_span_like_a_dropped_letter():
    # eSpeak NG reports the dark l of "nasılsın" with no duration, at the onset of the s after it.
    utterance = build_utterance("nasılsın")
    speech = synthesize_timeline(utterance)
    timeline, synthesis = speech.timeline, speech.synthesis
    vowel, l_sound, s_sound = timeline.phones[3:6]
    assert (vowel.letter, l_sound.letter, s_sound.letter) == ("ı", "l", "s")
    vowel_phone = next(event for event in synthesis.phone_events if 3 in event.letters)
    assert vowel.start == vowel_phone.start < l_sound.start < l_sound.end == vowel_phone.end <= s_sound.start
    assert l_sound.end - l_sound.start >= 0.005


def test_a_question_is_spoken_as_a_question():
    """The written '?' reaches the voice: the pitch rises at the end of a question and falls after a '.'."""
    question = build_utterance("Yarın geliyor musun?")
    statement = build_utterance("Yarın geliyor musun.")
    assert question.words[-1].ending == "?" and statement.words[-1].ending == "."

    def final_rise(synthesis):
        """Pitch of the last voiced 90 ms over the pitch 90 ms before that (autocorrelation, 30 ms frames)."""
        samples = synthesis.samples.astype(np.float64)
        rate = synthesis.sample_rate
        frame = int(0.03 * rate)
        pitches = []
        for start in range(0, len(samples) - frame, frame):
            piece = samples[start : start + frame] - samples[start : start + frame].mean()
            if np.sum(piece**2) < 1e6:
                continue
            correlation = np.correlate(piece, piece, "full")[frame - 1 :]
            low, high = int(rate / 350), int(rate / 60)
            pitches.append(rate / (low + int(np.argmax(correlation[low:high]))))
        return np.median(pitches[-3:]) / np.median(pitches[-6:-3])

    asked = synthesize_timeline(question, "phone").synthesis
    told = synthesize_timeline(statement, "phone").synthesis
    assert final_rise(asked) > 1.05 > 1.0 > final_rise(told)


def test_a_text_too_long_to_hold_as_audio_is_refused_before_speaking():
    from turkish_lipsync.core.speech.timeline import MAX_SPOKEN_LETTERS

    words = MAX_SPOKEN_LETTERS // 5 + 1
    utterance = build_utterance(" ".join(["kalem"] * words))
    with pytest.raises(TextError, match="split it into several texts"):
        synthesize_timeline(utterance, "phone")
    assert table_timeline(utterance).phones[-1].letter == "m"  # table timing needs no audio: still fine
