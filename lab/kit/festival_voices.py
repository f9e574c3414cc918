"""People's speech with every phone labelled: Festival's diphone voices, each recorded by a real speaker.

Every spectrum a diphone voice speaks was cut from a person's recording; Festival says where each segment
of what it speaks lies (`utt.save.segs`). So random sentences of real words of each voice's language,
spoken by it, give people's speech whose phones are labelled, in many voices and languages. Each phone is
mapped to the Turkish letter sound nearest it, or to "ignore" where none is near, by the language's table
in inventory/*.toml (validated on load: a phone the voice speaks that the table lacks is an error).

The voices come from Debian (`apt-get install` of PACKAGES; all GPL-2+, LGPL or BSD-like: they may train
weights that ship in a GPL-3.0-or-later product). Festival's Russian and Italian voices (HELD_OUT) are
never rendered here: they are kept to measure on.
"""

from __future__ import annotations

import subprocess
import tempfile
import tomllib
import unicodedata
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from turkish_lipsync.core.base.errors import DataError
from turkish_lipsync.core.speech.acoustic.labels import CLASS_INDEX, FRAME_SECONDS, SILENCE, frame_times
from turkish_lipsync.core.speech.audio import read_audio, resample
from turkish_lipsync.core.speech.features import ANALYSIS_RATE

INVENTORY = Path(__file__).with_name("inventory")
VOICELESS_STOPS = frozenset("çkpt")
SILENT_UNDER_DB = 40.0  # a voiceless stop's closure: its frames this far under the take's loud ones ...
CLOSURE_UNDER_DB = 15.0  # ... or this far under the phone before's loudest (as espeak.py finds closures)
ONSET_UNDER_DB = 30.0  # after a pause, a phone's frames this far under the loud ones are still the pause's
IGNORE = 255  # a frame label that teaches nothing (a phone no Turkish sound is near)
HELD_OUT = ("festvox-ru", "festvox-italp16k", "festvox-itapc16k")  # measure only: never rendered here


@dataclass(frozen=True)
class Voice:
    """A Festival voice: its Debian package, the Scheme call that selects it, its language's word list
    (wordfreq), how its text is encoded and which inventory table maps its phones."""

    package: str
    select: str
    words: str
    encoding: str
    inventory: str
    script_offset: int = 0  # Indic scripts: the code point distance from Devanagari (Telugu: 0x300)


VOICES = {
    "czech-dita": Voice("festvox-czech-dita", "voice_czech_dita", "cs", "iso-8859-2", "czech"),
    "czech-krb": Voice("festvox-czech-krb", "voice_czech_krb", "cs", "iso-8859-2", "czech"),
    "czech-machac": Voice("festvox-czech-machac", "voice_czech_machac", "cs", "iso-8859-2", "czech"),
    "czech-ph": Voice("festvox-czech-ph", "voice_czech_ph", "cs", "iso-8859-2", "czech"),
    "finnish-lj": Voice("festvox-suopuhe-lj", "voice_suo_fi_lj_diphone", "fi", "iso-8859-1", "finnish"),
    "finnish-mv": Voice("festvox-suopuhe-mv", "voice_hy_fi_mv_diphone", "fi", "iso-8859-1", "finnish"),
    "english-kal": Voice("festvox-kallpc16k", "voice_kal_diphone", "en", "ascii", "english"),
    "english-ked": Voice("festvox-kdlpc16k", "voice_ked_diphone", "en", "ascii", "english"),
    "hindi-nsk": Voice("festvox-hi-nsk", "voice_hindi_NSK_diphone", "hi", "utf-8", "indic"),
    "marathi-nsk": Voice("festvox-mr-nsk", "voice_marathi_NSK_diphone", "hi", "utf-8", "indic"),
    "telugu-nsk": Voice("festvox-te-nsk", "voice_telugu_NSK_diphone", "hi", "utf-8", "indic", 0x300),
}
PACKAGES = ("festival", "festival-czech", *sorted({voice.package for voice in VOICES.values()}))


def install() -> None:
    """Festival and the voices from Debian (apt-get install; run as root, as the training machine is)."""
    missing = [name for name in PACKAGES if not installed(name)]
    if missing:
        subprocess.run(["apt-get", "update", "-qq"], check=True)
        subprocess.run(["apt-get", "install", "-y", "-qq", *missing], check=True)


def installed(package: str) -> bool:
    """Whether Debian's package is installed (its status's state is "installed": a package dpkg knows of
    but never installed reads "unknown ok not-installed")."""
    status = subprocess.run(["dpkg-query", "-W", "-f=${Status}", package], capture_output=True, text=True)
    return status.stdout.split()[-1:] == ["installed"]


