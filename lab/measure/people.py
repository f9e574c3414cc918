"""How the product does on people's recordings: alignment, speech detection and audio alone.

    python -m lab.measure.people [--part report|tune] [--sets words syllables lists sentences]
                                     [--sentences N] [--aeneas] [--folder out/people]

The recordings are lab/kit/people.py's (build them first: `python -m lab.kit.people build`). Everything
acoustic was tuned and trained on its **tune** part; the figures to report come from the **report**
part (the default), which holds speakers, lines and languages the tuning never saw. Each recording goes
through the public entries a user's recording goes through (speech.synthesize_timeline with the
recording, speech.recognition.speech_from_audio without a text), from a 16-bit WAV at the recording's
own rate.

- words: words said alone (KTuberling's English words; the one-word lines of the game's Dutch and Czech
  voice acting), with their text (refused / warned / clean) and without (how many "no speech found");
- syllables (klettres): without a text, "no speech found"; the vowel heard in its class (a / e / i ı /
  o ö / u ü: the longest vowel heard); for those that start with b, m or p, a b, m or p heard before
  that vowel; for the rest, how often one is heard there anyway (each over all the syllables and over
  those that got a timeline);
- lists: lists of eight words or syllables of one speaker read with pauses (people.lists_of_eight), with
  their text written with commas: refused / warned, each item's onset against where its sound starts
  (median / p90 / max), and aeneas' on the same takes with --aeneas;
- lists-lines, lists-spaces (only when named): the same lists, their text written an item a line, or on
  one line with spaces only (no commas either way);
- sentences: the voice-acted lines of three words or more (every --sentences-th), with their Turkish
  spelling (refused / warned / clean), with the next line's spelling (another text: refused or warned),
  and without a text: "no speech found", the mouth's opening against the mouth aligned to the text
  (Pearson r on a 10 ms grid, smoothed over 60 ms, as lab/measure/recogniser.py measures it), and the
  text-aligned b, m, p that a recognised b, m or p overlaps;
- padded (only when named): the sentences (every --sentences-th) aligned as they come and with 3 s of
  digital silence before and after (a take exported from an editor's timeline): how many lines' word
  onsets move by more than 50 ms, and how many are warned either way. The speech is the same: ideally
  none moves;
- breaks (only when named): the Czech lines (every --sentences-th), three at a time, joined by BREAK_SECONDS
  of room (noise BREAK_ROOM_DB under their peak) into one take (a session's lines recorded in one file):
  without a text, how closely the letters heard match the three lines' spellings (difflib's ratio),
  beside each line heard alone; with the three lines' text, each word's onset against the line aligned
  alone (median / p90 / max), how many takes are warned, and in how many a word is put across a break
  (more than half a break from where its line alone puts it). The speech is the same: ideally the joined
  take is heard and aligned as its lines are;
- long (only when named): the report part's acted lines one after the other, 0.5 s apart, in one 10-minute
  take (lab/measure/recogniser.py's long_take, the take its speed is measured on), no text: how closely the
  letters heard within each line's span match its spelling (difflib's ratio, mean over the lines), beside
  each line heard alone. Ideally the long take is heard as its lines are;
- breaks-lines (only when named): the same takes, the script the lines' spellings without punctuation,
  one line each (its line breaks the only marks of where a line ends);
- music (only when named): the sentences (every --sentences-th) aligned as they come, and with
  MUSIC_SECONDS of an instrumental with no voice (lab/kit/takes.py's instrumental) before them (a video's
  intro) and after them (its outro): in how many lines the first word starts MUSIC_MOVED or more before
  its onset as they come (in the intro), or the last ends that much later (in the outro), how many lines'
  word onsets (or last word's end) move by more than MUSIC_MOVED at all, and how many are warned or
  refused. The speech is the same: ideally none moves;
- music-between (only when named): takes of MUSIC_GROUP consecutive Czech lines with the music between
  their halves (40 s and more from either end): the words whose onset is put in it. Ideally none;
- mbrola-words (only when named, MBROLA installed: lab/kit/diphone_voices.py): two Turkish speakers''
  diphones saying every distinct word of examples/corpus_tr.txt's held-out sentences alone, with their
  text (refused / warned / clean, the onset's error) and without ("no speech found").

Not a test: the figures go into docs/developer/measured/people.md.
"""

