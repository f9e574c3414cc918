"""Reading a user's recording and resampling it, block by block so a long take is never held twice.

The decoders (speech/decoders/) read WAV, FLAC, OGG, MP3, AAC and the sound tracks of videos, mixed to mono
as they are read; resampling through soxr (band-limited, streamed).
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np

from ..base.errors import AudioError
from .decoders import READ_BLOCK_FRAMES, RECORDING_KINDS, DecodedAudio, decode_recording

MAX_OUTPUT_RATE = 48_000  # the recording's own rate is kept up to this
# Clipping: a sample within CLIPPED_TOLERANCE of the take's peak, in a run of at least CLIPPED_RUN such
# samples, sits on a top the recorder or a gain stage cut flat (wherever the peak lies: a take normalised
# after it was clipped has its flat tops below full scale). CLIPPED_SHARE of the sounding samples (those
# within 40 dB of the peak) is clipping worth naming: of the people's recordings lab/kit/people.py
# fetches, 18 of about 3,500 pass it (KDE's Tswana syllables, 2-67 %), three more lie at 0.1-1 %.
CLIPPED_TOLERANCE = 1e-4  # of the peak: a few steps of 16-bit audio
CLIPPED_RUN = 3
CLIPPED_SHARE = 0.01


def read_audio(path: str | Path) -> tuple[np.ndarray, int]:
    """Mono float32 samples in [-1, 1] and the sample rate of a recording (see speech/decoders/)."""
    decoded = decode_audio(path)
    return decoded.samples, decoded.rate


def decode_audio(path: str | Path) -> DecodedAudio:
    """The recording decoded, with the name of the decoder that read it; AudioError where none can."""
    path = Path(path)
    if not path.is_file():
        raise AudioError(f"recording {path} does not exist; give the path of a recording: {RECORDING_KINDS}")
    decoded = decode_recording(path)
    if decoded.samples.size == 0 or decoded.rate <= 0:
        raise AudioError(f"recording {path} holds no audio; record the text again")
    if not np.isfinite(decoded.samples.sum(dtype=np.float64)):  # a NaN or infinity makes the sum one
        raise AudioError(
            f"recording {path} contains invalid samples (NaN or infinite); export it again as WAV"
        )
    return decoded


def clipping(samples: np.ndarray) -> str:
    """A clause naming the clipping of a take's mono samples (see CLIPPED_SHARE), or "" where it has none
    worth naming: a clipped take's sound is distorted, and what is heard in it fits its text less well."""
    peak = float(max(samples.max(initial=0.0), -samples.min(initial=0.0)))
    if peak == 0.0:
        return ""
    flat = sounding = 0
    run = 0  # the run of top samples reaching the end of the blocks read so far
    for begin in range(0, samples.size, READ_BLOCK_FRAMES):  # a long take is never copied whole
        block = np.abs(samples[begin : begin + READ_BLOCK_FRAMES])
        sounding += int(np.count_nonzero(block > peak * 0.01))
        edges = np.diff((block >= peak * (1 - CLIPPED_TOLERANCE)).view(np.int8), prepend=0, append=0)
        starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
        lengths = stops - starts
        if starts.size and starts[0] == 0:
            lengths[0] += run  # the run goes on from the block before
        elif run >= CLIPPED_RUN:
            flat += run
        run = 0
        if stops.size and stops[-1] == block.size:
            run, lengths = int(lengths[-1]), lengths[:-1]  # it may go on into the next block
        flat += int(lengths[lengths >= CLIPPED_RUN].sum())
    if run >= CLIPPED_RUN:
        flat += run
    share = flat / max(sounding, 1)
    if share < CLIPPED_SHARE:
        return ""
    return (
        f"the recording is clipped ({share:.0%} of its sound cut flat at its peak): record it again with "
        "less gain"
    )


def to_pcm16(samples: np.ndarray) -> np.ndarray:
    """Float samples in [-1, 1] as 16-bit PCM, rounded and clipped (1.0 is 32767, never wrapping): the
    exact inverse of reading PCM as float (divided by 32768), so a 16-bit sound read and written again
    is the same to the bit."""
    scaled = samples * 32768
    np.round(scaled, out=scaled)
    np.clip(scaled, -32768, 32767, out=scaled)
    return scaled.astype(np.int16)


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
