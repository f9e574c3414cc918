"""Train the acoustic model's network on eSpeak NG's speech and people's, and write its weights.

    nice -n 10 /path/to/recogniser-venv/bin/python -m lab.train.recogniser [--clips 5000] [--epochs 14]
        [--seed 7] [--cache DIR] [--out turkish_lipsync/core/speech/acoustic/phone_network.npz]

Set-up (once, outside the repository; torch is never a dependency of the extension, which runs the
network with numpy alone, acoustic/network.py):

    python3.11 -m venv ~/recogniser-venv
    ~/recogniser-venv/bin/pip install torch==2.13.0 -r requirements-dev.txt

What it does, every step seeded (the same seed gives the same corpus, voices, degradations and initial
weights; torch's CPU kernels may still differ in the last bits between machines):

1. Texts: the tuning sentences of examples/corpus_tr.txt (lines 1-30) and random sentences of wordfreq's
   Turkish words; the held-out sentences (lines 31-50) and their words are never used.
2. Voices: eSpeak NG's Turkish voice in every variant of its data but the held-out ones (HELD_OUT_VARIANTS,
   which lab/measure/recogniser.py speaks), at random rates (-30 %..+45 %) and pitches (-45 %..+45 %);
   the labels are the engine's own phone events matched to the letters (speech/align.py), one per 10 ms
   frame (acoustic/labels.py).
3. Degradations, drawn per clip: a speed change by resampling (formants and pitch up or down by up to
   12 %, as another vocal tract), a synthetic room (RT60 0.15-0.8 s), a telephone or a muffled band, room
   noise (white, pink, brown, babble-like) at 0-40 dB SNR or none, synthetic music underneath, noise or
   silence before and after the speech. Some clips are music or noise alone, labelled silence, so that a
   take without speech is recognised as such.
4. The network (acoustic/network.py's layout): a convolution over five frames, five residual blocks of
   dilated convolutions (dilations 1, 2, 4, 8, 16: it hears 0.35 s each side) and a softmax over the
   letters and silence, trained with Adam on frame-wise cross-entropy.
5. Rounds on people's speech (lab/kit/people.py's tune part, each recording clean and degraded), whose
   letters the previous round's network places by forced alignment to their Turkish spelling (--rounds).
6. A last round, FINAL_EPOCHS on from those weights at FINAL_LEARNING_RATE: every clip levelled as the
   extension levels it (acoustic/features.py: a take with little speech partly on people's long-term
   spectrum; the earlier rounds level each clip on itself), SHORT_CLIP_SHARE of eSpeak NG's clips cut to
   one or two words, half of every batch's clips heard through another vocal tract (FINAL_BAND_WARP).
   Rounds whose weights are in the cache (--cache) are not trained again; the last round's are kept there
   too, for lab/train/many_voices.py (the round on many people's voices) to go on from.
7. Written with it: each class's share of the frames (the decoder divides the posteriors by it), the
   letter-to-letter transition counts of the training texts (the decoder's bigram), the shortest
   durations, the training voices and the held-out ones; and beside it the long-term spectrum of the
   people's lines (acoustic/features.py levels a short take partly on it; --spectrum writes it alone).
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import re
import shutil
import sys
import time
from pathlib import Path

import numpy as np

from lab.kit import people
from lab.kit.corpus import held_out_sentences, tuning_sentences
from lab.kit.degradations import degrade, non_speech
from lab.kit.voices import speak_variant
from turkish_lipsync.core.base.errors import LipSyncError
from turkish_lipsync.core.speech.acoustic.features import (
    FEATURE_COUNT,
    LONG_TERM_SPECTRUM_FILE,
    log_bands,
    own_level_weight,
    recogniser_features,
    speech_levels,
)
from turkish_lipsync.core.speech.acoustic.forced import (
    PRIOR_WEIGHT,
    force_align,
    letter_model,
    text_units,
)
from turkish_lipsync.core.speech.acoustic.labels import CLASSES, FRAME_SECONDS, frame_labels
from turkish_lipsync.core.speech.acoustic.network import (
    DILATIONS,
    FIRST_KERNEL,
    KERNEL,
    WEIGHTS_FILE,
    load_network,
)
from turkish_lipsync.core.speech.features import ANALYSIS_RATE, frame_count
from turkish_lipsync.core.text.utterance import build_utterance

# Spoken only by lab/measure/recogniser.py: voices the network never heard.
HELD_OUT_VARIANTS = ("m3", "f4", "klatt3", "Andrea", "benjamin", "steph2", "iven2", "grandpa")
TURKISH_WORD = re.compile(r"^[abcçdefgğhıijklmnoöprsştuüvyz]+$")
CROP_FRAMES = 400
NON_SPEECH_SHARE = 0.05
LABEL_DURATION_SCALE = 0.5  # people's letters may be half as long as the shortest of eSpeak's
WORST_FITTING_SHARE = 0.1  # people's recordings whose spelling fits worst, left out of training
SHORT_CLIP_SHARE = 0.3  # of the last round's eSpeak NG clips: one or two words, as a take of a word
FINAL_EPOCHS = 10  # the last round goes on from round `--rounds`' weights ...
FINAL_LEARNING_RATE = 5e-4  # ... at a quarter of the learning rate
# ... and half its clips heard through another vocal tract, drawn anew each time: the mel bands stretched or
# squeezed by up to FINAL_BAND_WARP (formants up or down by a tenth, as a child's, a woman's or a man's),
# which the recorded clips' own resampling (degrade) covers only once per clip. Without it the round heard
# a one-letter "o" of a voice shifted up as "a", and put it 600 ms early (lab/measure/recordings.py,
# "a person").
FINAL_BAND_WARP = 0.12
CHANNELS = 128  # the network's width (acoustic/network.py runs the width its weights have)


def training_variants() -> list[str]:
    """Every variant in eSpeak NG's data (the espeakng-loader wheel's) but the held-out ones."""
    import espeakng_loader

    folder = Path(espeakng_loader.get_data_path()) / "voices" / "!v"
    return sorted(name.name for name in folder.iterdir() if name.name not in HELD_OUT_VARIANTS)


def training_texts(count: int, rng: np.random.Generator) -> list[str]:
    """The tuning sentences and random sentences of real Turkish words (none of the held-out ones)."""
    import wordfreq

    forbidden = {word for line in held_out_sentences() for word in re.findall(r"\w+", line.lower())}
    words = [word for word in wordfreq.top_n_list("tr", 30_000) if TURKISH_WORD.match(word)]
    words = [word for word in words if word not in forbidden]
    weights = 1.0 / np.sqrt(np.arange(1, len(words) + 1))
    weights /= weights.sum()
    texts = tuning_sentences()
    while len(texts) < count:
        chosen = rng.choice(len(words), size=int(rng.integers(3, 15)), p=weights)
        sentence = ""
        for position, index in enumerate(chosen):
            sentence += (" " if position else "") + words[index]
            if position + 1 < len(chosen) and rng.random() < 0.12:
                sentence += ","
        texts.append(sentence[0].upper() + sentence[1:] + rng.choice([".", ".", ".", "?", "!"]))
    return texts


# ---------------------------------------------------------------- degradations (16 kHz)


# ---------------------------------------------------------------- the corpus


def make_clip(job: tuple) -> tuple[np.ndarray, np.ndarray]:
    """Features and frame labels of one clip (degraded_clip), levelled as whole_take_level says."""
    *clip, whole_take_level = job
    samples, labels = degraded_clip(*clip)
    return recogniser_features(samples, whole_take_level).astype(np.float16), labels


def degraded_clip(
    text: str, variant: str, pitch: int, rate: int, seed: int, short: bool
) -> tuple[np.ndarray, np.ndarray]:
    """16 kHz samples of one clip and a label for each of its frames: a text in a voice, degraded (no
    text: music or noise, all silence).

    A short clip is one or two words of the spoken text, cut at the engine's word times with a little
    of what is around them: a take that holds one word, as a person's recording of a word does.
    """
    rng = np.random.default_rng(seed)
    if not text:
        samples = non_speech(rng)
        return samples, np.zeros(frame_count(samples.size), np.uint8)
    clean, timeline = speak_variant(text, variant, pitch, rate, stops_at_bursts=True)
    if not short:
        samples, lead, stretch = degrade(clean, rng)
        count = frame_count(samples.size)
        labels = frame_labels(timeline, count, stretch)
        offset = int(round(lead / FRAME_SECONDS))
        labels = np.concatenate((np.zeros(offset, np.uint8), labels))[:count]
        return samples, np.pad(labels, (0, count - len(labels)))
    hop = int(round(FRAME_SECONDS * ANALYSIS_RATE))
    labels = frame_labels(timeline, clean.size // hop + 1)
    words = timeline.words
    first = int(rng.integers(0, len(words)))
    last = min(len(words) - 1, first + int(rng.integers(0, 2)))
    begin = max(0, int((words[first].start - rng.uniform(0.03, 0.15)) / FRAME_SECONDS))
    stop = min(labels.size, int(np.ceil((words[last].end + rng.uniform(0.03, 0.15)) / FRAME_SECONDS)))
    samples, lead, stretch = degrade(clean[begin * hop : stop * hop], rng)
    return samples, moved_labels(labels[begin:stop], frame_count(samples.size), lead, stretch)


def moved_labels(labels: np.ndarray, count: int, lead: float, stretch: float) -> np.ndarray:
    """`count` frame labels of a degraded clip from its clean clip's labels (degrade's lead and stretch)."""
    offset = int(round(lead / FRAME_SECONDS))
    source = np.round((np.arange(count) - offset) / stretch).astype(np.int64)
    inside = (source >= 0) & (source < labels.size)
    moved = np.zeros(count, np.uint8)
    moved[inside] = labels[source[inside]]
    return moved


def make_corpus(count: int, seed: int, cache: Path, whole_take_level: bool = True) -> Path:
    """The eSpeak NG clips (the same texts and voices for a seed); without whole_take_level, levelled as
    the extension levels them and SHORT_CLIP_SHARE of them cut to a word or two."""
    path = cache / (f"corpus_{count}_{seed}.npz" if whole_take_level else f"corpus_{count}_{seed}_short.npz")
    if path.exists():
        return path
    rng = np.random.default_rng(seed)
    cuts = np.random.default_rng(seed + 500_000)
    texts = training_texts(count, rng)
    variants = training_variants()
    jobs = []
    for number, text in enumerate(texts):
        voice = (str(rng.choice(variants)), int(rng.integers(-45, 46)), int(rng.integers(-30, 46)))
        short = not whole_take_level and bool(cuts.random() < SHORT_CLIP_SHARE)
        jobs.append((text, *voice, seed + number, short, whole_take_level))
    jobs += [
        ("", "", 0, 0, seed + 100_000 + extra, False, whole_take_level)
        for extra in range(int(NON_SPEECH_SHARE * count))
    ]
    began = time.time()
    with multiprocessing.Pool(2) as pool:
        results = pool.map(make_clip, jobs, chunksize=16)
    features = np.concatenate([result[0] for result in results])
    labels = np.concatenate([result[1] for result in results])
    lengths = np.array([len(result[1]) for result in results])
    cache.mkdir(parents=True, exist_ok=True)
    np.savez(path, features=features, labels=labels, lengths=lengths)
    print(f"corpus: {len(jobs)} clips, {labels.size / 360000:.2f} h, {time.time() - began:.0f} s", flush=True)
    return path


# ---------------------------------------------------------------- people's speech


def people_labels(recording, network) -> tuple[np.ndarray, np.ndarray, float] | None:
    """16 kHz samples of a person's recording, frame labels from its Turkish spelling, and the fit.

    The labels come from forced alignment (acoustic/forced.py) with the previous round's network: the
    spelling fixes the letters and their order, the network only where each lies. The fit is the mean per
    frame of how much worse the forced path scores than the best class (0: the spelling fits every frame).
    """
    samples = people.read(recording, ANALYSIS_RATE)
    features = recogniser_features(samples, whole_take_level=True)  # as the labelling rounds learnt
    log_posteriors = network.log_posteriors(features)
    try:
        units = text_units(build_utterance(recording.turkish))
    except LipSyncError:
        return None
    if units.classes.size == 0:
        return None
    shortest = np.maximum(1, np.round(network.shortest * LABEL_DURATION_SCALE)).astype(np.int64)
    model = letter_model(units.classes, units.word_starts, shortest)
    if model.classes.size > len(features):
        return None
    alignment = force_align(log_posteriors, network.priors, model)
    labels = np.where(alignment.frame_letters >= 0, units.classes[alignment.frame_letters], 0).astype(
        np.uint8
    )
    scaled = log_posteriors - PRIOR_WEIGHT * np.log(network.priors)[None, :]
    fit = float(np.mean(alignment.frame_scores - scaled.max(axis=1)))
    return samples, labels, fit


def make_people_clip(job) -> tuple[np.ndarray, np.ndarray]:
    """Features and labels of a person's recording, clean (seed None) or degraded."""
    samples, labels, seed, whole_take_level = job
    if seed is None:
        features = recogniser_features(samples, whole_take_level)
        return features.astype(np.float16), labels[: len(features)]
    degraded, lead, stretch = degrade(samples, np.random.default_rng(seed))
    features = recogniser_features(degraded, whole_take_level)
    return features.astype(np.float16), moved_labels(labels, len(features), lead, stretch)


