"""Whisper's encoder and the classifier over it (acoustic/whisper.py), and the two hearings averaged.

The shipped weights are the real ones; what they hear is checked on eSpeak NG's Turkish made in the test.
"""

import math

import numpy as np
import pytest

from lab.kit.voices import TEST_VOICES, speak_variant
from turkish_lipsync.core.base.errors import DataError
from turkish_lipsync.core.speech.acoustic import whisper
from turkish_lipsync.core.speech.acoustic.features import recogniser_features
from turkish_lipsync.core.speech.acoustic.labels import CLASS_INDEX, CLASSES, frame_labels
from turkish_lipsync.core.speech.acoustic.network import convolve, load_network, matrix_of_taps
from turkish_lipsync.core.speech.recognition import recogniser
from turkish_lipsync.core.speech.recognition.settings import RecogniserSettings
from turkish_lipsync.core.speech.speech_detector import detect_speech

RATE = 16_000


@pytest.fixture(scope="module")
def spoken():
    """A held-out eSpeak NG voice reading a sentence full of bilabials, with its letters' frames."""
    variant, pitch, rate = TEST_VOICES["m3"]
    samples, timeline = speak_variant("Bir baba, mavi bir kapıyı boyamış.", variant, pitch, rate)
    count = len(recogniser_features(samples))
    return samples.astype(np.float32), frame_labels(timeline, count)


