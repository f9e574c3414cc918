"""Speech detection by Silero VAD in numpy: the reference's probabilities, short words, silence, noise, music.

The reference is Silero's own ONNX model run by onnxruntime (a development dependency only). Spoken words
come from eSpeak NG through the project's engine and, where people's recordings have been built (`python
lab/kit/people.py build`), from people.
"""

import importlib.metadata

import numpy as np
import pytest

from lab.kit.degradations import coloured_noise, music
from lab.kit.people import FOLDER as PEOPLE
from lab.kit.takes import write_wav
from turkish_lipsync.core.base.errors import AudioError, DataError
from turkish_lipsync.core.speech import speech_detector, synthesize_timeline
from turkish_lipsync.core.speech.audio import read_audio, resample
from turkish_lipsync.core.speech.features import ANALYSIS_RATE, HOP, frame_count
from turkish_lipsync.core.speech.recognition import speech_from_audio
from turkish_lipsync.core.text.utterance import build_utterance

RATE = ANALYSIS_RATE
KTUBERLING = PEOPLE / "packages/usr/share/ktuberling/sounds"
KLETTRES = PEOPLE / "dev/wav"
# Words whose loudest 0.2 s is the whole word, said by people (ktuberling: one word a file).
PEOPLES_WORDS = ("en/ball.ogg", "en/bow.ogg", "de/ball.ogg", "ru/ball.ogg", "uk/ball.ogg", "fr/chapeau.wav")


def spoken(text: str) -> np.ndarray:
    """eSpeak NG's Turkish voice saying the text, at 16 kHz."""
    synthesis = synthesize_timeline(build_utterance(text)).synthesis
    return resample(synthesis.samples.astype(np.float32) / 32768, synthesis.sample_rate, RATE)


def core(samples: np.ndarray, seconds: float = 0.2) -> np.ndarray:
    """The loudest `seconds` of the samples with 0.3 s of silence each side."""
    width = int(seconds * RATE)
    start = int(np.argmax(np.convolve(samples.astype(np.float64) ** 2, np.ones(width), "valid")))
    silence = np.zeros(int(0.3 * RATE), np.float32)
    return np.concatenate((silence, samples[start : start + width], silence))


