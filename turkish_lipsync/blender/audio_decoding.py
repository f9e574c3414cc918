"""Blender's own FFmpeg reads recordings for the core (through Audaspace's `aud`): AAC in M4A, MP4 and MOV,
the sound tracks of videos, at any rate and channel count. Registered with the core's decoders
(core/speech/decoders/) when the add-on registers, so the zips carry no FFmpeg of their own.

Audaspace decodes the whole file into memory: mixed to one channel first (its own mix sums the channels),
the sound is held twice in float32 for a moment (its buffer and the array it hands over), never in all its
channels at float64.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..core.speech.decoders import DECODERS, AudioDecoder, AudioFormat, DecodeFailed
from ..core.speech.decoders.matroska import first_audio_track
from . import compat


class BlenderAudioDecoder(AudioDecoder):
    name = "blender"
    label = "Blender's FFmpeg"
    order = 30  # after soundfile (WAV, FLAC, OGG, MP3 exactly), before PyAV: Blender's own reads first
    ffmpeg = True

    def decode(self, path: Path, audio_format: AudioFormat) -> tuple[np.ndarray, int]:
        import aud

        try:
            sound = aud.Sound(str(path))
            rate, channels = int(sound.specs[0]), int(sound.specs[1])
            if channels <= 2:  # Audaspace's mix to one channel sums them: halved, it is their mean
                samples = sound.rechannel(1).data()[:, 0]
                if channels == 2:
                    samples *= 0.5
            else:  # its mix of more channels leaves out the LFE: the mean of all, as every decoder takes
                samples = sound.data().mean(axis=1, dtype=np.float32)
            length = int(sound.length)
        except aud.error:
            raise DecodeFailed(
                "it found no sound to read in it (a video without a sound track, or a damaged file)"
            ) from None
        samples = samples[_priming_samples(path, audio_format, rate) :]
        # The padding of an AAC stream's last frame lies past the file's declared duration.
        return (samples[:length] if 0 < length < samples.size else samples), rate


def _priming_samples(path: Path, audio_format: AudioFormat, rate: int) -> int:
    """The encoder's priming samples Blender's FFmpeg decodes as sound (Matroska's CodecDelay; an Opus
    decoder drops its own pre-skip)."""
    if audio_format.name not in ("mkv", "webm") or not compat.FFMPEG_KEEPS_MATROSKA_CODEC_DELAY:
        return 0
    track = first_audio_track(path)
    if track is None or track.codec == "A_OPUS":
        return 0
    return round(track.codec_delay * rate)


def register() -> None:
    if compat.HAS_FFMPEG_AUDIO:
        DECODERS.register(BlenderAudioDecoder)


def unregister() -> None:
    DECODERS.unregister(BlenderAudioDecoder.name)