def inventory(name: str, folder: Path | None = None) -> dict[str, tuple[str, ...]]:
    """A language's phone table (folder: INVENTORY's): each phone to the letters it is heard as (empty:
    ignored)."""
    path = (folder or INVENTORY) / f"{name}.toml"
    with path.open("rb") as handle:
        phones = tomllib.load(handle).get("phones")
    if not isinstance(phones, dict) or not phones:
        raise DataError(f"data file {path}: a [phones] table is needed")
    table = {}
    for phone, heard in phones.items():
        letters = [heard] if isinstance(heard, str) else heard
        if heard == "ignore":
            letters = []
        if not isinstance(letters, list) or any(letter not in CLASS_INDEX for letter in letters):
            raise DataError(
                f"data file {path}: phone {phone!r} maps to {heard!r}; give a letter of "
                f"{''.join(CLASS_INDEX)}, a list of them, {SILENCE!r} or 'ignore'"
            )
        table[phone] = tuple(letters)
    return table


def sentences(voice: Voice, count: int, rng: np.random.Generator) -> list[str]:
    """Random sentences of the language's commoner words (3-12 words, some commas), as the voice reads."""
    import wordfreq

    words = [word for word in wordfreq.top_n_list(voice.words, 20_000) if _speakable(word, voice)]
    weights = 1.0 / np.sqrt(np.arange(1, len(words) + 1))
    weights /= weights.sum()
    out = []
    for _ in range(count):
        chosen = [words[index] for index in rng.choice(len(words), size=int(rng.integers(3, 13)), p=weights)]
        text = " ".join(word + ("," if rng.random() < 0.1 else "") for word in chosen).rstrip(",")
        out.append(text + str(rng.choice([".", ".", "?", "!"])))
    return [_in_script(text, voice) for text in out]


# Devanagari signs with no Telugu twin (candrabindu, nukta, candra e and o): words holding one stay out.
NO_TELUGU_TWIN = frozenset("\u0901\u093c\u0945\u0949")


def _speakable(word: str, voice: Voice) -> bool:
    if voice.words == "hi":  # Devanagari: its vowel signs are marks, not letters, to str.isalpha
        in_script = all("\u0900" <= char <= "\u097f" for char in word)
        return in_script and not (voice.script_offset and NO_TELUGU_TWIN & set(word))
    try:
        word.encode(voice.encoding)
    except UnicodeEncodeError:
        return False
    return word.isalpha()


def _in_script(text: str, voice: Voice) -> str:
    if not voice.script_offset:
        return text
    return "".join(
        chr(ord(char) + voice.script_offset) if "\u0900" <= char <= "\u097f" else char for char in text
    )


# Each word's segments, as a list of lists (written to a .words file beside the .segs).
WORD_PHONES = """(define (word_phones utt)
  (mapcar (lambda (word) (apply append (mapcar (lambda (syl) (mapcar item.name (item.daughters syl)))
                                             (item.daughters (item.relation word 'SylStructure)))))
          (utt.relation.items utt 'Word)))"""


def render(voice: Voice, texts: list[str], stretches: list[float], folder: Path) -> list[Path]:
    """Each text spoken by the voice at its duration stretch: folder/NNNN.wav, .segs and .words (each
    word's segments), made once: folder/NNNN.said keeps what was asked of the voice, so a stem made for
    another text or stretch (another seed, another count) is made again, not taken for this one."""
    folder.mkdir(parents=True, exist_ok=True)
    wanted = [folder / f"{number:04d}" for number in range(len(texts))]
    lines = [WORD_PHONES, f"({voice.select})"]
    for stem, text, stretch in zip(wanted, texts, stretches, strict=True):
        said = f"{voice.select}\n{stretch:.3f}\n{text}"
        if stem.with_suffix(".segs").exists() and _read_said(stem) == said:
            continue
        for suffix in (".wav", ".segs", ".words"):
            stem.with_suffix(suffix).unlink(missing_ok=True)
        stem.with_suffix(".said").write_text(said, encoding="utf-8")
        spoken = unicodedata.normalize("NFC", text).replace('"', "").replace("\\", "")
        # A sentence the voice's letter-to-sound rules cannot read is left out (unwind-protect), not the rest.
        lines += [
            f"(Parameter.set 'Duration_Stretch {stretch:.3f})",
            f'(unwind-protect (begin (set! utt (SynthText "{spoken}"))',
            f'  (utt.save.wave utt "{stem.with_suffix(".wav")}" \'riff)',
            f'  (set! words (fopen "{stem.with_suffix(".words")}" "w"))',
            '  (format words "%l\\n" (word_phones utt)) (fclose words)',
            f'  (utt.save.segs utt "{stem.with_suffix(".segs")}")) nil)',
        ]
    if len(lines) > 2:
        with tempfile.NamedTemporaryFile("wb", suffix=".scm", delete=False) as script:
            script.write("\n".join(lines).encode(voice.encoding, errors="replace"))
        subprocess.run(["festival", "-b", script.name], capture_output=True, timeout=3600)
        Path(script.name).unlink()
    return [
        stem for stem in wanted if stem.with_suffix(".segs").exists() and stem.with_suffix(".wav").exists()
    ]