def test_the_mel_bands_put_a_tone_in_its_band_and_keep_whispers_range():
    tone = 0.5 * np.sin(2 * np.pi * 1000 * np.arange(RATE) / RATE).astype(np.float32)
    mel = whisper.log_mel(tone)
    assert mel.shape == (whisper.WINDOW_SAMPLES // whisper.MEL_HOP, 80)
    centres = whisper._slaney_hz(
        np.linspace(0, whisper._slaney_mel(np.array(8000.0)), whisper.MEL_BANDS + 2)
    )[1:-1]
    assert abs(centres[int(np.argmax(mel[50]))] - 1000) < 60  # the band centred nearest 1 kHz
    # Whisper's range: floored 8 (log10) below the loudest, scaled by (x + 4) / 4: a 2-wide span.
    assert mel.max() - mel.min() == pytest.approx(2.0, abs=1e-5)
    assert np.all(mel[150:] == mel.min())  # the silence it was padded with


def test_the_mel_filters_each_hold_unit_area():
    filters = whisper._mel_filters()
    assert filters.shape == (201, 80)
    bin_hz = 8000 / 200
    areas = filters.sum(axis=0) * bin_hz
    assert np.all(np.abs(areas[10:] - 1) < 0.1)  # wider than a few bins: the sum is the area


def test_the_halving_convolution_is_every_other_frame_of_the_full_one():
    rng = np.random.default_rng(3)
    x = rng.normal(size=(40, 6)).astype(np.float32)
    weight = matrix_of_taps(rng.normal(size=(5, 6, 3)).astype(np.float32))
    bias = rng.normal(size=5).astype(np.float32)
    np.testing.assert_allclose(
        whisper._halving_convolution(x, weight, bias), convolve(x, weight, bias, 1)[::2], atol=1e-5
    )


def test_gelu_is_close_to_the_exact_one_and_finite_far_out():
    x = np.linspace(-6, 6, 241).astype(np.float32)
    exact = np.array([0.5 * v * (1 + math.erf(v / math.sqrt(2))) for v in x.astype(np.float64)])
    assert np.abs(whisper._gelu(x.copy()) - exact).max() < 1e-3
    far = whisper._gelu(np.array([-1e4, -60.0, 60.0, 1e4], np.float32))
    np.testing.assert_array_equal(far, [0.0, 0.0, 60.0, 1e4])


def test_the_attention_in_blocks_is_softmax_attention_head_by_head():
    rng = np.random.default_rng(5)
    heads, size, frames = 3, 8, whisper.ATTENTION_ROWS + 37  # a last block shorter than the others
    qkv = (4 * rng.normal(size=(frames, 3 * heads * size))).astype(np.float32)
    expected = np.empty((frames, heads * size))
    for head in range(heads):
        q, k, v = (qkv[:, (part * heads + head) * size :][:, :size].astype(np.float64) for part in range(3))
        scores = q @ k.T / math.sqrt(size)
        weights = np.exp(scores - scores.max(axis=1, keepdims=True))
        expected[:, head * size : (head + 1) * size] = weights / weights.sum(axis=1, keepdims=True) @ v
    np.testing.assert_allclose(whisper._attended(qkv, heads), expected, rtol=1e-4, atol=1e-4)


def test_the_hearing_hears_a_held_out_voices_bilabials_and_vowels(spoken):
    samples, labels = spoken
    heard = whisper.load_whisper_hearing().log_posteriors(samples)
    assert heard.shape == (len(labels), len(CLASSES))
    np.testing.assert_allclose(np.exp(heard).sum(axis=1), 1, atol=1e-4)
    best = heard.argmax(axis=1)
    bilabial = np.isin(labels, [CLASS_INDEX[letter] for letter in "bmp"])
    vowel = np.isin(labels, [CLASS_INDEX[letter] for letter in "aeıioöuü"])
    # Frames of the voice's own letters: its b/m/p frames mostly heard as closures, its vowels as vowels.
    assert np.mean(np.isin(best[bilabial], [CLASS_INDEX[letter] for letter in "bmp"])) > 0.5
    assert np.mean(np.isin(best[vowel], [CLASS_INDEX[letter] for letter in "aeıioöuü"])) > 0.8


def test_a_take_longer_than_a_window_is_heard_frame_for_frame_as_its_pieces_are(spoken):
    samples, _ = spoken
    seconds = whisper.WINDOW_SAMPLES // RATE + 1
    long = np.concatenate([samples] * int(np.ceil(seconds * RATE / len(samples))))[: seconds * RATE]
    hearing = whisper.load_whisper_hearing()
    heard = hearing.log_posteriors(long)
    assert len(heard) == len(recogniser_features(long))
    assert np.isfinite(heard).all()
    # Heard in shorter windows than a take that fits one, its pieces are heard nearly as each alone is.
    pieces = whisper.windows(long)
    assert len(pieces) == 4
    for begin, stop in pieces:
        alone = hearing.log_posteriors(long[begin:stop]).argmax(axis=1)
        first = begin // whisper.HOP
        assert np.mean(heard[first : first + len(alone)].argmax(axis=1) == alone) > 0.9


def test_a_long_takes_windows_end_in_its_pauses():
    rng = np.random.default_rng(9)
    window = whisper.LONG_TAKE_WINDOW
    take = rng.normal(0, 0.1, 3 * window + 1234).astype(np.float32)
    pause = slice(window - RATE, window - RATE + 4000)  # 0.25 s, 1 s before the window's end
    take[pause] *= 0.001
    found = whisper.windows(take)
    assert found[0][0] == 0 and found[-1][1] == len(take)
    assert all(stop == begin for (_, stop), (begin, _) in zip(found, found[1:], strict=False))
    assert all(0 < stop - begin <= window for begin, stop in found)
    assert all(stop % whisper.ENCODER_HOP == 0 for _, stop in found[:-1])  # on the encoder's frame grid
    assert pause.start < found[0][1] < pause.stop  # the first ends in the pause
    # With no pause in its last CUT_SEARCH samples, a window still ends within them (the quietest moment).
    assert window - whisper.CUT_SEARCH < found[1][1] - found[1][0] <= window
    # A take that fits Whisper's own window is one window, however short.
    assert whisper.windows(take[: whisper.WINDOW_SAMPLES]) == [(0, whisper.WINDOW_SAMPLES)]
    assert whisper.windows(take[:100]) == [(0, 100)]
    assert whisper.windows(take[:0]) == [(0, 0)]


def test_the_settings_weigh_the_two_hearings(spoken):
    samples, _ = spoken
    network_heard, whisper_heard = recogniser.hearings(samples)
    alone = recogniser.recognise_posteriors(network_heard, None, RecogniserSettings())
    network_only = recogniser.recognise_posteriors(
        network_heard, whisper_heard, RecogniserSettings(whisper_weight=0, network_sure=2)
    )
    assert [letter for phrase in alone.phrases for letter in phrase] == [
        letter for phrase in network_only.phrases for letter in phrase
    ]
    averaged, priors = recogniser._averaged(network_heard, whisper_heard, 0.5)
    np.testing.assert_allclose(np.exp(averaged).sum(axis=1), 1, atol=1e-4)
    assert priors is whisper.load_whisper_hearing().priors
    # Halfway between the two: each frame's scaled likelihoods are the mean of the two's (up to a constant).
    scaled = averaged - np.log(priors)
    expected = 0.5 * (network_heard - np.log(load_network().priors)) + 0.5 * (whisper_heard - np.log(priors))
    differences = scaled - expected
    assert np.allclose(differences, differences[:, :1], atol=1e-3)


def test_whisper_is_heard_only_where_the_network_is_not_sure(spoken):
    samples, _ = spoken
    network_heard, whisper_heard = recogniser.hearings(samples)
    # eSpeak NG's voice is one the network knows: heard by it alone, whatever Whisper would add.
    assert not recogniser.whisper_needed(network_heard, RecogniserSettings())
    alone = recogniser.recognise_posteriors(network_heard, None, RecogniserSettings())
    assert recogniser.recognise(samples).phrases == alone.phrases
    assert recogniser.recognise_posteriors(network_heard, whisper_heard).phrases == alone.phrases
    # Asked to be surer than it can be, the recogniser hears both, as a person's take is heard.
    always = RecogniserSettings(network_doubtful=2, network_sure=2)
    assert recogniser.whisper_needed(network_heard, always)
    both = recogniser.recognise_posteriors(network_heard, whisper_heard, always)
    assert recogniser.recognise(samples, always).phrases == both.phrases
    assert both.phrases != alone.phrases
    # Never with no weight; always where the network hears no speech at all.
    assert not recogniser.whisper_needed(network_heard, RecogniserSettings(whisper_weight=0, network_sure=2))
    silence = load_network().log_posteriors(recogniser_features(np.zeros(RATE, np.float32)))
    assert recogniser.whisper_needed(silence, RecogniserSettings())


def test_whispers_weight_falls_as_the_network_grows_sure():
    def heard(sureness: float) -> np.ndarray:  # every frame an "a" heard this surely
        posteriors = np.full((50, len(CLASSES)), (1 - sureness) / (len(CLASSES) - 1))
        posteriors[:, CLASS_INDEX["a"]] = sureness
        return np.log(posteriors).astype(np.float32)

    settings = RecogniserSettings(whisper_weight=0.5, network_doubtful=0.7, network_sure=0.9)
    assert recogniser.whisper_share(heard(0.5), settings) == pytest.approx(0.5)  # doubtful: its full weight
    assert recogniser.whisper_share(heard(0.7), settings) == pytest.approx(0.5)
    assert recogniser.whisper_share(heard(0.8), settings) == pytest.approx(0.25)  # halfway: half of it
    assert recogniser.whisper_share(heard(0.9), settings) == 0.0  # sure: not heard at all
    assert not recogniser.whisper_needed(heard(0.95), settings)
    step = RecogniserSettings(whisper_weight=0.5, network_doubtful=0.9, network_sure=0.9)
    assert recogniser.whisper_share(heard(0.89), step) == pytest.approx(0.5)


def test_a_take_in_the_fall_is_judged_as_with_whispers_full_weight(spoken):
    samples, _ = spoken
    network_heard, whisper_heard = recogniser.hearings(samples)
    falling = RecogniserSettings(network_doubtful=0.5, network_sure=2)  # eSpeak NG's take: in the fall
    share = recogniser.whisper_share(network_heard, falling)
    assert 0 < share < falling.whisper_weight
    full = RecogniserSettings(network_doubtful=2, network_sure=2)
    heard = recogniser.recognise_posteriors(network_heard, whisper_heard, falling)
    assert heard.confidence == recogniser.recognise_posteriors(network_heard, whisper_heard, full).confidence


def test_missing_or_foreign_weights_say_what_to_do(tmp_path):
    with pytest.raises(DataError, match="missing; reinstall the extension"):
        whisper.load_whisper_hearing(tmp_path / "none.npz")
    with np.load(whisper.WEIGHTS_FILE) as data:
        stored = {key: data[key] for key in data.files}
    stored["head/out.bias"] = stored["head/out.bias"][:-1]
    stored["head/out.weight"] = stored["head/out.weight"][:-1]
    stored["head/out.weight.scale"] = stored["head/out.weight.scale"][:-1]
    np.savez(tmp_path / "other.npz", **stored)
    with pytest.raises(DataError, match="trained on other classes"):
        whisper.load_whisper_hearing(tmp_path / "other.npz")
    (tmp_path / "broken.npz").write_bytes(b"not a zip")
    with pytest.raises(DataError, match="cannot be read"):
        whisper.load_whisper_hearing(tmp_path / "broken.npz")


def test_blocks_of_a_long_take_give_the_same_posteriors_as_one_piece(spoken, monkeypatch):
    samples, _ = spoken
    hearing = whisper.load_whisper_hearing()
    whole = hearing.log_posteriors(samples)
    monkeypatch.setattr(whisper, "HEAD_BLOCK_FRAMES", 64)
    np.testing.assert_allclose(hearing.log_posteriors(samples), whole, atol=1e-4)


def test_the_classifiers_first_convolution_over_repeated_frames_is_the_convolution_of_them():
    rng = np.random.default_rng(11)
    x = rng.normal(size=(30, 6)).astype(np.float32)
    rows = np.repeat(np.arange(30), 2)[1:-3]  # each frame twice, as our frames take the encoder's
    weight = matrix_of_taps(rng.normal(size=(4, 6, 5)).astype(np.float32))
    bias = rng.normal(size=4).astype(np.float32)
    for dilation in (1, 2, 40):
        np.testing.assert_allclose(
            whisper.convolve_repeated(x, rows, weight, bias, dilation),
            convolve(x[rows], weight, bias, dilation),
            atol=1e-4,
        )


def test_the_spans_around_speech_hold_each_run_with_its_margins_on_the_encoders_grid():
    hop, margin, grid = whisper.HOP, whisper.SPEECH_MARGIN, whisper.ENCODER_HOP
    speech = np.zeros(3000, bool)
    speech[100:200] = True
    speech[220:260] = True  # 0.2 s after the first run: one span with it
    speech[1000:1100] = True
    speech[2990:] = True  # speech to the take's end
    length = 3000 * hop + 77
    spans = whisper.speech_spans(speech, length)
    assert len(spans) == 3
    for (begin, stop), (first, last) in zip(spans, [(100, 260), (1000, 1100), (2990, 3000)], strict=True):
        assert begin % grid == 0 and (stop % grid == 0 or stop == length)
        assert begin <= first * hop - margin < begin + grid  # the margin before, rounded out to the grid
        assert min(length, (last - 1) * hop + whisper.WINDOW + margin) <= stop
        assert stop < (last - 1) * hop + whisper.WINDOW + margin + grid
    assert spans[-1][1] == length
    assert whisper.speech_spans(np.zeros(50, bool), 50 * hop) == []
    assert whisper.speech_spans(np.ones(50, bool), 50 * hop) == [(0, 50 * hop)]


def test_a_long_take_is_heard_around_its_speech_and_the_network_hears_the_rest_alone(spoken, monkeypatch):
    samples, _ = spoken
    rng = np.random.default_rng(2)
    room = (0.001 * rng.normal(size=25 * RATE)).astype(np.float32)
    take = np.concatenate([samples, room, samples])
    speech = detect_speech(take).speech
    hearing = whisper.load_whisper_hearing()
    encoded = []
    real = whisper.WhisperHearing.encode
    monkeypatch.setattr(
        whisper.WhisperHearing, "encode", lambda self, mel: encoded.append(1) or real(self, mel)
    )
    everywhere = hearing.log_posteriors(take)
    windows = len(encoded)
    around_speech = hearing.log_posteriors(take, speech)
    spans = whisper.speech_spans(speech, len(take))
    assert len(encoded) - windows == len(whisper.windows(np.zeros(sum(b - a for a, b in spans)))) < windows
    heard = ~np.isnan(around_speech[:, 0])
    centres = np.arange(len(heard)) * whisper.HOP + whisper.WINDOW // 2
    outside = np.all([(centres < begin) | (centres >= stop) for begin, stop in spans], axis=0)
    assert outside.sum() > 20 * RATE // whisper.HOP and not heard[outside].any()  # the room between
    assert heard[speech].all()  # the speech is, and nearly as in the whole take
    assert np.mean(around_speech[speech].argmax(axis=1) == everywhere[speech].argmax(axis=1)) > 0.9
    # Averaged with the network, the frames Whisper did not hear are the network's hearing alone.
    network_heard = recogniser._network_hearing(take)
    averaged, _ = recogniser._averaged(network_heard, around_speech, 0.5)
    alone, _ = recogniser._averaged(network_heard, around_speech, 0.0)
    assert np.isfinite(averaged).all()
    np.testing.assert_allclose(averaged[~heard], alone[~heard], atol=1e-4)
    assert np.abs(averaged[heard] - alone[heard]).max() > 1  # elsewhere Whisper counts