from __future__ import annotations

import argparse
import difflib
import re
import sys
import tempfile
from collections import Counter
from pathlib import Path

import numpy as np

from lab.kit import diphone_voices, people
from lab.kit.corpus import held_out_sentences
from lab.kit.scores import bilabial_scores, correlation, opening_trajectory
from lab.kit.takes import write_wav
from lab.kit.voices import RECORDED_RATE
from lab.measure.recogniser import long_take
from lab.measure.recordings import aeneas_onsets, takes
from turkish_lipsync.core.base.errors import LipSyncError
from turkish_lipsync.core.speech import synthesize_timeline
from turkish_lipsync.core.speech.recognition import speech_from_audio
from turkish_lipsync.core.text.utterance import build_utterance

VOWEL_CLASSES = {"a": "a", "e": "e", "ı": "iı", "i": "iı", "o": "oö", "ö": "oö", "u": "uü", "ü": "uü"}
BILABIALS = set("bmp")
RATE = 16000  # the takes people.py makes are written at this rate


ERRORS: Counter = Counter()  # other errors' messages (their first words), shown at the end
WARNINGS: Counter = Counter()  # warnings' kinds, shown at the end


def outcome(error: LipSyncError | None, warnings: tuple[str, ...]) -> str:
    if error is None:
        WARNINGS.update(" ".join(warning.split()[:6]) for warning in warnings)
        return "warned" if warnings else "clean"
    message = str(error)
    if "does not read this text" in message:
        return "refused"
    if "no speech" in message or "silent" in message:
        return "no speech"
    ERRORS[" ".join(message.split()[:3]) + " ... " + " ".join(message.split()[-8:])] += 1
    return "error"


def aligned(text: str, path: Path):
    """(timeline or None, outcome) of a recording aligned to its text."""
    try:
        speech = synthesize_timeline(build_utterance(text), recording=path)
    except LipSyncError as error:
        return None, outcome(error, ())
    return speech.timeline, outcome(None, speech.warnings)


def heard(path: Path):
    """(timeline or None, outcome) of a recording without its text."""
    try:
        _, speech = speech_from_audio(path)
    except LipSyncError as error:
        return None, outcome(error, ())
    return speech.timeline, outcome(None, speech.warnings)


def shares(counts: Counter, total: int) -> str:
    order = ("clean", "warned", "refused", "no speech", "error")
    return ", ".join(f"{name} {counts[name]} ({100 * counts[name] / max(total, 1):.0f} %)" for name in order)


def words(part: str, folder: Path) -> list[people.Recording]:
    said_alone = [r for r in people.recordings(folder, part, "word")]
    said_alone += [
        r
        for r in people.recordings(folder, part, "line")
        if len(r.turkish.split()) == 1 and len(r.turkish) > 1
    ]
    return said_alone


def list_items(part: str, folder: Path) -> list[people.Recording]:
    """The syllables and words of one word that lists of eight are read from (one word an item: the onsets
    compare)."""
    items = people.recordings(folder, part, "syllable") + people.recordings(folder, part, "word")
    return [item for item in items if len(item.turkish.split()) == 1]


def measure_words(part: str, folder: Path) -> None:
    chosen = words(part, folder)
    with_text, without = Counter(), Counter()
    for recording in chosen:
        with_text[aligned(recording.turkish, recording.path)[1]] += 1
        without[heard(recording.path)[1]] += 1
    sources = Counter(r.source.split("/")[0] for r in chosen)
    print(f"words said alone ({len(chosen)}: {dict(sources)})")
    print(f"  with their text: {shares(with_text, len(chosen))}")
    print(f"  no text:         {shares(without, len(chosen))}")


