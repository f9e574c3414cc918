"""How far the thesis's word timing and the engine-free table timing land from the phones eSpeak NG speaks.

    python -m lab.measure.timing [--text TEXT | FILE ...] [--minutes N]

Prints, per mode, the median, 90th percentile and maximum onset error in milliseconds over every letter,
measured against phone timing (each letter keyed on the phone the engine spoke for it). Then the speed:
synthesis real-time factor, and for a long text (--minutes, default 10) the time and peak Python memory
of synthesis, phone alignment and the alignment of a recording (the same text read slower and higher).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

import numpy as np

from turkish_lipsync.core.base.errors import LipSyncError
from turkish_lipsync.core.speech import synthesize_timeline, write_wav
from turkish_lipsync.core.text.utterance import build_utterance

SENTENCES = (
    "Bugün hava çok güzel, parka gidelim mi?",
    "Öğretmenimiz derste bize Türkiye'nin coğrafyasını anlattı.",
    "Ağabeyim sabahleyin erkenden kalkıp bahçeyi suladı.",
    "Yağmur yağınca sokaklar göle döndü ve çocuklar ıslandı.",
    "Mehmet kahvesini içerken gazetenin spor sayfasını okuyordu.",
    "İstanbul Boğazı'nın iki yakasını köprüler birbirine bağlar.",
    "Cumhuriyet bayramında okulumuzda büyük bir tören düzenlendi.",
    "Şu ağacın gölgesinde biraz dinlenelim, çok yorulduk.",
    "Annem akşam yemeği için zeytinyağlı fasulye pişirdi.",
    "Uçağımız rüzgâr yüzünden bir saat gecikti.",
    "Ilık bir rüzgâr denizden kıyıya doğru esiyordu.",
    "Hayır, o kalemi ben almadım, masanın üstündeydi.",
    "Elli yaşındaki adam hâlâ her sabah koşuyor.",
    "Eğer yarın kar yağarsa okullar tatil olacak.",
)


def onset_errors(text: str) -> dict[str, np.ndarray]:
    """Per mode, |letter onset - phone-timing onset| in ms."""
    utterance = build_utterance(text)
    phone = synthesize_timeline(utterance, "phone").timeline
    truth = np.array([p.start for p in phone.phones])
    errors = {}
    for mode in ("word", "table"):
        timeline = synthesize_timeline(utterance, mode).timeline
        errors[mode] = 1000 * np.abs(np.array([p.start for p in timeline.phones]) - truth)
    return errors


def print_comparison(texts: list[str]) -> None:
    collected: dict[str, list[np.ndarray]] = {"word": [], "table": []}
    for text in texts:
        for mode, errors in onset_errors(text).items():
            collected[mode].append(errors)
    letters = sum(errors.size for errors in collected["word"])
    print(f"onset error against phone timing, {len(texts)} texts, {letters} letters (ms)")
    print(f"{'mode':<8}{'median':>10}{'p90':>10}{'max':>10}")
    for mode, parts in collected.items():
        errors = np.concatenate(parts)
        print(f"{mode:<8}{np.median(errors):>10.1f}{np.percentile(errors, 90):>10.1f}{errors.max():>10.1f}")


def print_speed(minutes: float) -> None:
    one_pass = synthesize_timeline(build_utterance(" ".join(SENTENCES))).synthesis.duration
    repeats = max(1, round(minutes * 60 / one_pass))
    text = " ".join(SENTENCES * repeats)
    utterance = build_utterance(text)
    tracemalloc.start()
    began = time.perf_counter()
    synthesis = synthesize_timeline(utterance).synthesis
    elapsed = time.perf_counter() - began
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    audio_bytes = synthesis.samples.nbytes
    print(
        f"\nphone timing of {len(utterance.words)} words, {synthesis.duration / 60:.1f} min of speech: "
        f"{elapsed:.2f} s, real-time factor {synthesis.duration / elapsed:.0f}x, "
        f"peak Python memory {peak / 1e6:.0f} MB (audio {audio_bytes / 1e6:.0f} MB)"
    )
    slow = build_utterance(f'<PROS RATE="-25%" PITCH="+30%">{text}</PROS>')
    speech = synthesize_timeline(slow)  # the truth must come from the same run as the audio
    slow_truth, reading = speech.timeline, speech.synthesis
    with tempfile.TemporaryDirectory() as folder:
        path = write_wav(Path(folder) / "reading.wav", reading)
        tracemalloc.start()
        began = time.perf_counter()
        aligned = synthesize_timeline(utterance, recording=path).timeline
        elapsed = time.perf_counter() - began
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    error = 1000 * np.abs(
        np.array([p.start for p in aligned.phones]) - np.array([p.start for p in slow_truth.phones])
    )
    print(
        f"recording alignment of {reading.duration / 60:.1f} min: {elapsed:.2f} s "
        f"(real-time factor {reading.duration / elapsed:.0f}x), peak Python memory {peak / 1e6:.0f} MB; "
        f"onset error median {np.median(error):.1f} ms, p90 {np.percentile(error, 90):.1f} ms, "
        f"max {error.max():.0f} ms"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("files", nargs="*", type=Path, help="text or JSML files (default: some sentences)")
    parser.add_argument("--text", help="compare on this text instead")
    parser.add_argument("--minutes", type=float, default=10.0, help="length of the speed test (0: skip)")
    args = parser.parse_args(argv)
    try:
        if args.text:
            texts = [args.text]
        elif args.files:
            texts = [path.read_text(encoding="utf-8") for path in args.files]
        else:
            texts = list(SENTENCES)
        print_comparison(texts)
        if args.minutes > 0:
            print_speed(args.minutes)
    except (LipSyncError, OSError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
