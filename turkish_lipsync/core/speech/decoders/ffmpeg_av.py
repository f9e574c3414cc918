"""What FFmpeg reads, through PyAV where it is installed (the command line and the bpy module outside
Blender; Blender itself reads these through its own FFmpeg, blender/audio_decoding.py): AAC in M4A, MP4 and
MOV, the sound track of any video FFmpeg opens (MKV, WebM, AVI, ...), at its own rate and channel count.

Timing is kept exact: the encoder's priming samples (an AAC encoder's 1024 or 2112, which MP4's edit list
and Matroska's codec delay announce) are dropped where the decoder has not dropped them itself, and the
padding that fills an AAC stream's last frame is cut at the end its last packet declares.
"""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import numpy as np

from ...base.errors import AudioError
from .base import DECODERS, AudioDecoder, DecodeFailed, MonoBuffer
from .formats import AudioFormat

SAMPLE_SCALES = {"u8": 1 / 128, "s16": 1 / 32768, "s32": 1 / 2**31, "s64": 1 / 2**63, "flt": 1.0, "dbl": 1.0}


@DECODERS.register
class PyAVDecoder(AudioDecoder):
    name = "pyav"
    label = "PyAV (FFmpeg)"
    order = 40
    ffmpeg = True

    def missing(self) -> str:
        try:
            import av  # noqa: F401
        except ImportError:
            return "PyAV is not installed"
        return ""

    def decode(self, path: Path, audio_format: AudioFormat) -> tuple[np.ndarray, int]:
        import av

        try:
            with av.open(str(path)) as container:
                if not container.streams.audio:
                    kind = "" if audio_format.name == "unknown" else f"{audio_format.label} "
                    raise AudioError(
                        f"the {kind}file {path} has no sound track; give the recording itself, or a video "
                        "with its sound"
                    )
                return _decoded(container, container.streams.audio[0])
        except av.FFmpegError as error:
            raise DecodeFailed(getattr(error, "strerror", None) or str(error)) from None


def _decoded(container, stream) -> tuple[np.ndarray, int]:
    """Mono float32 of the stream from its first sample to its last packet's declared end."""
    rate = int(stream.codec_context.sample_rate or stream.rate or 0)
    if rate <= 0:
        raise DecodeFailed("the sound track has no sample rate")
    time_base = stream.time_base or Fraction(1, rate)
    # The stream's zero: its first sample, or zero where it starts before (Matroska's codec delay shifts
    # the priming samples to negative times).
    start = None if stream.start_time is None else max(stream.start_time, 0)
    gathered = MonoBuffer(_estimated_frames(container, stream, rate), rate)
    skip = None  # priming samples still to drop, known at the first frame
    end = None  # the stream's last sample, from its packets' timestamps and durations
    for packet in container.demux(stream):
        if packet.pts is not None and packet.duration:
            end = max(end or 0, packet.pts + packet.duration)
        for frame in packet.decode():
            if start is None:
                start = max(frame.pts or 0, 0)
            if skip is None:
                before = 0 if frame.pts is None else round((frame.pts - start) * time_base * rate)
                skip = max(0, -before)
            block = _mono(frame)
            dropped = min(skip, block.size)
            skip -= dropped
            gathered.append(block[dropped:])
    limit = None if end is None or start is None else round((end - start) * time_base * rate)
    return gathered.samples(limit), rate


def _estimated_frames(container, stream, rate: int) -> int:
    if stream.duration and stream.time_base:
        return int(stream.duration * stream.time_base * rate)
    if container.duration:  # in microseconds
        return int(container.duration * rate / 1_000_000)
    return 0


def _mono(frame) -> np.ndarray:
    """The frame's channels averaged, as float32 in [-1, 1]."""
    kind = frame.format.name.rstrip("p")
    channels = len(frame.layout.channels)
    data = frame.to_ndarray()
    if not frame.format.is_planar:
        data = data.reshape(-1, channels).T
    if kind == "u8":
        data = data.astype(np.float32) - 128
    averaged = data.mean(axis=0, dtype=np.float64 if kind in ("s32", "s64", "dbl") else np.float32)
    return (averaged * SAMPLE_SCALES.get(kind, 1.0)).astype(np.float32, copy=False)