def measure_syllables(part: str, folder: Path) -> None:
    chosen = people.recordings(folder, part, "syllable")
    counts, vowel_right, vowels, timed_vowels = Counter(), 0, 0, 0
    bilabial_heard = bilabial_total = stray_heard = stray_total = 0
    timed_bilabials = timed_strays = 0
    for recording in chosen:
        timeline, result = heard(recording.path)
        counts[result] += 1
        spelt_vowels = [letter for letter in recording.turkish if letter in VOWEL_CLASSES]
        starts_bilabial = recording.turkish[0] in BILABIALS
        bilabial_total += starts_bilabial
        stray_total += not starts_bilabial
        if spelt_vowels:
            vowels += 1
        if timeline is None:
            continue
        timed_vowels += bool(spelt_vowels)
        timed_bilabials += starts_bilabial
        timed_strays += not starts_bilabial
        phones = timeline.phones
        heard_vowels = [p for p in phones if p.letter in VOWEL_CLASSES]
        longest = max(heard_vowels, key=lambda p: p.end - p.start) if heard_vowels else None
        if spelt_vowels and longest is not None:
            vowel_right += VOWEL_CLASSES[longest.letter] == VOWEL_CLASSES[spelt_vowels[0]]
        before = [p for p in phones if longest is None or p.start < longest.start]
        found = any(p.letter in BILABIALS for p in before)
        bilabial_heard += found and starts_bilabial
        stray_heard += found and not starts_bilabial
    print(f"syllables, no text ({len(chosen)}): {shares(counts, len(chosen))}")
    print(
        f"  vowel heard in its class: {vowel_right} of {vowels} "
        f"({100 * vowel_right / max(vowels, 1):.0f} %); "
        f"of those with a timeline: {vowel_right} of {timed_vowels} "
        f"({100 * vowel_right / max(timed_vowels, 1):.0f} %)"
    )
    print(
        f"  b/m/p heard where the syllable starts with one: {bilabial_heard} of {bilabial_total} "
        f"({100 * bilabial_heard / max(bilabial_total, 1):.0f} %; of those with a timeline "
        f"{100 * bilabial_heard / max(timed_bilabials, 1):.0f} %); where it does not: {stray_heard} of "
        f"{stray_total} ({100 * stray_heard / max(stray_total, 1):.0f} %; of those with a timeline "
        f"{100 * stray_heard / max(timed_strays, 1):.0f} %)"
    )


LIST_SEPARATORS = {"lists": ", ", "lists-lines": "\n", "lists-spaces": " "}


def measure_lists(part: str, folder: Path, aeneas: bool, scratch: Path, separator: str = ", ") -> None:
    """separator: what the list's text puts between its items (a comma, a line break, a space)."""
    takes = people.lists_of_eight(list_items(part, folder), np.random.default_rng(8), RATE)
    counts, errors, theirs = Counter(), [], []
    for number, take in enumerate(takes):
        path = write_wav(scratch / f"list{number}.wav", take.samples, RATE)
        timeline, result = aligned(take.text.replace(", ", separator), path)
        counts[result] += 1
        if timeline is not None:
            found = np.array([word.start for word in timeline.words])
            if found.size == take.onsets.size:
                errors.append(np.abs(found - take.onsets))
        if aeneas:
            onsets, _ = aeneas_onsets(path, [item.strip(" .") for item in take.text.split(",")])
            if onsets.size == take.onsets.size:
                theirs.append(np.abs(onsets - take.onsets))
    written = {", ": "written with commas", "\n": "an item a line", " ": "with spaces only"}[separator]
    outcomes = shares(counts, len(takes))
    print(f"lists of eight read with pauses ({len(takes)} takes), their text {written}: {outcomes}")
    for name, found in (("item onsets", errors), ("aeneas", theirs)):
        if found:
            ms = 1000 * np.concatenate(found)
            spread = f"median {np.median(ms):.0f}, p90 {np.percentile(ms, 90):.0f}, max {ms.max():.0f}"
            print(f"  {name} (ms): {spread} ({len(found)} takes with every item)")


