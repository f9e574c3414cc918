"""Lip sync from the audio alone: held-out voices and sentences made in the test, and the bad takes.

The takes are eSpeak NG variants the network never heard (the weights' own list says so) reading held-out
sentences of examples/corpus_tr.txt, with room noise and noise before the first word, as in
lab/measure/recogniser.py; the truth is the variant's own phone events.
"""

import difflib

import numpy as np
import pytest

from lab.kit.corpus import held_out_sentences
from lab.kit.degradations import coloured_noise, music
from lab.kit.scores import bilabial_scores, correlation, loudness_envelope, opening_trajectory
from lab.kit.takes import RATE, write_wav
from lab.kit.voices import TEST_VOICES, make_take, speak_language, speak_variant
from turkish_lipsync.core.base.errors import AudioError
from turkish_lipsync.core.base.visemes import BILABIAL_VISEMES, VOWEL_VISEMES
from turkish_lipsync.core.speech.acoustic.features import FEATURE_COUNT
from turkish_lipsync.core.speech.acoustic.labels import CLASSES
from turkish_lipsync.core.speech.acoustic.network import load_network
from turkish_lipsync.core.speech.recognition import speech_from_audio
from turkish_lipsync.core.speech.recognition.decoder import decode

VOICES = ("m3", "Andrea", "klatt3")


@pytest.fixture(scope="module")
def takes(tmp_path_factory):
    """Four held-out sentences in three held-out voices, 30 dB room noise after 1 s of noise alone."""
    folder = tmp_path_factory.mktemp("takes")
    rng = np.random.default_rng(5)
    made = []
    for number, text in enumerate(held_out_sentences()[:4]):
        for name in VOICES:
            voice = TEST_VOICES[name]
            path, truth, lead, samples = make_take(text, voice, "30 dB, leading noise", folder, rng)
            kept = path.rename(folder / f"take_{number}_{name}.wav")
            made.append((kept, truth, lead, samples))
    return made


def test_the_voices_measured_were_never_heard_in_training():
    metadata = load_network().metadata
    for name in VOICES:
        assert TEST_VOICES[name][0] in metadata["held_out_variants"]
        assert TEST_VOICES[name][0] not in metadata["training_variants"]
    assert "people" in metadata["trained_on"]  # it says it learnt from people


def test_the_mouth_follows_held_out_voices_far_better_than_loudness(takes):
    recognised, loudness = [], []
    for path, truth, lead, samples in takes:
        duration = samples.size / RATE
        truth_track = opening_trajectory(truth, duration, lead)
        _, speech = speech_from_audio(path)
        recognised.append(correlation(truth_track, opening_trajectory(speech.timeline, duration)))
        loudness.append(correlation(truth_track, loudness_envelope(samples, RATE, truth_track.size)))
    # Measured 0.980 (worst take 0.973; the network alone 0.991), the loudness envelope 0.714; the issue
    # asks for 0.85.
    assert np.median(recognised) >= 0.97 and min(recognised) >= 0.93
    assert np.median(recognised) > np.median(loudness) + 0.2


def test_bilabials_close_and_vowels_do_not(takes):
    closed = bilabials = vowels_closed = vowels = 0
    for path, truth, lead, _ in takes:
        _, speech = speech_from_audio(path)
        scores = bilabial_scores(truth, speech.timeline, lead)
        closed, bilabials = closed + scores[0], bilabials + scores[1]
        vowels_closed, vowels = vowels_closed + scores[2], vowels + scores[3]
    assert bilabials > 30 and vowels > 200
    assert closed / bilabials >= 0.85  # measured 36 of 39 (92 %), as the network alone; the issue asks 80 %
    assert vowels_closed / vowels <= 0.01  # measured none of 240


def test_the_heard_speech_is_an_utterance_like_a_typed_one(takes):
    path, _, lead, samples = takes[0]
    utterance, speech = speech_from_audio(path)
    timeline = speech.timeline
    assert timeline.timing == "recognised"
    assert [phone.letter for phone in timeline.phones] == [letter.char for letter in utterance.letters]
    assert utterance.source == " ".join(word.text for word in utterance.words)
    starts = np.array([phone.start for phone in timeline.phones])
    assert np.all(np.diff(starts) > 0) and np.all([phone.end > phone.start for phone in timeline.phones])
    assert starts[0] > lead - 0.15  # nothing heard in the noise before the first word
    assert timeline.emotions == ()
    # The recording is the sound, at its own rate and length.
    assert speech.synthesis.sample_rate == RATE
    assert speech.synthesis.duration == pytest.approx(samples.size / RATE, abs=0.01)
    assert speech.warnings == ()


