"""MBROLA's Turkish diphone voices as stand-ins for Turkish people: takes with their truth, to measure on.

MBROLA's tr1 (a man) and tr2 (a woman) are recordings of two Turkish speakers cut into diphones; MBROLA
joins them at the durations and pitch eSpeak NG gives each phone. Unlike eSpeak NG's own voice, every sound
is a person's; unlike the shared people's voices, the language is Turkish. Measured with, never shipped
and never trained on (their licence forbids selling them inside a product).

The take: the system's eSpeak NG (`espeak-ng -v mb-tr1 --pho`) writes the phones, their durations and
pitch; eSpeak NG 1.51 spells the open e of a closed final syllable ("Erdem") as a phone tr1 and tr2 do not
have, and MBROLA would put silence there, so it is spoken as e; the `mbrola` program then renders them. The
truth: the product's own timeline of the text (its letters, visemes and words) with each letter moved onto
its phone's span in that list. Letters and phones are matched in order at the least cost (`paired`): a
letter with a phone it may be spoken as, a soft g or a doubled letter sharing its neighbour's ("ağaç" is
a long a and a ç, "seyrettik" one long t). A text that pairs only at a high cost is refused (none of
examples/corpus_tr.txt's 50 sentences is).

Needs Debian's mbrola, mbrola-tr1 and mbrola-tr2 (in contrib and non-free): with those sections in the apt
sources, `apt-get install mbrola-tr1 mbrola-tr2`, and the system's espeak-ng (`apt-get install espeak-ng`).

Measured by lab/measure/recordings.py and lab/measure/recogniser.py (sentences: `--voices
mbrola-tr1 mbrola-tr2`) and lab/measure/people.py (words said alone: `--sets mbrola-words`).
"""

from __future__ import annotations

import dataclasses
import shutil
import subprocess
import tempfile
from collections import Counter
from pathlib import Path

import numpy as np

from turkish_lipsync.core.base.model import Timeline, WordSpan
from turkish_lipsync.core.speech import synthesize_timeline
from turkish_lipsync.core.speech.audio import read_audio, resample
from turkish_lipsync.core.text.utterance import build_utterance

VOICES_FOLDER = Path("/usr/share/mbrola")
PAUSE = "_"
# eSpeak NG's phones the Turkish diphone voices lack, and the phone spoken in their place.
MISSING_PHONES = {"&": "e"}


class PhonesDoNotPair(ValueError):
    """The voice's phones and the text's letters cannot be matched one to one."""


def check_installed(voice: str) -> None:
    """Stop with what to install when the voice, the mbrola program or espeak-ng is missing."""
    missing = [program for program in ("mbrola", "espeak-ng") if shutil.which(program) is None]
    if not (VOICES_FOLDER / voice / voice).is_file():
        missing.append(f"the MBROLA voice {voice} ({VOICES_FOLDER / voice})")
    if missing:
        raise SystemExit(f"{', '.join(missing)} not installed: see lab/kit/diphone_voices.py's docstring")


def phones(text: str, voice: str) -> list[tuple[str, float, str]]:
    """eSpeak NG's phone list for MBROLA: (phone, milliseconds, the rest of the line: pitch points)."""
    done = subprocess.run(
        ["espeak-ng", "-q", "--pho", "-v", f"mb-{voice}", text], capture_output=True, text=True, check=True
    )
    listed = []
    for line in done.stdout.splitlines():
        fields = line.split(maxsplit=2)
        if len(fields) >= 2 and fields[1].isdigit():
            name = MISSING_PHONES.get(fields[0], fields[0])
            listed.append((name, float(fields[1]), fields[2] if len(fields) > 2 else ""))
    return listed


def render(listed: list[tuple[str, float, str]], voice: str, folder: Path) -> tuple[np.ndarray, int]:
    """The voice's samples (float32, -1..1) of the phone list and their rate."""
    pho, wav = folder / "take.pho", folder / "take.wav"
    pho.write_text("".join(f"{name} {ms:g} {pitch}\n" for name, ms, pitch in listed), encoding="ascii")
    subprocess.run(
        ["mbrola", "-e", str(VOICES_FOLDER / voice / voice), str(pho), str(wav)],
        capture_output=True,
        check=True,
    )
    return read_audio(wav)


# The phones each Turkish letter may be spoken as in the voices' phone list.
LETTER_PHONES = {
    "a": "a",
    "e": "e &",
    "ı": "@",
    "i": "I",
    "o": "o",
    "ö": "@'",
    "u": "u",
    "ü": "y",
    "b": "b",
    "c": "dZ",
    "ç": "tS",
    "d": "d",
    "f": "f",
    "g": "g G",
    "ğ": "G j",
    "h": "h",
    "j": "Z",
    "k": "k",
    "l": "l L l/ L/",
    "m": "m",
    "n": "n",
    "p": "p",
    "r": "r",
    "s": "s",
    "ş": "S",
    "t": "t",
    "v": "v",
    "y": "j",
    "z": "z",
}
VOWEL_PHONES = {phone for letter in "aeıioöuü" for phone in LETTER_PHONES[letter].split()}
UNLIKE = 1.0  # pairing a letter with a phone it is not spoken as
SILENT = 1.0  # a letter with no phone of its own (it shares its neighbour's)
QUIET_LETTER = 0.1  # ... a soft g, a letter doubled ("tt" is one long t), a vowel a soft g joins to its twin
EXTRA = 1.0  # a phone with no letter