def measure_sentences(part: str, folder: Path, every: int, scratch: Path) -> None:
    lines = people.sentence_lines(part, folder)
    for source in sorted({r.source.split("/")[0] for r in lines}):
        chosen = [r for r in lines if r.source.startswith(source)][::every]
        same, other, alone = Counter(), Counter(), Counter()
        openings, closed, bilabials = [], 0, 0
        for index, recording in enumerate(chosen):
            timeline, result = aligned(recording.turkish, recording.path)
            same[result] += 1
            other[aligned(chosen[(index + 1) % len(chosen)].turkish, recording.path)[1]] += 1
            found, heard_result = heard(recording.path)
            alone[heard_result] += 1
            if timeline is None or found is None:
                continue
            duration = max(timeline.duration, found.duration)
            openings.append(
                correlation(opening_trajectory(found, duration), opening_trajectory(timeline, duration))
            )
            hits, total, _, _ = bilabial_scores(timeline, found, 0.0)
            closed, bilabials = closed + hits, bilabials + total
        print(f"sentences, {source} ({len(chosen)} lines of {people.SENTENCE_WORDS}+ words)")
        print(f"  with their spelling:      {shares(same, len(chosen))}")
        print(f"  with another line's text: {shares(other, len(chosen))}")
        print(f"  no text:                  {shares(alone, len(chosen))}")
        if openings:
            print(
                "  no text, mouth opening r against the text-aligned mouth: "
                f"median {np.median(openings):.2f} "
                f"({len(openings)} lines); aligned b/m/p heard: {closed} of {bilabials} "
                f"({100 * closed / max(bilabials, 1):.0f} %)"
            )


PADDING_SECONDS = 3.0
MOVED = 0.05  # seconds a word onset may move before the line counts as moved


def measure_padded(part: str, folder: Path, every: int, scratch: Path) -> None:
    lines = people.sentence_lines(part, folder)
    for source in sorted({r.source.split("/")[0] for r in lines}):
        chosen = [r for r in lines if r.source.startswith(source)][::every]
        largest, not_clean = [], Counter()
        for recording in chosen:
            samples = people.read(recording, RATE)
            silence = np.zeros(int(PADDING_SECONDS * RATE), samples.dtype)
            plain = write_wav(scratch / "plain.wav", samples, RATE)
            padded = write_wav(scratch / "padded.wav", np.concatenate((silence, samples, silence)), RATE)
            timeline, result = aligned(recording.turkish, plain)
            again, again_result = aligned(recording.turkish, padded)
            not_clean["as they come"] += result != "clean"
            not_clean["padded"] += again_result != "clean"
            if timeline is not None and again is not None:
                starts = np.array([word.start for word in timeline.words])
                largest.append(np.abs([word.start - PADDING_SECONDS for word in again.words] - starts).max())
        moved = int(np.count_nonzero(np.array(largest) > MOVED))
        print(f"padded, {source} ({len(chosen)} lines, {PADDING_SECONDS:.0f} s of silence each side)")
        print(
            f"  lines with a word moved over {1000 * MOVED:.0f} ms: {moved} of {len(chosen)};"
            f" largest move median {1000 * np.median(largest):.0f} ms, max {1000 * max(largest):.0f} ms"
        )
        print(f"  not clean as they come: {not_clean['as they come']}, padded: {not_clean['padded']}")


MUSIC_SECONDS = 4.0
MUSIC_MOVED = 0.1