def _read_said(stem: Path) -> str | None:
    """What a stem was made from (render's .said), None where it was not written."""
    try:
        return stem.with_suffix(".said").read_text(encoding="utf-8")
    except OSError:
        return None


def segments(path: Path) -> list[tuple[float, float, str]]:
    """(start, end, phone) of each segment of a .segs file (Festival writes each segment's end)."""
    out = []
    start = 0.0
    lines = path.read_text(encoding="latin-1").splitlines()
    for line in lines[lines.index("#") + 1 :]:
        end, _, phone = line.split(maxsplit=2)
        out.append((start, float(end), phone.strip()))
        start = float(end)
    return out


def labelled(stem: Path, table: dict[str, tuple[str, ...]]) -> tuple[np.ndarray, np.ndarray]:
    """16 kHz float samples of a rendered text and a label per 10 ms frame (IGNORE where no letter is near).

    A phone heard as several letters (a diphthong, an affricate) shares its time among them evenly. A
    voiceless stop starts at its burst, as eSpeak NG's labels start it (lab/kit/voices.py's
    burst_timeline): the silence of its closure (its frames from its start that lie SILENT_UNDER_DB under
    the take's loud frames or CLOSURE_UNDER_DB under the phone before's loudest) is the phone before's, or
    the pause's. Festival starts a stop at its closure, and after a pause gives it 50-60 ms of the
    silence before (Czech, English): taught so, the network heard a list's pause as the next item's p, t or
    k (onsets 70-150 ms early) and keyed stops a closure early in the aligner, which gives each stop its
    closure itself. After a pause, any phone starts where its sound does (within ONSET_UNDER_DB of the
    take's loud frames, as lab/kit/people.py's sound_onset finds a person's item): Festival starts it up
    to 70 ms sooner (on the faint edge of a diphone), and taught so the network heard people's items start
    17 ms early (the lists of eight's onsets).
    """
    mono, rate = read_audio(stem.with_suffix(".wav"))
    samples = resample(mono, rate, ANALYSIS_RATE)
    hop = int(round(FRAME_SECONDS * ANALYSIS_RATE))
    count = samples.size // hop + 1
    times = frame_times(count)
    labels = np.zeros(count, np.uint8)
    level = _frame_levels(samples, count, hop)
    loud = np.percentile(level, 90)
    before = (0, 0)  # the frames of the phone before
    after_pause = True
    for start, end, phone in segments(stem.with_suffix(".segs")):
        if phone not in table:
            raise DataError(f"{INVENTORY}: phone {phone!r} (in {stem}.segs) is in no inventory table")
        letters = table[phone]
        first, stop = np.searchsorted(times, (start, end))
        if after_pause and letters and letters != (SILENCE,):
            sounding = first
            while sounding < stop - 1 and level[sounding] < loud - ONSET_UNDER_DB:
                sounding += 1
            labels[first:sounding] = CLASS_INDEX[SILENCE]
            first = sounding
        after_pause = letters == (SILENCE,)
        if letters and letters[0] in VOICELESS_STOPS and first < stop:
            quiet = max(loud - SILENT_UNDER_DB, level[slice(*before)].max(initial=-np.inf) - CLOSURE_UNDER_DB)
            burst = first + int(
                level[first] >= quiet
            )  # a frame astride the boundary may hold the phone before
            while burst < stop - 1 and level[burst] < quiet:
                burst += 1
            if burst > first + 1 or level[first] < quiet:
                labels[first:burst] = labels[first - 1] if first else 0
                first = burst
        before = (first, stop)
        if not letters:
            labels[first:stop] = IGNORE
            continue
        bounds = np.linspace(first, stop, len(letters) + 1).round().astype(int)
        for letter, begin, finish in zip(letters, bounds[:-1], bounds[1:], strict=True):
            labels[begin:finish] = CLASS_INDEX[letter]
    return samples, labels


def _frame_levels(samples: np.ndarray, count: int, hop: int) -> np.ndarray:
    """Each frame's power (dB) over the hop around its centre (labels.frame_times)."""
    offset = int(round(frame_times(1)[0] * ANALYSIS_RATE)) - hop // 2
    padded = np.pad(samples[offset:], (0, max(0, count * hop - samples[offset:].size)))
    return 10 * np.log10(np.mean(padded[: count * hop].reshape(count, hop) ** 2, axis=1) + 1e-12)
