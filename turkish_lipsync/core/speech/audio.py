"""Reading a user's audio file and resampling it, block by block so a long take is never held twice.

WAV through the stdlib, FLAC/OGG and float WAV through soundfile, mixed to mono as it is read;
resampling through soxr (band-limited, streamed).
"""

from __future__ import annotations

import struct
import wave
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from ..base.errors import AudioError

MAX_OUTPUT_RATE = 48_000  # the recording's own rate is kept up to this
READ_BLOCK_FRAMES = 1 << 20  # frames read and mixed to mono at a time: a long take is never held in stereo
# Clipping: a sample within CLIPPED_TOLERANCE of the take's peak, in a run of at least CLIPPED_RUN such
# samples, sits on a top the recorder or a gain stage cut flat (wherever the peak lies: a take normalised
# after it was clipped has its flat tops below full scale). CLIPPED_SHARE of the sounding samples (those
# within 40 dB of the peak) is clipping worth naming: of the people's recordings lab/kit/people.py
# fetches, 18 of about 3,500 pass it (KDE's Tswana syllables, 2-67 %), three more lie at 0.1-1 %.
CLIPPED_TOLERANCE = 1e-4  # of the peak: a few steps of 16-bit audio
CLIPPED_RUN = 3
CLIPPED_SHARE = 0.01


def read_audio(path: str | Path) -> tuple[np.ndarray, int]:
    """Mono float32 samples in [-1, 1] and the sample rate of a WAV, FLAC or OGG file (read in blocks)."""
    path = Path(path)
    if not path.is_file():
        raise AudioError(f"recording {path} does not exist; give the path of a WAV, FLAC or OGG file")
    mono, rate = None, 0
    if path.suffix.lower() == ".wav":
        try:
            mono, rate = _read_pcm_wav(path)
        except (wave.Error, EOFError, ValueError, RuntimeError, struct.error):
            mono = None  # not plain PCM (float, extensible, ...) or damaged: soundfile may still read it
        except OSError as error:
            raise AudioError(
                f"cannot open the recording {path} ({error}); check the file's permissions"
            ) from None
    if mono is None:
        mono, rate = _read_with_soundfile(path)
    if mono.size == 0 or rate <= 0:
        raise AudioError(f"recording {path} holds no audio; record the text again")
    if not np.isfinite(mono).all():
        raise AudioError(
            f"recording {path} contains invalid samples (NaN or infinite); export it again as WAV"
        )
    return mono, rate


def clipping(samples: np.ndarray) -> str:
    """A clause naming the clipping of a take's mono samples (see CLIPPED_SHARE), or "" where it has none
    worth naming: a clipped take's sound is distorted, and what is heard in it fits its text less well."""
    peak = float(max(samples.max(initial=0.0), -samples.min(initial=0.0)))
    if peak == 0.0:
        return ""
    flat = sounding = 0
    for begin in range(0, samples.size, READ_BLOCK_FRAMES):  # a long take is never copied whole
        block = np.abs(samples[begin : begin + READ_BLOCK_FRAMES + CLIPPED_RUN - 1])
        top = block >= peak * (1 - CLIPPED_TOLERANCE)
        runs = np.lib.stride_tricks.sliding_window_view(top, CLIPPED_RUN).all(axis=1)
        on_run = np.zeros(top.size, bool)
        for shift in range(CLIPPED_RUN):
            on_run[shift : shift + runs.size] |= runs
        own = min(READ_BLOCK_FRAMES, samples.size - begin)  # the overlap is the next block's
        flat += int(np.count_nonzero(on_run[:own]))
        sounding += int(np.count_nonzero(block[:own] > peak * 0.01))
    share = flat / max(sounding, 1)
    if share < CLIPPED_SHARE:
        return ""
    return (
        f"the recording is clipped ({share:.0%} of its sound cut flat at its peak): record it again with "
        "less gain"
    )


def _read_pcm_wav(path: Path) -> tuple[np.ndarray, int]:
    with wave.open(str(path), "rb") as handle:
        channels, width, rate = handle.getnchannels(), handle.getsampwidth(), handle.getframerate()
        if width not in (1, 2, 3, 4):
            raise ValueError(f"unsupported sample width {width}")
        mono = np.empty(handle.getnframes(), np.float32)
        filled = 0
        while filled < mono.size:
            data = handle.readframes(READ_BLOCK_FRAMES)
            frames = len(data) // (width * channels)
            if frames == 0:
                break
            samples = _pcm_to_float(data[: frames * width * channels], width).reshape(frames, channels)
            mono[filled : filled + frames] = samples.mean(axis=1)
            filled += frames
    return mono[:filled], rate