def hissed(samples: np.ndarray, snr: float = 20.0, seed: int = 3) -> np.ndarray:
    loud = np.sort(samples**2)[-samples.size // 4 :].mean()
    level = np.sqrt(loud / 10 ** (snr / 10))
    return (samples + level * coloured_noise(samples.size, "white", np.random.default_rng(seed))).astype(
        np.float32
    )


def not_speech(kind: str) -> np.ndarray:
    rng = np.random.default_rng(21)
    if kind == "silence":
        return np.zeros(4 * RATE, np.float32)
    if kind == "music":
        return (0.2 * music(8 * RATE, rng)).astype(np.float32)
    return (0.1 * coloured_noise(5 * RATE, kind, rng)).astype(np.float32)


def onnx_probabilities(samples: np.ndarray) -> np.ndarray:
    """Silero's default ONNX model, chunk by chunk as its own wrapper runs it (context and state carried)."""
    onnxruntime = pytest.importorskip("onnxruntime")
    model = importlib.metadata.distribution("silero-vad").locate_file("silero_vad/data/silero_vad.onnx")
    options = onnxruntime.SessionOptions()
    options.intra_op_num_threads = options.inter_op_num_threads = 1
    session = onnxruntime.InferenceSession(str(model), options, providers=["CPUExecutionProvider"])
    count = -(-samples.size // speech_detector.CHUNK)
    padded = np.zeros(speech_detector.CONTEXT + count * speech_detector.CHUNK, np.float32)
    padded[speech_detector.CONTEXT : speech_detector.CONTEXT + samples.size] = samples
    state = np.zeros((2, 1, speech_detector.STATE), np.float32)
    probabilities = []
    for index in range(count):
        window = padded[
            index * speech_detector.CHUNK : (index + 1) * speech_detector.CHUNK + speech_detector.CONTEXT
        ]
        output, state = session.run(
            None, {"input": window[None], "state": state, "sr": np.array(RATE, np.int64)}
        )
        probabilities.append(output[0, 0])
    return np.array(probabilities, np.float32)


def peoples_word(name: str) -> np.ndarray:
    path = KTUBERLING / name
    if not path.is_file():
        pytest.skip(f"people's recordings not built here ({path}); see lab/measure/detection.py")
    samples, rate = read_audio(path)
    return resample(samples, rate, RATE)


@pytest.mark.parametrize("kind", ["speech", "hissing speech", "a person", "silence", "white", "music"])
def test_the_numpy_network_gives_silero_onnx_probabilities(kind):
    samples = {
        "speech": lambda: spoken("Annem sabahları erkenden kalkar ve bütün aileye kahvaltı hazırlar."),
        "hissing speech": lambda: hissed(spoken("Toplantı saat üçte başlayacak."), 10),
        "a person": lambda: peoples_word("en/ball.ogg"),
        "silence": lambda: not_speech("silence"),
        "white": lambda: not_speech("white"),
        "music": lambda: not_speech("music"),
    }[kind]()
    reference = onnx_probabilities(samples)
    ours = speech_detector.chunk_probabilities(samples)
    assert ours.dtype == np.float32 and ours.shape == reference.shape
    np.testing.assert_allclose(ours, reference, atol=1e-4)
    if kind in ("speech", "a person"):
        assert reference.max() > 0.9  # the comparison covers confident speech, not only silence


def test_a_long_take_is_computed_in_blocks_with_the_same_result(monkeypatch):
    samples = np.tile(hissed(spoken("Kütüphaneden aldığım kitabı geri vermem gerekiyor.")), 3)
    whole = speech_detector.chunk_probabilities(samples)
    monkeypatch.setattr(speech_detector, "BLOCK_CHUNKS", 37)
    np.testing.assert_allclose(speech_detector.chunk_probabilities(samples), whole, atol=1e-5)


@pytest.mark.parametrize("word", ["ev", "su", "bir"])
@pytest.mark.parametrize("room", ["quiet", "hissing"])
def test_a_short_word_is_speech(word, room):
    samples = core(spoken(word))
    samples = samples if room == "quiet" else hissed(samples)
    assert speech_detector.detect_speech(samples).found


@pytest.mark.parametrize("name", PEOPLES_WORDS)
def test_a_persons_word_and_its_loudest_fifth_of_a_second_are_speech(name):
    word = peoples_word(name)
    for samples in (word, core(word), hissed(core(word))):
        assert speech_detector.detect_speech(samples).found


@pytest.mark.parametrize("kind", ["silence", "white", "pink", "brown", "babble", "music"])
def test_silence_noise_and_music_are_not_speech(kind):
    detection = speech_detector.detect_speech(not_speech(kind))
    assert not detection.found and not detection.speech.any()


def test_frames_follow_the_analysis_frames_and_mark_the_word():
    lead = 0.8
    word = spoken("merhaba")
    samples = np.concatenate((np.zeros(int(lead * RATE), np.float32), word, np.zeros(RATE, np.float32)))
    detection = speech_detector.detect_speech(samples)
    assert detection.speech.size == detection.probabilities.size == frame_count(samples.size)
    (start, stop), *others = detection.spans()
    assert not others
    seconds = HOP / RATE
    voiced = np.flatnonzero(np.abs(word) > 0.05 * np.abs(word).max())
    assert abs(start * seconds - (lead + voiced[0] / RATE)) < 0.1
    assert abs(stop * seconds - (lead + voiced[-1] / RATE)) < 0.15
    longer = speech_detector.detect_speech(samples, frame_count(samples.size) + 50)
    assert not longer.speech[-50:].any() and (longer.speech[:-50] == detection.speech).all()


@pytest.mark.parametrize("count", [0, 1, 300, 513])
def test_an_empty_or_tiny_take_has_no_speech_and_its_frames(count):
    samples = np.random.default_rng(2).normal(scale=0.1, size=count).astype(np.float32)
    detection = speech_detector.detect_speech(samples)
    assert detection.speech.size == frame_count(count) and not detection.found
    assert speech_detector.detect_speech(samples, 7).speech.size == 7


def test_a_short_run_is_speech_where_the_takes_sound_is_and_a_long_one_anywhere():
    low, high, dip = 0.02, 0.9, 0.1  # under the silence threshold, over the speech threshold, a dip
    chunk = speech_detector.CHUNK / RATE
    padding = round(speech_detector.DEFAULT_DETECTOR.speech_padding / chunk)

    def take(run_chunks, loud_everywhere):
        probabilities = np.array([low] * 20 + [high] * run_chunks + [low] * 20)
        energies = np.full(probabilities.size, 1.0 if loud_everywhere else 1e-4)
        energies[20 : 20 + run_chunks] = 1.0
        return speech_detector.speech_chunks(probabilities, energies)

    short = round(0.15 / chunk)  # a word of 0.15 s
    assert speech_detector.runs(take(short, False)).tolist() == [[20 - padding, 20 + short + padding]]
    assert not take(short, True).any()  # the same run inside loud music or noise is a blip
    long = round(speech_detector.DEFAULT_DETECTOR.certain_speech / chunk) + 1
    assert take(long, True).any()
    assert not take(1, False).any()  # one chunk is a click
    closure = np.array([low] * 20 + [high] * 4 + [dip] + [high] * 4 + [low] * 20)
    assert len(speech_detector.runs(speech_detector.speech_chunks(closure, closure))) == 1
    pause = np.array([low] * 20 + [high] * 6 + [low] * 12 + [high] * 6 + [low] * 20)
    assert len(speech_detector.runs(speech_detector.speech_chunks(pause, pause))) == 2


def test_missing_weights_are_a_clear_error(monkeypatch, tmp_path):
    monkeypatch.setattr(speech_detector, "EXTENSION_ROOT", tmp_path)
    real_distribution = importlib.metadata.distribution

    def without_silero(name):
        if name == "silero-vad":
            raise importlib.metadata.PackageNotFoundError(name)
        return real_distribution(name)

    monkeypatch.setattr(importlib.metadata, "distribution", without_silero)
    with pytest.raises(DataError, match="reinstall the extension.*pip install --no-deps silero-vad"):
        speech_detector.weights_path()


@pytest.mark.parametrize("content", [b"", b"\x0a\xff\xff\xff\xff\x0f", b"not a model at all"])
def test_damaged_weights_are_a_clear_error(tmp_path, content):
    path = tmp_path / speech_detector.WEIGHTS_NAME
    path.write_bytes(content)
    with pytest.raises(DataError, match=str(path)):
        speech_detector.load_detector(path)


def test_the_recogniser_takes_a_fifth_of_a_second_word_and_refuses_noise(tmp_path):
    word = write_wav(tmp_path / "ev.wav", hissed(core(spoken("ev"))), RATE)
    utterance, speech = speech_from_audio(word)
    assert speech.timeline.phones
    noise = write_wav(tmp_path / "hiss.wav", not_speech("white"), RATE)
    with pytest.raises(AudioError, match="no speech found"):
        speech_from_audio(noise)


def test_the_aligner_takes_a_single_short_word_and_refuses_silence(tmp_path):
    from tests.core.test_speech_recording import other_voice

    voice, _ = other_voice("ev", "tr+f3", 25, 0)
    word = resample(voice, 44100, RATE)
    path = write_wav(tmp_path / "ev.wav", hissed(core(word)), RATE)
    timeline = synthesize_timeline(build_utterance("ev"), recording=path).timeline
    assert timeline.timing == "recording" and len(timeline.words) == 1
    silent = write_wav(tmp_path / "sessiz.wav", np.zeros(2 * RATE), RATE)
    with pytest.raises(AudioError, match="silent"):
        synthesize_timeline(build_utterance("ev"), recording=silent)


@pytest.mark.parametrize(("name", "spelling"), [("uk-ba", "ba"), ("uk-vov", "vov"), ("uk-bo", "bo")])
def test_a_persons_fifth_of_a_second_syllable_is_not_silent_to_the_aligner_or_the_recogniser(
    tmp_path, name, spelling
):
    path = KLETTRES / f"klettres-uk-{name}.wav"
    if not path.is_file():
        pytest.skip(f"people's recordings not built here ({path}); see lab/measure/detection.py")
    samples, rate = read_audio(path)
    take = write_wav(tmp_path / "take.wav", hissed(core(resample(samples, rate, RATE))), RATE)
    try:
        synthesize_timeline(build_utterance(spelling), recording=take)
    except AudioError as error:  # the aligner, learnt from eSpeak NG, may not know the voice (issue 31)
        assert "silent" not in str(error)
    assert speech_from_audio(take)[1].timeline.phones


@pytest.mark.parametrize(("name", "spelling"), [("de/ear.ogg", "or"), ("sv/mun.wav", "mun")])
def test_a_word_the_webrtc_mask_barely_hears_is_not_silent_to_the_aligner(tmp_path, name, spelling):
    from turkish_lipsync.core.speech.aligner_settings import DEFAULT_ALIGNER
    from turkish_lipsync.core.speech.voice_activity import speech_frames

    samples = core(peoples_word(name))
    assert (
        np.count_nonzero(speech_frames(samples, frame_count(samples.size)))
        < DEFAULT_ALIGNER.least_speech_frames
    )
    assert speech_detector.detect_speech(samples).found
    take = write_wav(tmp_path / "take.wav", samples, RATE)
    try:
        synthesize_timeline(build_utterance(spelling), recording=take)
    except AudioError as error:  # the aligner, learnt from eSpeak NG, may not know the voice (issue 31)
        assert "silent" not in str(error)
