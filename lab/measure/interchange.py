"""How well cue files carry our timing, and how fast chunks join.

    python -m lab.measure.interchange [--fps 25] [--sentences 20]

1. Cue files as the timing source: every sentence of examples/corpus_tr.txt (the first N) is timed by eSpeak
   NG's phones, written in each cue format, read back as the timing source of the same text, and each
   letter's and word's start compared with the original: median, 90th percentile and maximum error (ms), and
   the share of letters within a frame. A second pass reads cues of a slower reading (every time x1.3 after
   0.2 s of silence) and compares with the original stretched alike.
2. The join: three lossless H.264 chunks of 960x540 (250 frames each, made with PyAV) joined with a WAV into
   one MP4: the median time of 3 runs.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from lab.kit.corpus import corpus_sentences
from turkish_lipsync.core.speech import synthesize_timeline
from turkish_lipsync.core.speech.cue_timing import timeline_from_cues
from turkish_lipsync.core.speech.cues import cue_formats, read_cue_file
from turkish_lipsync.core.text.utterance import build_utterance


def _stretched(path: Path, factor: float, lead_in: float) -> None:
    document = json.loads(path.read_text(encoding="utf-8"))
    for cue in document["mouthCues"]:
        cue["start"], cue["end"] = lead_in + factor * cue["start"], lead_in + factor * cue["end"]
    document["mouthCues"].insert(0, {"start": 0.0, "end": lead_in, "value": "X"})
    path.write_text(json.dumps(document), encoding="utf-8")


def measure_cue_timing(sentences: list[str], fps: float) -> None:
    errors: dict[str, tuple[list[float], list[float]]] = {}
    with tempfile.TemporaryDirectory() as folder:
        for number, sentence in enumerate(sentences):
            utterance = build_utterance(sentence)
            timeline = synthesize_timeline(utterance, "phone").timeline
            for export_format in (*cue_formats(), "stretched rhubarb-json"):
                stretched = export_format.startswith("stretched")
                name = export_format.split()[-1]
                cue_format = cue_formats()[name]
                path = Path(folder) / f"{number}{cue_format.suffixes[0]}"
                path.write_text(cue_format.write(timeline, fps)[0], encoding="utf-8")
                factor, lead_in = (1.3, 0.2) if stretched else (1.0, 0.0)
                if stretched:
                    _stretched(path, factor, lead_in)
                imported, _ = timeline_from_cues(utterance, read_cue_file(path, fps))
                letters, words = errors.setdefault(export_format, ([], []))
                for original, phone in zip(timeline.phones, imported.phones, strict=True):
                    letters.append(abs(phone.start - (lead_in + factor * original.start)))
                for original, word in zip(timeline.words, imported.words, strict=True):
                    words.append(abs(word.start - (lead_in + factor * original.start)))
    print(f"cue files as the timing source, {len(sentences)} sentences at {fps:g} fps (errors in ms):")
    print("format | letters: median p90 max, within a frame | words: median p90 max")
    for export_format, (letters, words) in errors.items():
        letter_ms, word_ms = np.array(letters) * 1000, np.array(words) * 1000
        within = (np.array(letters) <= 1 / fps + 1e-9).mean() * 100
        letter_figures = (
            f"{np.median(letter_ms):.0f} {np.percentile(letter_ms, 90):.0f} {letter_ms.max():.0f}"
        )
        word_figures = f"{np.median(word_ms):.0f} {np.percentile(word_ms, 90):.0f} {word_ms.max():.0f}"
        print(f"{export_format} | {letter_figures}, {within:.0f}% | {word_figures}")


def measure_join(repeats: int = 3) -> None:
    import av
    import soundfile

    from turkish_lipsync.core.interchange.video import join_videos

    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        rng = np.random.default_rng(0)
        base = rng.integers(0, 255, (540, 960, 3), dtype=np.uint8)
        chunks = []
        for number in range(3):
            chunks.append(folder / f"chunk{number}.mp4")
            with av.open(str(chunks[-1]), "w") as out:
                stream = out.add_stream("libx264", rate=25, options={"qp": "0", "bf": "0"})
                stream.width, stream.height, stream.pix_fmt = 960, 540, "yuv444p"
                for frame in range(250):
                    picture = np.roll(base, 4 * (number * 250 + frame), axis=1)
                    for packet in stream.encode(av.VideoFrame.from_ndarray(picture, format="rgb24")):
                        out.mux(packet)
                for packet in stream.encode(None):
                    out.mux(packet)
        wav = folder / "speech.wav"
        soundfile.write(wav, np.zeros(30 * 22050, dtype=np.int16), 22050)
        megabytes = sum(chunk.stat().st_size for chunk in chunks) / 1e6
        timings = []
        for _ in range(repeats):
            started = time.perf_counter()
            joined = join_videos(chunks, folder / "joined.mp4", wav)
            timings.append(time.perf_counter() - started)
        seconds = float(np.median(timings))
        print(
            f"join: 3 chunks, {joined.frame_count} frames of 960x540 lossless H.264 ({megabytes:.0f} MB) + "
            f"30 s of speech: {seconds:.2f} s ({joined.frame_count / seconds:.0f} frames/s)"
        )


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--fps", type=float, default=25.0)
    parser.add_argument("--sentences", type=int, default=20)
    arguments = parser.parse_args()
    measure_cue_timing(corpus_sentences()[: arguments.sentences], arguments.fps)
    measure_join()
    return 0


if __name__ == "__main__":
    sys.exit(main())