def make_people_corpus(
    folder: Path,
    network_path: Path,
    copies: int,
    seed: int,
    cache: Path,
    name: str,
    whole_take_level: bool,
    part: str = "tune",
) -> Path:
    """The tune part's recordings (lab/kit/people.py; or the train part's), labelled by the network at
    network_path, each clean and degraded `copies - 1` times; the worst-fitting tenth (a spelling far from
    what is said, laughter, shouts over music) left out. whole_take_level: how the features are levelled."""
    path = cache / f"people_{name}_{copies}_{seed}.npz"
    if path.exists():
        return path
    network = load_network(network_path)
    began = time.time()
    chosen = people.training_recordings(folder) if part == "tune" else people.recordings(folder, part)
    labelled = [people_labels(recording, network) for recording in chosen]
    labelled = [item for item in labelled if item is not None]
    fits = np.array([fit for _, _, fit in labelled])
    kept = [item for item in labelled if item[2] >= np.percentile(fits, 100 * WORST_FITTING_SHARE)]
    jobs = [
        (samples, labels, None if copy == 0 else seed + 1_000_000 * copy + number, whole_take_level)
        for number, (samples, labels, _) in enumerate(kept)
        for copy in range(copies)
    ]
    with multiprocessing.Pool(2) as pool:
        results = pool.map(make_people_clip, jobs, chunksize=16)
    features = np.concatenate([result[0] for result in results])
    labels = np.concatenate([result[1] for result in results])
    lengths = np.array([len(result[1]) for result in results])
    np.savez(path, features=features, labels=labels, lengths=lengths)
    print(
        f"people ({name}): {len(kept)} of {len(labelled)} recordings kept (fit >= "
        f"{np.percentile(fits, 100 * WORST_FITTING_SHARE):.2f}), {len(jobs)} clips, "
        f"{labels.size / 360000:.2f} h, {time.time() - began:.0f} s",
        flush=True,
    )
    return path


