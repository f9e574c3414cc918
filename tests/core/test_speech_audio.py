"""Reading a user's audio (WAV, FLAC, float WAV), resampling it and finding its clipping."""

import re

import numpy as np
import soundfile

from tests.core.test_speech_recording import write_pcm_wav
from turkish_lipsync.core.speech import audio, read_audio, synthesize_timeline
from turkish_lipsync.core.speech.audio import clipping, resample
from turkish_lipsync.core.text.utterance import build_utterance


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


def test_clipping_is_named_where_the_tops_are_cut_flat_at_any_peak(monkeypatch):
    voice = synthesize_timeline(build_utterance("Kapıyı kapat, içerisi çok soğuk.")).synthesis.samples
    voice = voice.astype(np.float32) / np.abs(voice).max()
    assert clipping(voice) == ""  # a voice's peaks are not flat
    assert clipping(np.zeros(1000, np.float32)) == ""
    clipped = np.clip(4 * voice, -1, 1)
    named = clipping(clipped)
    share = int(re.search(r"\((\d+)% of its sound", named).group(1))
    assert 5 <= share <= 30 and "less gain" in named
    assert clipping(0.5 * clipped) == named  # normalised after it was clipped: the same flat tops
    monkeypatch.setattr(audio, "READ_BLOCK_FRAMES", 4099)  # counted block by block, runs across blocks
    assert clipping(clipped) == named