def paired(letters: list[str], names: list[str]) -> list[int]:
    """For each letter, the index of the phone it is spoken with (letters and phones matched in order at
    the least cost; a letter with no phone of its own shares its neighbour's)."""
    count, phone_count = len(letters), len(names)
    cost = np.full((count + 1, phone_count + 1), np.inf)
    step = np.zeros((count + 1, phone_count + 1), np.int8)  # 0 pair, 1 silent letter, 2 extra phone
    cost[0, 0] = 0.0
    for i in range(count + 1):
        for j in range(phone_count + 1):
            if i and j:
                like = names[j - 1] in LETTER_PHONES.get(letters[i - 1], "").split()
                option = cost[i - 1, j - 1] + (0.0 if like else UNLIKE)
                if option < cost[i, j]:
                    cost[i, j], step[i, j] = option, 0
            if i:
                letter, before = letters[i - 1], letters[max(0, i - 3) : i - 1]
                # a soft g, a doubled letter ("tt"), the vowel a soft g joins to its twin ("ağa")
                quiet = letter == "ğ" or before[-1:] == [letter] or before == [letter, "ğ"]
                option = cost[i - 1, j] + (QUIET_LETTER if quiet else SILENT)
                if option < cost[i, j]:
                    cost[i, j], step[i, j] = option, 1
            if j:
                option = cost[i, j - 1] + EXTRA
                if option < cost[i, j]:
                    cost[i, j], step[i, j] = option, 2
    if cost[count, phone_count] > 0.25 * count:
        raise PhonesDoNotPair(
            f"{phone_count} phones for {count} letters pair at a cost of {cost[-1, -1]:.1f}"
        )
    owner = [-1] * count
    i, j = count, phone_count
    while i or j:
        move = step[i, j]
        if move == 0:
            owner[i - 1] = j - 1
            i, j = i - 1, j - 1
        elif move == 1:
            i -= 1
        else:
            j -= 1
    own = list(owner)
    for index in range(count):
        if own[index] < 0:
            owner[index] = _shared(index, letters[index], own, names)
    return owner


def _shared(index: int, letter: str, own: list[int], names: list[str]) -> int:
    """The phone a letter with none of its own shares: a neighbour's it may be spoken as ("a ğ a" is one
    long a), else a neighbouring vowel's (a soft g lengthens its vowel), else the previous one's."""
    before = next((own[i] for i in range(index - 1, -1, -1) if own[i] >= 0), None)
    after = next((own[i] for i in range(index + 1, len(own)) if own[i] >= 0), None)
    near = [phone for phone in (before, after) if phone is not None]
    for test in (
        lambda phone: names[phone] in LETTER_PHONES.get(letter, "").split(),
        lambda phone: names[phone] in VOWEL_PHONES,
        lambda phone: True,
    ):
        chosen = next((phone for phone in near if test(phone)), None)
        if chosen is not None:
            return chosen
    raise PhonesDoNotPair("a text with no phone")


def retimed(timeline: Timeline, listed: list[tuple[str, float, str]]) -> Timeline:
    """The timeline with its letters on their phones' spans (seconds from the take's start); letters sharing a
    phone share its span in equal parts."""
    starts = np.concatenate(([0.0], np.cumsum([ms for _, ms, _ in listed]))) / 1000
    spoken = [index for index, (name, _, _) in enumerate(listed) if name != PAUSE]
    owner = paired([phone.letter.lower() for phone in timeline.phones], [listed[i][0] for i in spoken])
    sharing, placed = Counter(owner), Counter()  # letters per phone, and those given a part so far
    letters = []
    for phone, own in zip(timeline.phones, owner, strict=True):
        begin, end = starts[spoken[own]], starts[spoken[own] + 1]
        part = (end - begin) / sharing[own]
        place = placed[own]
        placed[own] += 1
        letters.append(
            dataclasses.replace(
                phone, start=float(begin + place * part), end=float(begin + (place + 1) * part)
            )
        )
    words = []
    for word in timeline.words:
        own = [phone for phone in letters if phone.word_index == word.index]
        words.append(WordSpan(own[0].start, own[-1].end, word.index, word.text))
    return dataclasses.replace(
        timeline,
        phones=tuple(letters),
        words=tuple(words),
        duration=float(starts[-1]),
        emotions=(),
        emphases=(),
        engine_onsets=(),
    )


def speak(text: str, voice: str, sample_rate: int) -> tuple[np.ndarray, Timeline]:
    """The voice ("tr1" or "tr2") reading the text: float samples at sample_rate and the truth's timeline."""
    check_installed(voice)
    listed = phones(text, voice)
    with tempfile.TemporaryDirectory() as folder:
        samples, rate = render(listed, voice, Path(folder))
    truth = retimed(synthesize_timeline(build_utterance(text)).timeline, listed)
    return resample(samples, rate, sample_rate).astype(np.float64), truth
