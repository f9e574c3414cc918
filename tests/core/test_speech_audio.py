"""Reading a user's audio (WAV, FLAC, float WAV) and resampling it."""

import numpy as np
import soundfile

from tests.core.test_speech_recording import write_pcm_wav
from turkish_lipsync.core.speech import read_audio
from turkish_lipsync.core.speech.audio import resample


def test_a_flac_recording_is_read_like_a_wav(tmp_path):
    rng = np.random.default_rng(8)
    stereo = np.stack([0.3 * np.sin(2 * np.pi * 220 * np.arange(16000) / 16000)] * 2, axis=1)
    path = write_pcm_wav(
        tmp_path / "reading.wav", stereo + rng.normal(0, 0.002, stereo.shape), 16000, channels=2
    )
    samples, rate = read_audio(path)
    flac = tmp_path / "reading.flac"
    soundfile.write(str(flac), samples, rate, subtype="PCM_16")
    again, again_rate = read_audio(flac)
    assert again_rate == rate == 16000
    assert np.max(np.abs(again - samples)) < 2 / 32768


def test_float_wav_is_read_through_soundfile(tmp_path):
    tone = 0.5 * np.sin(2 * np.pi * 440 * np.arange(8000) / 8000)
    path = tmp_path / "float.wav"
    soundfile.write(str(path), tone, 8000, subtype="FLOAT")
    samples, rate = read_audio(path)
    assert rate == 8000 and np.allclose(samples, tone, atol=1e-6)


def test_resampling_keeps_a_tone_and_its_level():
    source_rate, target_rate = 48000, 22050
    time = np.arange(source_rate) / source_rate
    tone = 0.5 * np.sin(2 * np.pi * 1000 * time)
    result = resample(tone, source_rate, target_rate)
    assert result.size == target_rate
    expected = 0.5 * np.sin(2 * np.pi * 1000 * np.arange(target_rate) / target_rate)
    assert np.max(np.abs(result[200:-200] - expected[200:-200])) < 0.01
