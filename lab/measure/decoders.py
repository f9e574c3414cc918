"""Recordings as they arrive (MP3, M4A, the sound tracks of MP4, MOV, MKV and WebM videos, OGG Opus): how
each decoder keeps a take's timing and length, and how far the alignment of each encoding lies from its WAV's.

    python -m lab.measure.decoders [--blender] [--sentences N]

Each held-out sentence of examples/corpus_tr.txt (lines 31-50) is read by eSpeak NG a little slower and
higher after 0.4 s of faint noise (lab/kit/encoded_takes.py), written as a 44.1 kHz stereo WAV and encoded
as each of ENCODINGS with PyAV (FFmpeg's encoders: LAME, FFmpeg's AAC, libopus; each at its own rate and
channel count). Per format and decoder it prints the largest shift of the sound against the WAV (by
cross-correlation, ms) and the largest difference of length (ms); then, for the decoder the chain chooses,
the phone and word onsets of the take aligned to its text against the WAV's (median and max, ms). With
--blender (in a venv whose bpy has audio: 4.5, 5.0), Blender's own FFmpeg (aud) is registered as the add-on
registers it, and reads the AAC and the videos before PyAV.

Not a test: the figures go into docs/developer/measured/timing-and-recordings.md.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

from lab.kit.corpus import held_out_sentences
from lab.kit.encoded_takes import (
    ENCODINGS,
    REFERENCE_RATE,
    lag_seconds,
    write_takes,
)
from turkish_lipsync.core.speech import synthesize_timeline
from turkish_lipsync.core.speech.audio import decode_audio
from turkish_lipsync.core.speech.decoders import DECODERS, sniff_format
from turkish_lipsync.core.text.utterance import build_utterance

WAV_RATE = REFERENCE_RATE


def decoder_shifts(paths: dict[str, Path], shifts: dict, lengths: dict) -> None:
    """Each available decoder's shift and length difference on each encoding, gathered by (format, name)."""
    reference = decode_audio(paths["wav"]).samples
    for name in ENCODINGS:
        audio_format = sniff_format(paths[name])
        for decoder in DECODERS.entries().values():
            if decoder.claims(audio_format) and not decoder.missing():
                samples, rate = decoder.decode(paths[name], audio_format)
                shifts.setdefault((name, decoder.name), []).append(lag_seconds(samples, rate, reference))
                extra = samples.size / rate - reference.size / WAV_RATE
                lengths.setdefault((name, decoder.name), []).append(extra)


def onset_differences(text: str, paths: dict[str, Path], phones: dict, words: dict) -> None:
    """Each encoding's onsets against the WAV's; "wav again" is the WAV aligned once more at the end, the
    spread of the alignment itself (eSpeak NG's rendition moves a little with what it spoke before)."""
    utterance = build_utterance(text)
    timelines = {name: synthesize_timeline(utterance, recording=p).timeline for name, p in paths.items()}
    timelines["wav again"] = synthesize_timeline(utterance, recording=paths["wav"]).timeline
    for name in [*ENCODINGS, "wav again"]:
        for kind, gathered in (("phones", phones), ("words", words)):
            found = [item.start for item in getattr(timelines[name], kind)]
            wav = [item.start for item in getattr(timelines["wav"], kind)]
            gathered.setdefault(name, []).extend(np.abs(np.subtract(found, wav)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--blender", action="store_true", help="register Blender's own decoder (aud)")
    parser.add_argument("--sentences", type=int, default=20, help="how many held-out sentences")
    arguments = parser.parse_args()
    if arguments.blender:
        from turkish_lipsync.blender import audio_decoding

        audio_decoding.register()
    shifts, lengths, phones, words, chosen = {}, {}, {}, {}, {}
    sentences = held_out_sentences()[: arguments.sentences]
    for number, text in enumerate(sentences, start=1):
        with tempfile.TemporaryDirectory() as folder:
            paths = write_takes(Path(folder), text)
            chosen |= {name: decode_audio(paths[name]).decoder for name in ["wav", *ENCODINGS]}
            decoder_shifts(paths, shifts, lengths)
            onset_differences(text, paths, phones, words)
        print(f"sentence {number}/{len(sentences)}", file=sys.stderr, flush=True)
    print("| format | decoder | rate, channels | largest shift (ms) | largest length difference (ms) |")
    print("|---|---|---|---|---|")
    for (name, decoder), values in shifts.items():
        codec, rate, channels, video = ENCODINGS[name]
        kind = f"{name} ({codec}{', ' + video if video else ''})"
        shift = max(np.abs(values)) * 1000
        longest = max(np.abs(lengths[name, decoder])) * 1000
        print(f"| {kind} | {decoder} | {rate} Hz, {channels} | {shift:.2f} | {longest:.2f} |")
    print()
    print("| format | decoder | phones | phones vs WAV: median, max (ms) | over 10 ms | words: max (ms) |")
    print("|---|---|---|---|---|---|")
    for name, values in phones.items():
        median, largest = np.median(values) * 1000, max(values) * 1000
        decoder = chosen[name.removesuffix(" again")]
        over = int(np.count_nonzero(np.asarray(values) > 0.0105))
        print(f"| {name} | {decoder} | {len(values)} | {median:.1f}, {largest:.1f} | {over} | "
              f"{max(words[name]) * 1000:.1f} |")  # fmt: skip


if __name__ == "__main__":
    main()