def write_long_term_spectrum(folder: Path, out: Path = LONG_TERM_SPECTRUM_FILE) -> None:
    """Band by band, the median spectral shape of the tune part's lines of people (Dutch and Czech: studio
    recordings with and without the high bands) that hold speech enough for their own level
    (features.py levels a short take partly on it)."""
    shapes = []
    for recording in people.recordings(folder, "tune", "line"):
        loudness, shape, level = speech_levels(log_bands(people.read(recording, ANALYSIS_RATE)))
        if own_level_weight(loudness, level) == 1.0:  # speech enough to be levelled on itself alone
            shapes.append(shape)
    np.save(out, np.median(shapes, axis=0).astype(np.float32))
    print(f"wrote {out} (the median of {len(shapes)} lines)")


def warped_bands(torch, bands, most: float, rng: np.random.Generator):
    """A batch's log mel bands (clips x bands x frames), half of the clips' band axis stretched by a factor
    drawn within 1 +- most (linear interpolation between neighbouring bands, the top band held)."""
    count = bands.shape[1]
    grid = torch.arange(count, dtype=torch.float32)
    warped = bands.clone()
    for clip in np.flatnonzero(rng.random(len(bands)) < 0.5):
        position = torch.clamp(grid * float(rng.uniform(1 - most, 1 + most)), 0, count - 1)
        low = position.floor().long()
        high = torch.clamp(low + 1, max=count - 1)
        share = (position - low)[:, None]
        warped[clip] = bands[clip, low] * (1 - share) + bands[clip, high] * share
    return warped