def measure_music(part: str, folder: Path, every: int, scratch: Path) -> None:
    music = takes.instrumental(MUSIC_SECONDS, RATE)
    lines = people.sentence_lines(part, folder)[::every]
    moved, largest, results, into = Counter(), {"intro": [], "outro": []}, Counter(), Counter()
    for recording in lines:
        samples = people.read(recording, RATE)
        if samples.size == 0:
            continue
        samples = 0.5 * samples / np.abs(samples).max()  # the music's peak 0.3 beside the voice's 0.5
        plain, _ = aligned(recording.turkish, write_wav(scratch / "plain.wav", samples, RATE))
        if plain is None:
            continue
        for name, take, lead in (("intro", (music, samples), MUSIC_SECONDS), ("outro", (samples, music), 0)):
            timeline, result = aligned(
                recording.turkish, write_wav(scratch / "music.wav", np.concatenate(take), RATE)
            )
            results[name, result] += 1
            if timeline is None:
                largest[name].append(np.inf)
            else:
                starts = [word.start - lead for word in timeline.words] + [timeline.words[-1].end - lead]
                truth = [word.start for word in plain.words] + [plain.words[-1].end]
                difference = np.array(starts) - truth
                largest[name].append(float(np.abs(difference).max()))
                # the first word started in the intro, or the last word ended in the outro
                into[name] += bool(
                    difference[0] < -MUSIC_MOVED if name == "intro" else difference[-1] > MUSIC_MOVED
                )
            into[name] += timeline is None
            moved[name] += largest[name][-1] > MUSIC_MOVED
    count = len(largest["intro"])
    print(f"music, {part} part ({count} lines, {MUSIC_SECONDS:.0f} s of an instrumental before or after)")
    for name in ("intro", "outro"):
        found = np.array(largest[name])
        print(
            f"  {name}: the speech drawn into the music (or refused) in {into[name]} of {count}; "
            f"a word moved over {1000 * MUSIC_MOVED:.0f} ms in {moved[name]}; "
            f"largest move median {1000 * np.median(found):.0f} ms; warned {results[name, 'warned']}, "
            f"refused {results[name, 'refused']}"
        )


MUSIC_GROUP = 28  # lines a take: about 100 s, the music 40 s and more from either end
MUSIC_GROUP_EVERY = 200


