"""Joining rendered video chunks and the speech into one MP4 without re-encoding the video (PyAV).

A render farm renders frame ranges of one .blend on many machines; the chunks are H.264 streams made with
the same settings, so their packets are copied one after another with shifted timestamps, and the speech
is encoded once as AAC over the whole length. Needs no Blender: any Python with the `av` package runs it.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import numpy as np

from ..base.errors import AudioError, LipSyncError

AUDIO_RATE = 48000


class VideoError(LipSyncError):
    """Video chunks that cannot be joined."""


@dataclass(frozen=True)
class JoinResult:
    path: Path
    frame_count: int
    seconds: float
    chunk_frames: tuple[int, ...]


def _require_av():
    try:
        import av
    except ImportError as error:
        raise VideoError(
            "Joining videos needs PyAV: install the 'av' package into the Python that runs it "
            "(python -m pip install av), or run render.py --join with a Python that has it."
        ) from error
    return av


def _open(av, path: Path):
    try:
        return av.open(os.fspath(path))
    except (OSError, av.error.FFmpegError) as error:
        raise VideoError(f"Cannot read the video {path}: {error}. Render this chunk again.") from None


def _signature(stream) -> tuple:
    context = stream.codec_context
    return (context.name, context.width, context.height, context.format.name, stream.average_rate)


def join_videos(
    chunks: list[Path], out: Path, audio: Path | None = None, whole_speech: bool = True
) -> JoinResult:
    """Copy the chunks' video packets in order into `out` (MP4), with the audio file as AAC from the first
    frame on, cut to the video's length. The chunks must share codec, size, pixel format and frame rate.

    whole_speech: the chunks must hold the whole speech (a farm's join; a shorter video means a chunk is
    missing); False where the video is a frame range the user chose (one render's own sound).
    """
    if not chunks:
        raise VideoError("No chunks to join: give the rendered chunk videos in frame order.")
    av = _require_av()
    out = Path(out)
    partial = out.with_name(out.stem + ".joining" + out.suffix)
    inputs = []
    try:
        for chunk in chunks:
            inputs.append(_open(av, Path(chunk)))
        streams = _same_video_streams(chunks, inputs)
        rate = Fraction(streams[0].average_rate)
        out.parent.mkdir(parents=True, exist_ok=True)
        with av.open(os.fspath(partial), "w", format="mp4") as output:
            video_out = output.add_stream_from_template(streams[0])
            audio_out = output.add_stream("aac", rate=AUDIO_RATE, layout="mono") if audio else None
            chunk_frames = _copy_video(chunks, inputs, streams, output, video_out, rate)
            frames = sum(chunk_frames)
            seconds = float(frames / rate)
            if audio_out is not None:
                _encode_audio(
                    av, output, audio_out, Path(audio), seconds, float(1 / rate), frames, whole_speech
                )
        os.replace(partial, out)
    finally:
        for container in inputs:
            container.close()
        partial.unlink(missing_ok=True)
    return JoinResult(out, frames, seconds, tuple(chunk_frames))


def _same_video_streams(chunks: list[Path], inputs: list) -> list:
    """Each chunk's video stream, all encoded alike (codec, size, pixel format, rate, codec set-up)."""
    streams = []
    for chunk, container in zip(chunks, inputs, strict=True):
        if not container.streams.video:
            raise VideoError(f"{chunk} holds no video stream; render this chunk again.")
        streams.append(container.streams.video[0])
    first = _signature(streams[0])
    for chunk, stream in zip(chunks, streams, strict=True):
        if (
            _signature(stream) != first
            or stream.codec_context.extradata != streams[0].codec_context.extradata
        ):
            raise VideoError(
                f"{chunk} was encoded differently from {chunks[0]} ({_signature(stream)} against "
                f"{first}): render every chunk from the same .blend with the same render.py settings."
            )
    return streams


def _copy_video(
    chunks: list[Path], inputs: list, streams: list, output, video_out, rate: Fraction
) -> list[int]:
    """The chunks' packets muxed one after another, each chunk's times moved on by the frames before it;
    returns each chunk's frame count. A chunk that overlaps the one before is refused."""
    chunk_frames: list[int] = []
    frames = 0
    last_dts = None
    for chunk, container, stream in zip(chunks, inputs, streams, strict=True):
        offset = round(Fraction(frames) / rate / stream.time_base)
        count = 0
        for packet in container.demux(stream):
            if packet.dts is None:  # the demuxer's end-of-stream marker
                continue
            packet.pts += offset
            packet.dts += offset
            seconds = float(packet.dts * stream.time_base)
            if last_dts is not None and seconds <= last_dts:
                raise VideoError(
                    f"{chunk} overlaps the chunk before it (a frame at {seconds:.3f} s again): give each "
                    "frame range once, in order."
                )
            last_dts = seconds
            packet.stream = video_out
            output.mux(packet)
            count += 1
        chunk_frames.append(count)
        frames += count
    return chunk_frames


def _encode_audio(
    av, output, stream, audio: Path, seconds: float, frame_seconds: float, frames: int, whole_speech: bool
) -> None:
    """The audio file as mono AAC, exactly `seconds` long (padded with silence after the speech).

    With whole_speech, speech longer than the video by more than a frame means a chunk is missing: refused,
    not cut.
    """
    samples_left = int(round(seconds * AUDIO_RATE))
    resampler = av.AudioResampler(format="fltp", layout="mono", rate=AUDIO_RATE)
    try:
        source = av.open(os.fspath(audio))
    except (OSError, av.error.FFmpegError) as error:
        raise AudioError(
            f"Cannot read the speech audio {audio}: {error}. Generate the animation again."
        ) from None
    with source:
        if not source.streams.audio:
            raise AudioError(f"{audio} holds no audio stream; give the speech WAV.")
        blocks = []
        for frame in source.decode(source.streams.audio[0]):
            blocks += [resampled.to_ndarray()[0] for resampled in resampler.resample(frame)]
        blocks += [resampled.to_ndarray()[0] for resampled in resampler.resample(None)]
    samples = np.concatenate(blocks) if blocks else np.zeros(0, dtype=np.float32)
    speech = samples.size / AUDIO_RATE
    if whole_speech and speech > seconds + frame_seconds + 0.01:
        raise VideoError(
            f"The chunks hold {frames} frames ({seconds:.2f} s) and the speech {audio} lasts {speech:.2f} s: "
            f"a chunk of the frame range is missing (about {round((speech - seconds) / frame_seconds)} "
            "frames); join every chunk, in order."
        )
    samples = np.pad(samples[:samples_left], (0, max(0, samples_left - samples.size)))
    frame = av.AudioFrame.from_ndarray(
        np.ascontiguousarray(samples[None, :], dtype=np.float32), "fltp", "mono"
    )
    frame.sample_rate = AUDIO_RATE
    for packet in stream.encode(frame):
        output.mux(packet)
    for packet in stream.encode(None):
        output.mux(packet)
