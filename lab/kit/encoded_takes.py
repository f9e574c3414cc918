"""A take of the product's own voice in the forms recordings arrive in: WAV, MP3, M4A, the sound track of
MP4, MOV, MKV and WebM videos, OGG Opus, each at its own rate and channel count, encoded with PyAV (FFmpeg);
and where a decoded sound lies against its WAV's. Used by lab/measure/decoders.py and the tests."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import numpy as np

from turkish_lipsync.core.speech import synthesize_timeline
from turkish_lipsync.core.speech.audio import resample
from turkish_lipsync.core.text.utterance import build_utterance

TAKE_TEXT = "Merhaba, benim adım Erdem. Bu sabah vapura binip karşıya geçtim, deniz çok güzeldi."
LEAD_IN = 0.4  # seconds of room noise before the voice
VIDEO_SIZE = 32  # pixels: the picture only has to be there
REFERENCE_RATE = 44100  # the WAV's rate, at which shifts are measured
# name: (codec, sample rate, channels, video codec or None)
ENCODINGS = {
    "mp3": ("libmp3lame", 44100, 2, None),
    "m4a": ("aac", 48000, 2, None),
    "mp4": ("aac", 32000, 1, "libx264"),
    "mov": ("aac", 44100, 2, "libx264"),
    "mkv": ("aac", 48000, 2, "libx264"),
    "webm": ("libopus", 48000, 2, "libvpx-vp9"),
    "ogg": ("libopus", 24000, 1, None),
}


def spoken_voice(text: str = TAKE_TEXT, rate: int = 48000) -> np.ndarray:
    """The text read a little slower and higher by eSpeak NG, after a lead-in of faint noise, at rate."""
    utterance = build_utterance(f'<PROS RATE="-15%" PITCH="+20%">{text}</PROS>')
    synthesis = synthesize_timeline(utterance).synthesis
    voice = resample(synthesis.samples.astype(np.float32) / 32768, synthesis.sample_rate, rate)
    lead, tail = np.zeros(int(LEAD_IN * rate), np.float32), np.zeros(rate // 4, np.float32)
    voice = np.concatenate((lead, voice, tail))
    return voice + np.random.default_rng(4).normal(0, 0.001, voice.size).astype(np.float32)


def channels_of(voice: np.ndarray, channels: int) -> np.ndarray:
    """[channels, frames]: the voice, each further channel a little quieter (a stereo microphone)."""
    return np.stack([voice * (1 - 0.2 * channel) for channel in range(channels)]).astype(np.float32)


def write_takes(folder: Path, text: str = TAKE_TEXT) -> dict[str, Path]:
    """The text spoken (spoken_voice) as a 16-bit stereo WAV at REFERENCE_RATE and in every encoding."""
    import soundfile

    voice = spoken_voice(text, rate=REFERENCE_RATE)
    wav = folder / "take.wav"
    soundfile.write(str(wav), channels_of(voice, 2).T, REFERENCE_RATE, subtype="PCM_16")
    return {"wav": wav} | {name: write_take(folder, name, voice, REFERENCE_RATE) for name in ENCODINGS}


def write_take(folder: Path, name: str, voice: np.ndarray, voice_rate: int) -> Path:
    """The voice encoded as ENCODINGS[name] into folder/take.<name>."""
    codec, rate, channels, video = ENCODINGS[name]
    samples = channels_of(resample(voice, voice_rate, rate), channels)
    return encode(folder / f"take.{name}", samples, rate, codec, video)


def encode(
    path: Path, samples: np.ndarray, rate: int, codec: str, video: str | None = None, sound: bool = True
) -> Path:
    """Planar float samples [channels, frames] encoded with PyAV, beside a changing picture where video
    (without the sound where sound is False: a video with no sound track, one second long)."""
    import av

    with av.open(str(path), "w") as container:
        picture = _video_stream(container, video) if video else None
        if sound:
            _mux_sound(container, samples, rate, codec)
        if picture is not None:
            _mux_pictures(container, picture, samples.shape[1] / rate if sound else 1.0)
    return path


def _mux_sound(container, samples: np.ndarray, rate: int, codec: str) -> None:
    import av

    layout = {1: "mono", 2: "stereo", 6: "5.1"}[samples.shape[0]]
    stream = container.add_stream(codec, rate=rate, layout=layout)
    stream.bit_rate = 96000 * samples.shape[0]
    size = stream.codec_context.frame_size or 1024
    for begin in range(0, samples.shape[1], size):
        frame = av.AudioFrame.from_ndarray(
            np.ascontiguousarray(samples[:, begin : begin + size]), format="fltp", layout=layout
        )
        frame.sample_rate, frame.pts, frame.time_base = rate, begin, Fraction(1, rate)
        container.mux(stream.encode(frame))
    container.mux(stream.encode(None))


def _video_stream(container, codec: str):
    stream = container.add_stream(codec, rate=25)
    stream.width = stream.height = VIDEO_SIZE
    stream.pix_fmt = "yuv420p"
    return stream


def _mux_pictures(container, stream, seconds: float) -> None:
    import av

    for index in range(int(seconds * 25) + 1):
        picture = np.full((VIDEO_SIZE, VIDEO_SIZE, 3), index % 256, np.uint8)
        frame = av.VideoFrame.from_ndarray(picture, format="rgb24")
        frame.pts = index
        container.mux(stream.encode(frame))
    container.mux(stream.encode(None))


def lag_seconds(samples: np.ndarray, rate: int, reference: np.ndarray) -> float:
    """How much later the samples' sound lies than the reference's (at REFERENCE_RATE), by
    cross-correlation."""
    heard = resample(samples, rate, REFERENCE_RATE) if rate != REFERENCE_RATE else samples
    size = 1 << int(np.ceil(np.log2(heard.size + reference.size)))
    correlation = np.fft.irfft(np.fft.rfft(heard, size) * np.conj(np.fft.rfft(reference, size)), size)
    lag = int(np.argmax(correlation))
    return (lag - size if lag > size // 2 else lag) / REFERENCE_RATE