def test_the_decoder_holds_every_letter_for_its_shortest_duration():
    """Posteriors that flip every frame between two vowels decode to a few held segments, not chatter."""
    network = load_network()
    frames = 300
    noisy = np.full((frames, len(CLASSES)), -8.0)
    a, e = CLASSES.index("a"), CLASSES.index("e")
    noisy[np.arange(frames), np.where(np.arange(frames) % 2, a, e)] = -0.05
    noisy[np.arange(frames), np.where(np.arange(frames) % 2, e, a)] = -0.3
    segments = decode(noisy.astype(np.float32), network.priors, network.transitions, network.shortest)
    assert len(segments) <= 3
    assert segments[0].first == 0 and segments[-1].stop == frames
    assert all(first.stop == second.first for first, second in zip(segments, segments[1:], strict=False))


def test_blocks_of_a_long_take_give_the_same_posteriors_as_one_piece(monkeypatch):
    from turkish_lipsync.core.speech.acoustic import network as network_module

    features = np.random.default_rng(2).normal(size=(3000, FEATURE_COUNT)).astype(np.float32)
    whole = load_network().log_posteriors(features)
    monkeypatch.setattr(network_module, "BLOCK_FRAMES", 700)
    np.testing.assert_allclose(load_network().log_posteriors(features), whole, atol=1e-4)


@pytest.mark.parametrize(
    "kind",
    ["silence", "hiss", "pink noise", "music"],
)
def test_a_take_without_speech_is_refused(tmp_path, kind):
    rng = np.random.default_rng(4)
    rate = 16_000
    samples = {
        "silence": np.zeros(4 * rate),
        "hiss": 0.05 * coloured_noise(4 * rate, "white", rng),
        "pink noise": 0.1 * coloured_noise(4 * rate, "pink", rng),
        "music": 0.2 * music(6 * rate, rng),
    }[kind]
    path = write_wav(tmp_path / "take.wav", samples, rate)
    with pytest.raises(AudioError, match="no speech found"):
        speech_from_audio(path)


def test_a_long_break_between_sentences_is_heard_as_a_short_one(tmp_path):
    """Two sentences 20 s apart in a quiet room are heard as nearly the same letters as 1 s apart: the room
    of a break that long filled the share of loud frames the take is levelled on (letters the same
    0.93 over these voices before, 0.99 since)."""
    rng = np.random.default_rng(6)
    same = []
    for name in ("f4", "Andrea", "klatt3", "benjamin"):
        first, _ = speak_variant(held_out_sentences()[0], *TEST_VOICES[name])
        second, _ = speak_variant(held_out_sentences()[1], *TEST_VOICES[name])
        room = 10 ** (-50 / 20) * np.abs(first).max()
        heard = []
        for seconds in (1, 20):
            samples = np.concatenate((first, np.zeros(seconds * 16000), second))
            samples += rng.normal(0, room, samples.size)
            _, speech = speech_from_audio(write_wav(tmp_path / f"break_{seconds}.wav", samples, 16000))
            heard.append("".join(phone.letter for phone in speech.timeline.phones))
        assert len(heard[0]) > 60
        same.append(difflib.SequenceMatcher(None, heard[0], heard[1]).ratio())
    assert np.mean(same) > 0.97, np.round(same, 3)


def test_another_language_is_followed_but_reported_as_doubtful(tmp_path):
    samples, rate = speak_language("The quick brown fox jumps over the lazy dog, then it runs away.", "en")
    path = write_wav(tmp_path / "english.wav", np.concatenate((np.zeros(rate // 2), samples)), rate)
    utterance, speech = speech_from_audio(path)
    assert len(speech.timeline.phones) > 10
    assert any("low confidence" in warning for warning in speech.warnings)


def test_every_closure_is_a_bilabial_letter_and_no_vowel_is_closed(takes):
    for path, *_ in takes:
        utterance, speech = speech_from_audio(path)
        for letter in utterance.letters:
            assert (letter.viseme in BILABIAL_VISEMES) == (letter.char in "bmp")
            if letter.is_vowel:
                assert letter.viseme in VOWEL_VISEMES
