"""Recordings of people to tune and measure on, each with a Turkish spelling of what is said, split in two.

    python -m lab.kit.people build [--folder out/people]     # fetch and unpack (apt-get download + dpkg-deb)
    python -m lab.kit.people list [--part tune|report|train] [--kind line|syllable|word]

Sources (Debian packages, fetched with `apt-get download`, unpacked with `dpkg-deb -x`, nothing installed;
all GPL or similar: measured with, never copied into the project):

- `dev/`: ../shared/voices/dev_voices.py's folder (Fish Fillets NG's Dutch voice acting, about 1,500 lines
  with a Turkish spelling of the game's Dutch script; KDE's klettres: about 200 syllables said by native
  speakers of Russian, Ukrainian, Tswana, French and Czech);
- fillets-ng-data-cs: the same game's Czech voice acting (other actors, another language), spelt in
  Turkish letters by `spell_czech` from the game's Czech script;
- ktuberling-data: single English words said by a person (KTuberling's English sound theme), spelt in
  Turkish letters by hand (ENGLISH_WORDS);
- klettres-data's other languages (lab/kit/klettres_syllables.py: Malayalam, Lithuanian, Low German,
  German, Danish, Dutch, Hebrew, English), for training only: the **train** part.

The split keeps tuning apart from reporting: the acoustic model trains on the **tune** part's Dutch lines
(two thirds of the game's levels) and its Russian and Tswana syllables, and the judgement's constants are
tuned on the tune part's Czech lines too (a third of the levels: voices the network never learnt from, as
a user's are); figures are reported on the **report** part (the Dutch lines of the other third of the
levels, the other Czech lines, the Ukrainian, French and Czech syllables, the English words).

`lists_of_eight` joins eight recordings of one speaker with pauses of that speaker's own noise floor, as a
list read aloud with pauses; the truth is where each item's sound starts.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from lab import REPOSITORY
from lab.kit import klettres_syllables

FOLDER = REPOSITORY / "out" / "people"
DEV_VOICES = REPOSITORY.parent / "shared" / "voices" / "dev_voices.py"
PACKAGES = ("fillets-ng-data-cs", "ktuberling-data")
TUNING_SYLLABLES = ("klettres-ru", "klettres-tn")
SENTENCE_WORDS = 3  # lines of at least this many words are sentences
REPORT_EVERY_NTH_LEVEL = 3  # the Dutch lines of levels 0, 3, 6, ... of the sorted level names are reported
# The Czech lines of levels 1, 4, 7, ... tune the judgement's constants (never the network: voices it has
# not heard, as a user's are); the other Czech lines are reported.
CZECH_TUNING_EVERY_NTH_LEVEL = 3

# KTuberling's English words as a Turkish reader would spell what is said (the game names each sound by
# the English word it says; a prefix such as "egypt_" names the playground).
ENGLISH_WORDS = {
    "ball": "bol", "bow": "bou", "coat": "kout", "ear": "iyır", "earring": "iyırring", "eye": "ay",
    "eyebrow": "aybrau", "flower": "flauır", "hair": "heır", "hat": "het", "moustache": "mıstaş",
    "mouth": "mauf", "nose": "nouz", "shoe": "şu", "shorts": "şorts", "skirt": "skört",
    "spectacles": "spektıkılz", "stick": "stik", "sunglasses": "sanglasız", "tie": "tay",
    "umbrella": "ambrela", "bridge": "bric", "birds": "börds", "palmtree": "pam tri", "grass": "gras",
    "camel": "kemıl", "road": "roud", "cart": "kart", "sphynx": "sfinks", "column": "kolım",
    "girl": "görl", "well": "vel", "pyramid": "pirımid", "man": "men", "arch": "arç", "oasis": "oueysis",
    "woman": "vumın", "boy": "boy", "donkey": "donki", "car": "kar", "cyclist": "sayklist",
    "bicycle": "baysikıl", "train": "treyn", "sign": "sayn", "planet": "plenıt", "satellite": "setılayt",
    "radar": "reydar", "moonwalker": "munvokır", "rocket": "rokıt", "ufo": "yufou", "hotel": "houtel",
    "astronaut": "astrınot", "monster": "monstır", "alien": "eyliın", "earth": "örf",
    "fallingstar": "foling star", "star": "star", "anchovy": "ançıvi", "bacon": "beykın",
    "brocolli": "brokıli", "cheese": "çiz", "cucumber": "kyukambır", "mushroom": "maşrum", "olive": "oliv",
    "onion": "anyın", "oregano": "origanou", "pepper": "pepır", "pepperoni": "pepırouni",
    "pineapple": "paynepıl", "salami": "sılami", "tomato": "tımeytou",
}  # fmt: skip

CZECH = (
    ("ch", "h"), ("dě", "dye"), ("tě", "tye"), ("ně", "nye"), ("mě", "mnye"), ("ě", "ye"), ("ř", "rj"),
    ("č", "ç"), ("š", "ş"), ("ž", "j"), ("á", "a"), ("é", "e"), ("í", "i"), ("ý", "i"), ("ó", "o"),
    ("ú", "u"), ("ů", "u"), ("ď", "dy"), ("ť", "ty"), ("ň", "ny"), ("y", "i"), ("j", "y"), ("c", "ts"),
    ("w", "v"), ("x", "ks"), ("q", "kv"),
)  # fmt: skip


@dataclass(frozen=True)
class Recording:
    """One recording of a person: what kind, where from, the file, what is said and its Turkish spelling."""

    kind: str  # line, syllable or word
    source: str  # e.g. fillets-nl/airplane, klettres-uk, ktuberling-en, fillets-cs/airplane
    ident: str
    path: Path
    text: str
    turkish: str
    part: str  # tune or report

    @property
    def speaker(self) -> str:
        """Who speaks, as far as the source tells: a game line's character code (its ident's second
        part, `let-v-oko`: the fish v), else the source (a line named otherwise, `help3`, is a level's)."""
        parts = self.ident.split("-")
        if self.source.startswith("fillets") and len(parts) > 2 and len(parts[1]) == 1:
            return self.source.split("/")[0] + "/" + parts[1]
        return self.source


def spell_czech(text: str) -> str:
    """A Turkish spelling of Czech text: a fixed letter table, close to what is said."""
    spelt = text.lower()
    for written, turkish in CZECH:
        spelt = spelt.replace(written, turkish)
    spelt = re.sub(r"[^a-zçğıöşü .,?!]", " ", spelt)
    return re.sub(r"\s+", " ", spelt).strip()


def build(folder: Path = FOLDER) -> None:
    """The dev voices, then the two held-out packages unpacked, and their manifest."""
    folder.mkdir(parents=True, exist_ok=True)
    if not (folder / "dev" / "manifest.tsv").exists():
        subprocess.run([sys.executable, str(DEV_VOICES), str(folder / "dev")], check=True)
    unpacked = folder / "packages"
    if not (unpacked / "usr/share/ktuberling").is_dir():
        with tempfile.TemporaryDirectory() as temporary:
            fetched = subprocess.run(["apt-get", "download", *PACKAGES], cwd=temporary, capture_output=True)
            if fetched.returncode:
                subprocess.run(["apt-get", "update", "-qq"], capture_output=True)
                subprocess.run(["apt-get", "download", *PACKAGES], cwd=temporary, check=True)
            for package in Path(temporary).glob("*.deb"):
                subprocess.run(["dpkg-deb", "-x", str(package), str(unpacked)], check=True)
    rows = _czech_lines(folder) + _english_words(folder)
    _write_manifest(folder / "held_out.tsv", rows)
    print(f"{len(rows)} held-out recordings in {folder / 'held_out.tsv'}")
    syllables = klettres_syllables.rows(folder / "dev" / "packages" / "usr/share/klettres")
    _write_manifest(folder / "klettres.tsv", syllables)
    print(f"{len(syllables)} syllables to train on in {folder / 'klettres.tsv'}")


def _write_manifest(path: Path, rows: list[tuple[str, ...]]) -> None:
    with open(path, "w", encoding="utf-8") as manifest:
        manifest.write("kind\tsource\tid\twav\ttext\tturkish\n")
        for row in rows:
            manifest.write("\t".join(row) + "\n")


def _czech_lines(folder: Path) -> list[tuple[str, ...]]:
    game = folder / "dev" / "packages" / "usr/share/games/fillets-ng"
    sounds = folder / "packages" / "usr/share/games/fillets-ng/sound"
    rows = []
    for script in sorted(game.glob("script/*/dialogs_cs.lua")):
        level = script.parent.name
        for match in re.finditer(
            r'dialogId\("([^"]+)",[^)]*\)\s*\ndialogStr\("((?:[^"\\]|\\.)*)"\)', script.read_text("utf-8")
        ):
            sound = sounds / level / "cs" / f"{match.group(1)}.ogg"
            said = match.group(2).replace('\\"', '"')
            if sound.exists() and not re.search(r"\d", said) and spell_czech(said):
                rows.append(
                    ("line", f"fillets-cs/{level}", match.group(1), str(sound), said, spell_czech(said))
                )
    return rows


def _english_words(folder: Path) -> list[tuple[str, ...]]:
    theme = folder / "packages" / "usr/share/ktuberling/sounds"
    rows = []
    for name, file in re.findall(
        r'name="([^"]+)" file="([^"]+)"', (theme / "en.soundtheme").read_text("utf-8")
    ):
        word = name.split("_")[-1]
        if word in ENGLISH_WORDS and (theme / file).exists():
            rows.append(("word", "ktuberling-en", name, str(theme / file), word, ENGLISH_WORDS[word]))
    return rows


def training_recordings(folder: Path = FOLDER) -> list[Recording]:
    """What the acoustic model learns from: the tune part but its Czech lines (the train part, KLettres'
    other languages, is a corpus of its own: recordings(folder, "train"))."""
    return [r for r in recordings(folder, "tune") if not r.source.startswith("fillets-cs")]


def recordings(folder: Path = FOLDER, part: str | None = None, kind: str | None = None) -> list[Recording]:
    """Every recording (or those of one part and kind), in a fixed order."""
    found = []
    levels = sorted(
        {
            row[1]
            for row in _rows(folder / "dev" / "manifest.tsv", folder / "dev")
            if row[1].startswith("fillets")
        }
    )
    reported_levels = set(levels[::REPORT_EVERY_NTH_LEVEL])
    tuning_czech_levels = {
        "fillets-cs/" + level.split("/")[1] for level in levels[1::CZECH_TUNING_EVERY_NTH_LEVEL]
    }
    for manifest, base in (
        (folder / "dev" / "manifest.tsv", folder / "dev"),
        (folder / "held_out.tsv", None),
        (folder / "klettres.tsv", None),
    ):
        for row_kind, source, ident, wav, text, turkish in _rows(manifest, base):
            if source.removeprefix("klettres-") in klettres_syllables.LANGUAGES:
                row_part = "train"
            elif source.startswith("ktuberling"):
                row_part = "report"
            elif source.startswith("fillets-cs"):
                row_part = "tune" if source in tuning_czech_levels else "report"
            elif source.startswith("fillets-nl"):
                row_part = "report" if source in reported_levels else "tune"
            else:
                row_part = "tune" if source in TUNING_SYLLABLES else "report"
            recording = Recording(row_kind, source, ident, Path(wav), text, turkish, row_part)
            if (part is None or part == row_part) and (kind is None or kind == row_kind):
                found.append(recording)
    return found


def sentence_lines(part: str, folder: Path = FOLDER) -> list[Recording]:
    """The voice-acted lines of SENTENCE_WORDS words or more."""
    return [r for r in recordings(folder, part, "line") if len(r.turkish.split()) >= SENTENCE_WORDS]


def _rows(manifest: Path, base: Path | None) -> list[tuple[str, ...]]:
    if not manifest.exists():
        raise SystemExit(f"{manifest} is missing: run `python -m lab.kit.people build` first")
    lines = manifest.read_text(encoding="utf-8").splitlines()[1:]
    rows = []
    for line in lines:
        kind, source, ident, wav, text, turkish = line.split("\t")
        rows.append((kind, source, ident, str(base / wav) if base else wav, text, turkish))
    return rows


def read(recording: Recording, rate: int = 16000) -> np.ndarray:
    """The recording as float samples at `rate`, mono."""
    import soundfile
    import soxr

    samples, native = soundfile.read(str(recording.path), dtype="float32", always_2d=True)
    return soxr.resample(samples.mean(axis=1), native, rate).astype(np.float32)


def sound_onset(samples: np.ndarray, rate: int) -> float:
    """Where a clean recording's sound starts (seconds): the first of 20 ms of 5 ms hops within 30 dB of
    its loudest hops and 10 dB above its quietest, once its DC offset is taken away (the running mean
    over 20 ms). Many of KTuberling's English words sit on an offset as loud as their speech, with a
    click where the file starts: neither is a sound that starts."""
    hop = rate // 200
    samples = samples.astype(np.float64)
    window = rate // 50
    padded = np.pad(samples, (window // 2, window - window // 2 - 1), mode="edge")
    samples = samples - np.convolve(padded, np.full(window, 1 / window), mode="valid")
    blocks = samples[: samples.size // hop * hop].reshape(-1, hop)
    levels = 10 * np.log10(np.mean(blocks**2, axis=1) + 1e-12)
    floor, peak = np.percentile(levels, 5), np.percentile(levels, 99)
    threshold = max(floor + 10, peak - 30)
    above = levels > threshold
    lasting = np.lib.stride_tricks.sliding_window_view(np.append(above, [True] * 3), 4).all(axis=1)
    first = int(np.argmax(lasting))
    return first * hop / rate


@dataclass(frozen=True, eq=False)
class ListTake:
    """A list read with pauses: the audio (float, `rate`), its text (items joined by commas), item onsets."""

    samples: np.ndarray
    rate: int
    text: str
    onsets: np.ndarray
    speaker: str


def lists_of_eight(items: list[Recording], rng: np.random.Generator, rate: int = 16000) -> list[ListTake]:
    """Lists of eight items of one speaker each, joined by 0.4-0.9 s of that speaker's own noise floor."""
    by_speaker: dict[str, list[Recording]] = {}
    for item in items:
        by_speaker.setdefault(item.speaker, []).append(item)
    takes = []
    for speaker, own in sorted(by_speaker.items()):
        order = rng.permutation(len(own))
        for first in range(0, len(own) - 7, 8):
            chosen = [own[index] for index in order[first : first + 8]]
            clips = [read(item, rate) for item in chosen]
            floor = _quietest_stretch(np.concatenate(clips), rate)
            pieces, onsets, position = [], [], 0
            for clip in clips:
                gap = rng.uniform(0.4, 0.9)
                pause = np.resize(floor, int(gap * rate)) * rng.choice([-1, 1])
                pieces += [pause, clip]
                position += pause.size
                onsets.append((position + sound_onset(clip, rate) * rate) / rate)
                position += clip.size
            pieces.append(np.resize(floor, int(0.5 * rate)))
            text = ", ".join(item.turkish for item in chosen)
            takes.append(ListTake(np.concatenate(pieces), rate, text, np.array(onsets), speaker))
    return takes


def _quietest_stretch(samples: np.ndarray, rate: int) -> np.ndarray:
    """The speaker's own room: the quietest 50 ms of their recordings, to be looped."""
    hop = rate // 20
    blocks = samples[: samples.size // hop * hop].reshape(-1, hop)
    return blocks[int(np.argmin(np.mean(blocks.astype(np.float64) ** 2, axis=1)))].copy()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("command", choices=("build", "list"))
    parser.add_argument("--folder", type=Path, default=FOLDER)
    parser.add_argument("--part", choices=("tune", "report", "train"))
    parser.add_argument("--kind", choices=("line", "syllable", "word"))
    arguments = parser.parse_args(argv)
    if arguments.command == "build":
        build(arguments.folder)
        return 0
    chosen = recordings(arguments.folder, arguments.part, arguments.kind)
    counts: dict[tuple[str, str, str], int] = {}
    for recording in chosen:
        key = (recording.part, recording.kind, recording.source.split("/")[0])
        counts[key] = counts.get(key, 0) + 1
    for (part, kind, source), count in sorted(counts.items()):
        print(f"{part}\t{kind}\t{source}\t{count}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