def measure_music_between(part: str, folder: Path, scratch: Path) -> None:
    """Takes of MUSIC_GROUP consecutive Czech lines (0.5 s apart; one every MUSIC_GROUP_EVERY lines) with
    the music between their halves: the words put in it (an onset more than MUSIC_MOVED inside it)."""
    music = takes.instrumental(MUSIC_SECONDS, RATE)
    lines = [r for r in people.sentence_lines(part, folder) if r.source.startswith("fillets-cs")]
    gap = np.zeros(RATE // 2)
    found = []
    for first in range(0, len(lines) - MUSIC_GROUP + 1, MUSIC_GROUP_EVERY):
        chosen = lines[first : first + MUSIC_GROUP]
        pieces = []
        for recording in chosen:
            clip = people.read(recording, RATE)
            pieces += [0.5 * clip / np.abs(clip).max(), gap] if clip.size else []
        half = len(pieces) // 4 * 2  # the first half's lines and their gaps
        start = sum(piece.size for piece in pieces[:half]) / RATE
        take = np.concatenate((*pieces[:half], music, *pieces[half:]))
        timeline, result = aligned(
            " ".join(r.turkish for r in chosen), write_wav(scratch / "between.wav", take, RATE)
        )
        inside = (start + MUSIC_MOVED, start + MUSIC_SECONDS - MUSIC_MOVED)
        words = None if timeline is None else sum(inside[0] < w.start < inside[1] for w in timeline.words)
        found.append(f"{words if words is not None else 'refused'} ({result})")
    print(f"music between, {part} part ({len(found)} takes of {MUSIC_GROUP} Czech lines, the music halfway)")
    print(f"  words put in the music: {', '.join(found)}")


BREAK_SECONDS = 20.0
BREAK_ROOM_DB = 55.0


def measure_breaks(part: str, folder: Path, every: int, scratch: Path, a_line_each: bool = False) -> None:
    """a_line_each: the script is the lines' spellings without punctuation, one line each (the text's only
    marks of where a line ends are its line breaks); else the spellings as they are, joined by spaces."""
    lines = [r for r in people.sentence_lines(part, folder) if r.source.startswith("fillets-cs")][::every]

    def script(recording: people.Recording) -> str:
        return re.sub(r"[^\w\s]", "", recording.turkish) if a_line_each else recording.turkish

    rng = np.random.default_rng(5)
    joined_match, alone_match, errors, warned, groups, across, warned_alone = [], [], [], 0, 0, 0, 0
    for first in range(0, len(lines) - 2, 3):
        group = lines[first : first + 3]
        clips = [people.read(recording, RATE) for recording in group]
        room = 10 ** (-BREAK_ROOM_DB / 20) * max(np.abs(clip).max() for clip in clips)
        spelling = "".join(recording.turkish for recording in group).replace(" ", "")
        heard_alone, starts, offset, results = "", [], 0.0, set()
        for recording, clip in zip(group, clips, strict=True):
            path = write_wav(scratch / "line.wav", clip, RATE)
            alone, _ = heard(path)
            heard_alone += "".join(phone.letter for phone in alone.phones) if alone is not None else ""
            timeline, result = aligned(script(recording), path)
            results.add(result)
            starts += [word.start + offset for word in timeline.words] if timeline is not None else []
            offset += clip.size / RATE + BREAK_SECONDS
        pieces = [part for clip in clips for part in (clip, rng.normal(0, room, int(BREAK_SECONDS * RATE)))]
        path = write_wav(scratch / "joined.wav", np.concatenate(pieces), RATE)
        joined, _ = heard(path)
        heard_joined = "".join(phone.letter for phone in joined.phones) if joined is not None else ""
        joined_match.append(difflib.SequenceMatcher(None, heard_joined, spelling).ratio())
        alone_match.append(difflib.SequenceMatcher(None, heard_alone, spelling).ratio())
        timeline, result = aligned(("\n" if a_line_each else " ").join(map(script, group)), path)
        groups += 1
        warned += result != "clean"
        warned_alone += results != {"clean"}
        if timeline is not None and len(timeline.words) == len(starts):
            errors.append(np.abs(np.array([word.start for word in timeline.words]) - starts))
            across += bool((errors[-1] > BREAK_SECONDS / 2).any())
    ms = 1000 * np.concatenate(errors)
    print(
        f"breaks, fillets-cs ({groups} takes of three lines, {BREAK_SECONDS:.0f} s of room between them"
        + ("; the script a line each, no punctuation)" if a_line_each else ")")
    )
    print(
        f"  no text: letters against the spellings {np.mean(joined_match):.3f} joined, "
        f"{np.mean(alone_match):.3f} each line alone"
    )
    print(
        f"  with the text: not clean {warned} of {groups} (a line of the take not clean alone: "
        f"{warned_alone}); a word put across a break in {across}; "
        f"word onsets against each line aligned alone median {np.median(ms):.0f}, "
        f"p90 {np.percentile(ms, 90):.0f}, max {ms.max():.0f} ms"
    )


LONG_MINUTES = 10


def measure_long(scratch: Path) -> None:
    take, spans = long_take(LONG_MINUTES, of_people=True)
    path = write_wav(scratch / "long.wav", take, RECORDED_RATE)
    del take
    joined, _ = heard(path)
    phones = joined.phones if joined is not None else ()
    together, alone = [], []
    for start, end, recording in spans:
        spelling = re.sub(r"[^\w]", "", recording.turkish)
        inside = "".join(p.letter for p in phones if start <= (p.start + p.end) / 2 < end)
        together.append(difflib.SequenceMatcher(None, inside, spelling, autojunk=False).ratio())
        line, _ = heard(recording.path)
        letters = "".join(p.letter for p in line.phones) if line is not None else ""
        alone.append(difflib.SequenceMatcher(None, letters, spelling, autojunk=False).ratio())
    print(f"long take, no text ({LONG_MINUTES} minutes: {len(spans)} acted lines one after the other)")
    print(
        f"  letters within each line's span against its spelling {np.mean(together):.4f}; "
        f"each line heard alone {np.mean(alone):.4f}"
    )


def measure_diphone_words(scratch: Path) -> None:
    """MBROLA's two Turkish speakers (lab/kit/diphone_voices.py) saying every distinct word of the held-out
    sentences alone, 0.4 s of silence each side, 40 dB pink noise: with the word's text, and with none."""
    words = sorted(
        {word for text in held_out_sentences() for word in re.findall(r"[^\W\d_]+(?:'\w+)?", text)}
    )
    rng = np.random.default_rng(4)
    for voice in ("tr1", "tr2"):
        with_text, without, errors, named = Counter(), Counter(), [], []
        for word in words:
            samples, _ = diphone_voices.speak(word, voice, takes.RATE)
            take = takes.Take(samples, np.zeros(1), np.zeros(0), np.zeros(1, bool))
            take = takes.add_noise(takes.padded(take, 0.4, 0.4), 40, "pink", rng)
            path = write_wav(scratch / "word.wav", take.samples, takes.RATE)
            timeline, result = aligned(word, path)
            with_text[result] += 1
            if timeline is not None:
                errors.append(abs(timeline.words[0].start - take.words[0]) * 1000)
            _, alone = heard(path)
            without[alone] += 1
            named += [f"{word} ({result})"] if result != "clean" else []
            named += [f"{word} (no text: {alone})"] if alone == "no speech" else []
        spread = f"median {np.median(errors):.0f}, p90 {np.percentile(errors, 90):.0f}, max {max(errors):.0f}"
        print(f"MBROLA {voice}: {len(words)} words said alone")
        print(f"  with their text: {shares(with_text, len(words))}; onsets (ms): {spread}")
        print(f"  no text:         {shares(without, len(words))}")
        print(f"  not clean: {', '.join(named) or 'none'}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", choices=("tune", "report"), default="report")
    parser.add_argument("--sets", nargs="+", default=["words", "syllables", "lists", "sentences"])
    parser.add_argument("--sentences", type=int, default=5, help="measure every Nth sentence")
    parser.add_argument("--aeneas", action="store_true", help="align the lists with aeneas too")
    parser.add_argument("--folder", type=Path, default=people.FOLDER)
    arguments = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as scratch:
        for name in arguments.sets:
            if name == "words":
                measure_words(arguments.part, arguments.folder)
            elif name == "syllables":
                measure_syllables(arguments.part, arguments.folder)
            elif name in LIST_SEPARATORS:
                separator = LIST_SEPARATORS[name]
                measure_lists(arguments.part, arguments.folder, arguments.aeneas, Path(scratch), separator)
            elif name == "sentences":
                measure_sentences(arguments.part, arguments.folder, arguments.sentences, Path(scratch))
            elif name == "padded":
                measure_padded(arguments.part, arguments.folder, arguments.sentences, Path(scratch))
            elif name in ("breaks", "breaks-lines"):
                every, a_line_each = arguments.sentences, name == "breaks-lines"
                measure_breaks(arguments.part, arguments.folder, every, Path(scratch), a_line_each)
            elif name == "long":
                measure_long(Path(scratch))
            elif name == "music":
                measure_music(arguments.part, arguments.folder, arguments.sentences, Path(scratch))
            elif name == "music-between":
                measure_music_between(arguments.part, arguments.folder, Path(scratch))
            elif name == "mbrola-words":
                measure_diphone_words(Path(scratch))
            sys.stdout.flush()
    for title, counts in (("other errors", ERRORS), ("warnings", WARNINGS)):
        if counts:
            print(f"{title}:")
            for message, count in counts.most_common(8):
                print(f"  {count:4d}  {message}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