def _pcm_to_float(data: bytes, width: int) -> np.ndarray:
    if width == 1:
        return (np.frombuffer(data, np.uint8).astype(np.float32) - 128) / 128
    if width == 2:
        return np.frombuffer(data, "<i2").astype(np.float32) / 32768
    if width == 3:
        raw = np.frombuffer(data, np.uint8).reshape(-1, 3).astype(np.int32)
        value = raw[:, 0] | (raw[:, 1] << 8) | (raw[:, 2] << 16)
        return (np.where(value >= 1 << 23, value - (1 << 24), value) / float(1 << 23)).astype(np.float32)
    return (np.frombuffer(data, "<i4") / float(1 << 31)).astype(np.float32)


def _read_with_soundfile(path: Path) -> tuple[np.ndarray, int]:
    try:
        import soundfile
    except ImportError:
        raise AudioError(
            f"cannot read {path}: FLAC, OGG and float WAV need the Python package soundfile "
            "(`pip install soundfile`); or export the recording as 16-bit PCM WAV"
        ) from None
    try:
        with soundfile.SoundFile(str(path)) as handle:
            blocks = [
                block.mean(axis=1, dtype=np.float32)
                for block in handle.blocks(READ_BLOCK_FRAMES, dtype="float32", always_2d=True)
            ]
            rate = handle.samplerate
    except Exception as error:  # soundfile raises its own error types, varying by version
        raise AudioError(
            f"cannot read the recording {path} ({error}); export it as a WAV, FLAC or OGG file"
        ) from None
    return (np.concatenate(blocks) if blocks else np.zeros(0, np.float32)), int(rate)


def to_pcm16(samples: np.ndarray) -> np.ndarray:
    """Float samples in [-1, 1] as 16-bit PCM, rounded and clipped (1.0 is 32767, never wrapping): the
    exact inverse of reading PCM as float (divided by 32768), so a 16-bit sound read and written again
    is the same to the bit."""
    return np.clip(np.round(samples * 32768), -32768, 32767).astype(np.int16)


def resampled_pcm(samples: np.ndarray, source_rate: int, target_rate: int) -> np.ndarray:
    """16-bit PCM at the target rate, made block by block (a long take has no float copy to spare)."""
    return np.concatenate(
        [to_pcm16(block) for block in _resampled_blocks(samples, source_rate, target_rate)]
        or [np.zeros(0, np.int16)]
    )


def decibels_under_loud(power: np.ndarray) -> np.ndarray:
    """Each frame's power in dB under the loud frames' (the 95th percentile): 0 at loud speech, -35 and
    lower in a pause."""
    loud = float(np.percentile(power, 95)) if power.size else 1.0
    return 10 * np.log10(np.maximum(power, 1e-12) / max(loud, 1e-12))


def levels_under_loud(samples: np.ndarray, hop: int) -> np.ndarray:
    """decibels_under_loud of each `hop` samples' mean power (samples as float or PCM alike)."""
    count = samples.size // hop
    power = (samples[: count * hop].astype(np.float64).reshape(count, hop) ** 2).mean(axis=1)
    return decibels_under_loud(power)


def resample(samples: np.ndarray, source_rate: int, target_rate: int, scale: float = 1.0) -> np.ndarray:
    """float32 samples (times scale) at the target rate: soxr's band-limited resampling, block by block."""
    blocks = list(_resampled_blocks(samples, source_rate, target_rate, scale))
    return np.concatenate(blocks) if blocks else np.zeros(0, np.float32)


def _resampled_blocks(
    samples: np.ndarray, source_rate: int, target_rate: int, scale: float = 1.0
) -> Iterator[np.ndarray]:
    """float32 blocks of the samples (times scale) resampled by one soxr stream."""
    import soxr

    stream = (
        soxr.ResampleStream(source_rate, target_rate, 1, dtype="float32")
        if source_rate != target_rate
        else None
    )
    for begin in range(0, samples.size, READ_BLOCK_FRAMES):
        block = samples[begin : begin + READ_BLOCK_FRAMES].astype(np.float32) * np.float32(scale)
        if stream is None:
            yield block
        else:
            yield stream.resample_chunk(block, last=begin + READ_BLOCK_FRAMES >= samples.size)