# ---------------------------------------------------------------- statistics the decoder needs


def label_runs(labels: np.ndarray, lengths: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Per clip: the class of each run of equal frame labels and the run's length in frames."""
    out = []
    for clip in np.split(labels, np.cumsum(lengths)[:-1]):
        if clip.size:
            bounds = np.concatenate(([0], np.flatnonzero(np.diff(clip.astype(np.int16))) + 1, [clip.size]))
            out.append((clip[bounds[:-1]], np.diff(bounds)))
    return out


def transition_counts(runs: list[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """How often class b's run follows class a's in the training clips (add-one: nothing is impossible)."""
    counts = np.ones((len(CLASSES), len(CLASSES)))
    for classes, _ in runs:
        np.add.at(counts, (classes[:-1], classes[1:]), 1)
    return counts


def shortest_durations(runs: list[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """Per class, the 5th percentile of its runs' lengths (frames): the decoder's minimum duration."""
    lengths: list[list[int]] = [[] for _ in CLASSES]
    for classes, durations in runs:
        for name, duration in zip(classes, durations, strict=True):
            lengths[name].append(duration)
    return np.array([max(1, int(np.percentile(values or [3], 5))) for values in lengths], np.int16)


# ---------------------------------------------------------------- training (torch)


def build_network(torch, channels: int = CHANNELS):
    nn = torch.nn

    class Block(nn.Module):
        def __init__(self, dilation: int) -> None:
            super().__init__()
            self.dilated = nn.Conv1d(channels, channels, KERNEL, dilation=dilation, padding=dilation)
            self.mix = nn.Conv1d(channels, channels, 1)

        def forward(self, x):
            return x + self.mix(torch.relu(self.dilated(x)))

    class PhoneNetwork(nn.Module):
        def __init__(self) -> None:
            super().__init__()
            self.first = nn.Conv1d(FEATURE_COUNT, channels, FIRST_KERNEL, padding=FIRST_KERNEL // 2)
            self.blocks = nn.ModuleList([Block(dilation) for dilation in DILATIONS])
            self.dropout = nn.Dropout(0.1)
            self.last = nn.Conv1d(channels, len(CLASSES), 1)

        def forward(self, x):
            x = torch.relu(self.first(x))
            for block in self.blocks:
                x = self.dropout(block(x))
            return self.last(torch.relu(x))

    return PhoneNetwork()


def load_corpora(paths: list[Path]) -> dict[str, np.ndarray]:
    """The clips of several corpora one after the other, and which corpus each clip came from."""
    parts = [np.load(path) for path in paths]
    return {
        "features": np.concatenate([part["features"] for part in parts]),
        "labels": np.concatenate([part["labels"] for part in parts]),
        "lengths": np.concatenate([part["lengths"] for part in parts]),
        "sources": np.concatenate([np.full(len(part["lengths"]), n) for n, part in enumerate(parts)]),
    }


def train(
    corpora: list[Path],
    epochs: int,
    seed: int,
    out: Path,
    description: str,
    start: Path | None = None,
    learning_rate: float = 2e-3,
    band_warp: float = 0.0,
    teacher: Path | None = None,
    channels: int = CHANNELS,
    keep_start: bool = False,
    taught: int = 1,
) -> None:
    """Train on the corpora's clips (the first is the project's own speech; its statistics feed the
    decoder), from random weights or those at `start`, and write the weights.

    With a `teacher`, the first `taught` corpora's clips (eSpeak NG's alone by default) learn what that
    network hears in them (its posteriors, frame by frame, through the same augmentation) instead of their
    labels: the student keeps the teacher's hearing of them, its confidence included, while the other
    corpora teach it people's. With more `channels` than the weights at `start` have, those weights are
    grown into the wider network: the new channels start unheard by the old ones, so it begins as the
    start network and learns with the room it gained; with `keep_start`, the start's channels stay as they
    are and hear only each other (what they heard stays exactly the start's), and only the grown channels
    and what the classes hear of them learn."""
    import torch

    torch.manual_seed(seed)
    torch.set_num_threads(2)
    data = load_corpora(corpora)
    features, labels, lengths = data["features"], data["labels"], data["lengths"]
    starts = np.concatenate(([0], np.cumsum(lengths)[:-1]))
    rng = np.random.default_rng(seed)
    clips = rng.permutation(len(lengths))
    validation = clips[: len(clips) // 30]
    training = clips[len(clips) // 30 :]
    network = build_network(torch, channels)
    if start is not None:
        started = _load_weights(torch, network, start)
        if keep_start:
            _keep_weights(torch, network, started)
    teacher_network = _frozen(torch, teacher) if teacher is not None else None
    optimiser = torch.optim.Adam(network.parameters(), lr=learning_rate)
    steps_per_epoch = int(lengths[training].sum() / CROP_FRAMES / 32)
    schedule = torch.optim.lr_scheduler.OneCycleLR(
        optimiser, max_lr=learning_rate, total_steps=epochs * steps_per_epoch, pct_start=0.15
    )
    feature_tensor = torch.from_numpy(features.astype(np.float32))
    label_tensor = torch.from_numpy(np.where(labels < len(CLASSES), labels.astype(np.int64), -100))

    def batch(chosen):
        xs, ys = [], []
        for clip in chosen:
            length = lengths[clip]
            first = starts[clip] + (rng.integers(0, length - CROP_FRAMES + 1) if length > CROP_FRAMES else 0)
            stop = first + min(length, CROP_FRAMES)
            x = feature_tensor[first:stop]
            y = label_tensor[first:stop]
            if len(y) < CROP_FRAMES:  # short clip: padded with silence, not counted
                pad = CROP_FRAMES - len(y)
                x = torch.cat((x, torch.full((pad, FEATURE_COUNT), -6.0)))
                y = torch.cat((y, torch.full((pad,), -100, dtype=torch.int64)))
            xs.append(x.T)
            ys.append(y)
        return torch.stack(xs), torch.stack(ys)

    loss_function = torch.nn.CrossEntropyLoss(ignore_index=-100)
    for epoch in range(epochs):
        began = time.time()
        network.train()
        total = 0.0
        for _ in range(steps_per_epoch):
            chosen = rng.choice(training, size=32)
            x, y = batch(chosen)
            # Channel and level changes the features' levelling does not undo entirely: a random tilt.
            tilt = torch.linspace(-1, 1, FEATURE_COUNT - 1)[None, :, None] * torch.randn(32, 1, 1)
            x[:, :-1] += 0.15 * tilt
            if band_warp:
                x[:, :-1] = warped_bands(torch, x[:, :-1], band_warp, rng)
            if teacher_network is None:
                loss = loss_function(network(x), y)
            else:
                loss = _distilled_loss(
                    torch, network(x), y, x, teacher_network, data["sources"][chosen] < taught
                )
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            schedule.step()
            total += float(loss.detach())
        network.eval()
        right = np.zeros(len(corpora))
        count = np.zeros(len(corpora))
        with torch.no_grad():
            for clip in validation:
                x = feature_tensor[starts[clip] : starts[clip] + lengths[clip]].T[None]
                guess = network(x)[0].argmax(0).numpy()
                truth = labels[starts[clip] : starts[clip] + lengths[clip]]
                right[data["sources"][clip]] += int((guess == truth).sum())
                count[data["sources"][clip]] += int((truth < len(CLASSES)).sum())  # ignored frames aside
        shares = ", ".join(f"{r / max(c, 1):.3f}" for r, c in zip(right, count, strict=True))
        print(
            f"epoch {epoch + 1}/{epochs}: loss {total / steps_per_epoch:.3f}, "
            f"validation frames right {shares} (per corpus), {time.time() - began:.0f} s",
            flush=True,
        )
    export(network, data, out, seed, epochs, description)


def _load_weights(torch, network, path: Path) -> dict[str, tuple[int, ...]]:
    """The weights at `path` into the network, each into its leading channels where the network is wider;
    a wider layer's weights from the new input channels to the old outputs are zero (the old outputs are
    as they were), the new outputs keep their random start. Returns each layer's shape at `path`."""
    state = network.state_dict()
    shapes = {}
    with np.load(path) as weights, torch.no_grad():
        for name, value in state.items():
            old = torch.from_numpy(weights[f"weight/{name}"])
            value[tuple(slice(0, size) for size in old.shape)] = old
            if value.ndim == 3 and value.shape[1] > old.shape[1]:
                value[: old.shape[0], old.shape[1] :] = 0
            shapes[name] = tuple(old.shape)
    network.load_state_dict(state)
    return shapes


def _keep_weights(torch, network, shapes: dict[str, tuple[int, ...]]) -> None:
    """The start's channels stay computed as they were: in every layer but the last, the weights into the
    start's outputs (of these shapes) get no gradient from any input, the grown inputs' included (they
    stay zero); in the last, the start's channels' weights. Only the grown channels learn, and what the
    classes hear of them."""
    for name, parameter in network.named_parameters():
        learns = torch.ones_like(parameter)
        if name.startswith("last."):
            learns[tuple(slice(0, size) for size in shapes[name])] = 0
        else:
            learns[: shapes[name][0]] = 0
        parameter.register_hook(lambda gradient, learns=learns: gradient * learns)


def _frozen(torch, path: Path):
    """A network with the weights at `path`, frozen, to teach."""
    with np.load(path) as weights:
        network = build_network(torch, len(weights["weight/first.weight"]))
    _load_weights(torch, network, path)
    network.eval()
    for parameter in network.parameters():
        parameter.requires_grad_(False)
    return network


def _distilled_loss(torch, logits, y, x, teacher, taught: np.ndarray):
    """Frame-wise cross-entropy: against the labels for the clips not `taught`, against the teacher's
    posteriors for those that are (counted frames only, the padding aside); the mean over all frames."""
    log_student = torch.log_softmax(logits, dim=1)
    counted = y >= 0
    hard = -log_student.gather(1, y.clamp(min=0)[:, None])[:, 0]
    if taught.any():
        with torch.no_grad():
            soft_target = torch.softmax(teacher(x[taught]), dim=1)
        hard[taught] = -(soft_target * log_student[taught]).sum(1)
    return hard[counted].sum() / counted.sum().clamp(min=1)


def export(network, data, out: Path, seed: int, epochs: int, description: str) -> None:
    state = network.state_dict()
    weights = {name: value.detach().numpy().astype(np.float32) for name, value in state.items()}
    labels, lengths = data["labels"], data["lengths"]
    priors = np.bincount(labels[labels < len(CLASSES)], minlength=len(CLASSES)).astype(np.float64) + 1
    # The decoder's Turkish letter transitions and shortest durations: from the Turkish texts alone (the
    # first corpus), not from people's speech in other languages spelt in Turkish letters.
    own = data["sources"] == 0
    own_frames = np.repeat(own, lengths)
    runs = label_runs(labels[own_frames], lengths[own])
    metadata = {
        "classes": list(CLASSES),
        "seed": seed,
        "epochs": epochs,
        "clips": int(len(lengths)),
        "hours": round(float(labels.size) / 360000, 2),
        "training_variants": training_variants(),
        "held_out_variants": list(HELD_OUT_VARIANTS),
        "trained_on": description,
    }
    np.savez_compressed(
        out,
        metadata=np.array(json.dumps(metadata)),
        priors=(priors / priors.sum()).astype(np.float32),
        transitions=transition_counts(runs).astype(np.float32),
        shortest=shortest_durations(runs),
        **{f"weight/{name}": value for name, value in weights.items()},
    )
    print(f"wrote {out} ({out.stat().st_size / 1e6:.2f} MB)")


def labelling_rounds(args, own: str) -> Path:
    """The weights of the last round that labels people's speech (round `--rounds`), trained with the
    rounds before it where the cache does not hold them."""
    last = args.cache / f"round_{args.rounds}_{args.seed}.npz"
    if last.exists():
        return last
    network = args.cache / f"round_0_{args.seed}.npz"
    if not network.exists():
        train([make_corpus(args.clips, args.seed, args.cache)], args.epochs, args.seed, network, own)
    for round_number in range(1, args.rounds + 1):
        name = f"round_{round_number}"
        previous, network = network, args.cache / f"{name}_{args.seed}.npz"
        if not network.exists():
            speech = make_people_corpus(args.people, previous, args.copies, args.seed, args.cache, name, True)
            description = (
                f"{own}; and people's speech (lab/kit/people.py's tune part, labelled by forced alignment "
                f"with round {round_number - 1}'s network, clean and degraded)"
            )
            corpus = make_corpus(args.clips, args.seed, args.cache)
            train([corpus, speech], args.epochs, args.seed, network, description)
    return network


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--clips", type=int, default=5000, help="spoken texts (non-speech clips come on top)")
    parser.add_argument("--epochs", type=int, default=14)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--cache", type=Path, default=Path.home() / ".cache" / "turkish_lipsync_recogniser")
    parser.add_argument("--out", type=Path, default=WEIGHTS_FILE)
    parser.add_argument("--people", type=Path, default=people.FOLDER, help="lab/kit/people.py's folder")
    parser.add_argument("--rounds", type=int, default=2, help="rounds of labelling people's speech")
    parser.add_argument("--copies", type=int, default=3, help="each person's recording: clean and degraded")
    parser.add_argument("--corpus-only", action="store_true", help="make the corpus and stop")
    parser.add_argument("--spectrum", action="store_true", help="only write people's long-term spectrum")
    args = parser.parse_args(argv)
    if args.spectrum:
        write_long_term_spectrum(args.people)
        return 0
    if args.corpus_only:
        make_corpus(args.clips, args.seed, args.cache)
        make_corpus(args.clips, args.seed, args.cache, whole_take_level=False)
        return 0
    args.cache.mkdir(parents=True, exist_ok=True)
    own = "eSpeak NG's Turkish voice (variants, rates, pitches), degraded"
    network = labelling_rounds(args, own)
    # The last round: every clip levelled as the extension levels it (a short take partly on people's
    # long-term spectrum), with short clips among eSpeak NG's; going on from the last round's weights.
    write_long_term_spectrum(args.people)
    corpus = make_corpus(args.clips, args.seed, args.cache, whole_take_level=False)
    name = f"round_{args.rounds + 1}"
    speech = make_people_corpus(args.people, network, args.copies, args.seed, args.cache, name, False)
    description = (
        f"{own}, a third of it cut to a word or two; and people's speech (lab/kit/people.py's tune part, "
        f"labelled by forced alignment with round {args.rounds}'s network, clean and degraded); "
        f"{FINAL_EPOCHS} epochs on from round {args.rounds}'s weights, half the clips' mel bands warped by "
        f"up to {FINAL_BAND_WARP:.0%}"
    )
    train(
        [corpus, speech],
        FINAL_EPOCHS,
        args.seed,
        args.out,
        description,
        network,
        FINAL_LEARNING_RATE,
        FINAL_BAND_WARP,
    )
    shutil.copyfile(args.out, args.cache / f"{name}_{args.seed}.npz")  # lab/train/many_voices.py goes on
    return 0


if __name__ == "__main__":
    sys.exit(main())
