"""Forced alignment: where each letter of a known text lies in a recording, from the network's posteriors.

A left-to-right hidden Markov model of the text: each letter a chain of states as long as its shortest
duration (its last state loops), and before every word and at both ends a silence that may be skipped, so
a speaker may pause between any two words or run them together; a pause may hold a hesitation's sound
("ııı", "eee", "mmm": a vowel or a nasal held, at a cost per frame), which then draws no word into it.
The emissions are the network's scaled likelihoods (posteriors over priors), as the recogniser's decoder
uses them; Viterbi finds the best path.
Every frame looks at a band of states only (`band`): a long take is aligned in memory that grows with its
length, not with the product of its frames and letters.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...base.model import Utterance
from ..voice_activity import runs
from .labels import CLASS_INDEX, SILENCE, VOWEL_CLASSES

PRIOR_WEIGHT = 0.8  # posteriors / priors ** PRIOR_WEIGHT (the decoder's)
ENTER_COST = 0.5  # natural-log units per letter entered: a slight push toward fewer, longer stays
POSTERIOR_FLOOR = 1e-3
PAUSE_COST = 2.0  # entering a pause between words costs this much more than going on speaking
# A hesitation's sound is held where it scores within HELD_MARGIN of the frame's best class on
# hesitation_frames frames of a run of hesitation_frames / HELD_SHARE: an "eee" the network hears with a few
# b- or d-like frames in it is held at its own scores (a grey-scale opening, the least score over the run,
# priced it under the next word's own vowel by about a nat a frame, and the word was drawn into it).
HELD_MARGIN = 1.0
HELD_SHARE = 0.6
# A pause may hold the sound the word before it ends on, or the vowel the next word begins with, only where
# PARTING_FRAMES or more of silence part the hold from that word, within PARTING_REACH frames of the hold's
# end (its fade): "eee, eğlenceliydi" is a hesitation, "eeeğlenceliydi" a drawn-out vowel.
PARTING_FRAMES = 5
PARTING_REACH = 5
VITERBI_BLOCK_CELLS = 1 << 20  # the forward pass gathers its frames' band scores this many at a time


@dataclass(frozen=True, eq=False)
class TextUnits:
    """The text's letters that are sounds, in order: their classes, word starts and utterance letters."""

    classes: np.ndarray
    word_starts: np.ndarray  # True where a letter begins a word (a pause may come before it)
    letters: np.ndarray  # index into Utterance.letters
    marked: np.ndarray  # True where a letter begins a word the text puts a pause before (a comma, a stop)


def text_units(utterance: Utterance) -> TextUnits:
    """The utterance's letters as the network's classes (a ğ, which is no sound of its own, left out)."""
    classes, starts, letters, marked = [], [], [], []
    for word in utterance.words:
        first = True
        for index in range(word.first_letter, word.first_letter + word.letter_count):
            name = utterance.letters[index].char
            if name in CLASS_INDEX:
                classes.append(CLASS_INDEX[name])
                starts.append(first)
                letters.append(index)
                marked.append(first and word.pause_before > 0)
                first = False
    return TextUnits(
        np.array(classes, np.int64),
        np.array(starts, bool),
        np.array(letters, np.int64),
        np.array(marked, bool),
    )


@dataclass(frozen=True, eq=False)
class LetterModel:
    """The states of a text's model: the class each state emits, where letters and pauses start."""

    classes: np.ndarray  # per state: class index (silence for pauses)
    loops: np.ndarray  # per state: it may repeat
    skippable: np.ndarray  # per state: a pause that may be skipped (the path jumps over it)
    letter_of_state: np.ndarray  # per state: index of its letter, -1 for a pause
    first_states: np.ndarray  # per letter: its first state
    unmarked: np.ndarray  # per state: a pause between two words the text puts none between


def letter_model(
    units: np.ndarray, word_starts: np.ndarray, shortest: np.ndarray, marked: np.ndarray | None = None
) -> LetterModel:
    """The model of a sequence of letter classes (`units`), pauses possible before each word start.

    shortest: per class, the fewest frames a letter of it lasts. marked: per unit, whether the text puts
    a pause before it (TextUnits.marked; every pause counts as marked where it is not given).
    """
    marked = np.ones(len(units), bool) if marked is None else marked
    classes, loops, skippable, owners, firsts = [CLASS_INDEX[SILENCE]], [True], [True], [-1], []
    unmarked = [False]
    for index, (unit, starts_word) in enumerate(zip(units, word_starts, strict=True)):
        if starts_word and index:
            classes.append(CLASS_INDEX[SILENCE])
            loops.append(True)
            skippable.append(True)
            owners.append(-1)
            unmarked.append(not marked[index])
        firsts.append(len(classes))
        length = int(max(1, shortest[unit]))
        classes += [int(unit)] * length
        loops += [False] * (length - 1) + [True]
        skippable += [False] * length
        owners += [index] * length
        unmarked += [False] * length
    classes.append(CLASS_INDEX[SILENCE])
    loops.append(True)
    skippable.append(True)
    owners.append(-1)
    unmarked.append(False)
    return LetterModel(
        np.array(classes, np.int64),
        np.array(loops),
        np.array(skippable),
        np.array(owners, np.int64),
        np.array(firsts, np.int64),
        np.array(unmarked),
    )


@dataclass(frozen=True, eq=False)
class ForcedAlignment:
    """Each letter's first frame and the frame after its last; each frame's state's letter (-1: a pause)."""

    starts: np.ndarray
    stops: np.ndarray
    frame_letters: np.ndarray
    frame_scores: np.ndarray  # per frame: the network's scaled log likelihood of the path's class there
    # per frame: the class of the hesitation's sound a pause holds there rather than silence (-1: none)
    frame_hesitations: np.ndarray


def force_align(
    log_posteriors: np.ndarray,
    priors: np.ndarray,
    model: LetterModel,
    band: tuple[np.ndarray, np.ndarray] | None = None,
    silence_bias: np.ndarray | None = None,
    break_cost: np.ndarray | None = None,
    hesitation_classes: np.ndarray | None = None,
    hesitation_cost: float = 0.0,
    hesitation_frames: int = 1,
) -> ForcedAlignment:
    """The best path of the frames through the model (every letter at least its shortest duration).

    band: per frame, the first state and the state after the last it may be in (the whole model if None);
    neither may decrease from one frame to the next (the text is read in order).
    silence_bias: per frame, added to silence's score (natural-log units): negative where a speech
    detector hears the speaker (the network, unsure of a voice unlike any it learnt from, hears silence
    sooner than a wrong letter), positive where a quiet voice in the background may fill a pause.
    break_cost: per frame, what a pause the text does not mark (LetterModel.unmarked) costs there more than
    one it marks: a long break in a session's recording lies where the text puts a pause, and the first
    words of the line after it are not drawn before it into the last one's dying sound.
    hesitation_classes: the classes a pause may hold (scored as the likeliest of them): a person's "ııı"
    before a word, one sound held for hesitation_frames or more (a word's run of such sounds is none),
    at hesitation_cost a frame.
    """
    frames = len(log_posteriors)
    states = len(model.classes)
    if band is None:
        low, high = np.zeros(frames, np.int64), np.full(frames, states, np.int64)
    else:
        low, high = band
        if np.any(np.diff(low) < 0) or np.any(np.diff(high) < 0):
            raise ValueError("the band of states moves back between frames")
    heard = (log_posteriors - PRIOR_WEIGHT * np.log(priors)[None, :]).astype(np.float64)
    # The network is sometimes sure of silence in a voice unlike any it learnt from: no letter is taken
    # for less likely than POSTERIOR_FLOOR, so the detector's speech can still outweigh it.
    scores = np.maximum(log_posteriors, np.log(POSTERIOR_FLOOR)) - PRIOR_WEIGHT * np.log(priors)[None, :]
    if silence_bias is not None:
        scores[:, CLASS_INDEX[SILENCE]] += silence_bias[:frames]
    # A pause emits a class of its own: silence, or in a pause the text does not mark (where a person
    # hesitates, not between a list's items) a hesitation's sound if it scores higher; an unmarked pause
    # its score less the break's cost.
    silent = scores[:, CLASS_INDEX[SILENCE]]
    hesitating, sound_of_kind, kind_of_state = _hesitating(
        scores, model, hesitation_classes, hesitation_cost, hesitation_frames
    )
    unmarked = np.maximum(silent[:, None], hesitating)
    unmarked -= 0.0 if break_cost is None else break_cost[:frames, None]
    classes = scores.shape[1]
    scores = np.column_stack((scores, unmarked))
    pause_column = np.where(model.unmarked, classes + kind_of_state, CLASS_INDEX[SILENCE])
    emitted = np.where(model.letter_of_state < 0, pause_column, model.classes)
    last_scores, moves = _viterbi(scores, emitted, model, low, high)
    last = states - 1
    end = last if last_scores[last + 2] >= last_scores[last + 1] else last - 1
    if not np.isfinite(last_scores[end + 2]):
        raise ValueError("no path through the text's model within the band")
    path = np.empty(frames, np.int64)
    state = end
    for frame in range(frames - 1, -1, -1):
        path[frame] = state
        if frame:
            state -= int(moves[frame, state - low[frame]])
    frame_letters = model.letter_of_state[path]
    starts, stops = _letter_spans(frame_letters, len(model.first_states))
    frame_scores = heard[np.arange(frames), model.classes[path]]
    every, kinds = np.arange(frames), kind_of_state[path]
    held = model.unmarked[path] & (hesitating[every, kinds] > silent)
    frame_hesitations = np.where(held, sound_of_kind[every, kinds], -1)
    return ForcedAlignment(starts, stops, frame_letters, frame_scores, frame_hesitations)


def _hesitating(
    scores: np.ndarray, model: LetterModel, classes: np.ndarray | None, cost: float, frames: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per frame, a hesitation's score for each kind of pause and the class that scores it, and each
    state's kind: the best of the classes held for `frames` or more, less `cost`. The sound the word
    before the pause ends on, and the vowel the next word begins with, are held only where a silence
    parts the hold from that word (_parted): unparted, they are those words' own (a drawn-out vowel, a
    room's tail). One kind that holds none where no classes are given."""
    if classes is None or len(classes) == 0:
        none = np.full((len(scores), 1), -np.inf)
        return none, np.full(none.shape, -1), np.zeros(len(model.classes), np.int64)
    sounds = np.asarray(classes)
    held = _held(scores[:, sounds], scores.max(axis=1), frames) - cost
    silent = scores.argmax(axis=1) == CLASS_INDEX[SILENCE]
    sounding = np.isfinite(held) & ~silent[:, None]
    parted = (_parted(sounding, silent, after=False), _parted(sounding, silent, after=True))
    theirs = _neighbouring_sounds(model)[:, :, None] == sounds[None, None, :]
    kinds, kind_of_state = np.unique(theirs.reshape(len(theirs), -1), axis=0, return_inverse=True)
    hesitating = np.full((len(scores), len(kinds)), -np.inf)
    sound = np.full(hesitating.shape, -1)
    for column, kind in enumerate(kinds):
        before, after = kind.reshape(2, -1)
        allowed = (parted[0] | ~before) & (parted[1] | ~after)
        kept = np.where(allowed, held, -np.inf)
        best = kept.argmax(axis=1)
        hesitating[:, column] = kept[np.arange(len(scores)), best]
        sound[:, column] = sounds[best]
    return hesitating, sound, kind_of_state.reshape(-1)


def parting_gaps(silent: np.ndarray) -> np.ndarray:
    """(start, stop) of each run of PARTING_FRAMES or more silent frames: a pause that parts a
    hesitation from a word holding its sound."""
    found = runs(silent)
    return found[found[:, 1] - found[:, 0] >= PARTING_FRAMES]


def _parted(held: np.ndarray, silent: np.ndarray, after: bool) -> np.ndarray:
    """frames x columns: True on each run of `held` frames that a parting gap (parting_gaps of
    `silent`) follows (`after`) or precedes within PARTING_REACH frames."""
    frames = len(silent)
    if not after:
        return _parted(held[::-1], silent[::-1], True)[::-1]
    gap_starts = np.zeros(frames + 1, bool)
    gap_starts[parting_gaps(silent)[:, 0]] = True
    reach = np.concatenate(([0], np.cumsum(gap_starts)))
    index = np.arange(frames + 1)
    near = reach[np.minimum(index + PARTING_REACH + 1, frames + 1)] - reach[index] > 0  # a gap from here
    # Each frame's run end: the first frame at or after it that is not held.
    ending = np.where(np.vstack((~held, np.ones((1, held.shape[1]), bool))), index[:, None], frames)
    run_end = np.minimum.accumulate(ending[::-1], axis=0)[::-1][:frames]
    return held & near[run_end]


def _neighbouring_sounds(model: LetterModel) -> np.ndarray:
    """states x 2: for a pause, the class of the letter before it and of the next word's first letter
    where that is a vowel (-1 where there is none); -1, -1 for a letter's state. A word that begins with
    a consonant keeps the pause free to hold its vowel's sound: the consonant parts the two ("eee
    gelmeden")."""
    found = np.full((len(model.classes), 2), -1, np.int64)
    vowels = np.isin(model.classes, VOWEL_CLASSES)
    for state in np.flatnonzero(model.letter_of_state < 0).tolist():
        if state and model.letter_of_state[state - 1] >= 0:
            found[state, 0] = model.classes[state - 1]
        following = state + 1
        if following < len(model.classes) and model.letter_of_state[following] >= 0 and vowels[following]:
            found[state, 1] = model.classes[following]
    return found


def _held(scores: np.ndarray, best: np.ndarray, frames: int) -> np.ndarray:
    """Each column's scores where it is held: within HELD_MARGIN of the frame's best score (`best`) on
    `frames` frames or more of a run of frames / HELD_SHARE holding that frame (a sound heard more
    briefly, a word's vowel between its consonants, is not held); -inf elsewhere."""
    if frames <= 1:
        return scores
    if len(scores) < frames:
        return np.full_like(scores, -np.inf)
    run = min(len(scores), int(np.ceil(frames / HELD_SHARE)))
    runs_held = _run_sums(scores >= best[:, None] - HELD_MARGIN, run) >= frames  # the run from each frame
    holding = _run_sums(np.pad(runs_held, ((run - 1, run - 1), (0, 0))), run)  # the runs over each frame
    return np.where(holding > 0, scores, -np.inf)


def _run_sums(flags: np.ndarray, run: int) -> np.ndarray:
    """Each column's count of true flags in every run of `run` rows, one per row a run can start on."""
    counts = np.cumsum(flags, axis=0)
    return counts[run - 1 :] - np.concatenate((np.zeros((1, flags.shape[1]), counts.dtype), counts[:-run]))


def _transitions(model: LetterModel) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per state, the log cost of staying in it, of entering it from the state before, and of entering
    it from two before (skipping a pause)."""
    states = len(model.classes)
    stay = np.where(model.loops, 0.0, -np.inf)
    enter = np.where(model.letter_of_state >= 0, -ENTER_COST, -ENTER_COST - PAUSE_COST)
    # Entering state s from s-2 skips the pause s-1.
    jump = np.full(states, -np.inf)
    jump[2:] = np.where(model.skippable[1:-1], enter[2:], -np.inf)
    # A letter's later states are entered at no cost: the cost is paid once, at its first state.
    first_of_letter = np.zeros(states, bool)
    first_of_letter[model.first_states] = True
    enter = np.where(first_of_letter | (model.letter_of_state < 0), enter, 0.0)
    return stay, enter, jump


def _viterbi(
    scores: np.ndarray, emitted: np.ndarray, model: LetterModel, low: np.ndarray, high: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The forward pass within the band, each state scored by its `emitted` column of `scores`: the best
    path's score into each state at the last frame (with two guard states before state 0), and each
    frame's move into each state of its band (0 stay, 1 from the state before, 2 from two before; a tie
    keeps the lower)."""
    frames, states = len(scores), len(model.classes)
    stay, enter, jump = _transitions(model)
    width = int((high - low).max())
    moves = np.zeros((frames, width), np.int8)
    entering = moves.view(bool)  # a move's first decision: entered rather than stayed
    previous = np.full(states + 2, -np.inf)  # two guard states before state 0
    start = np.full(states, -np.inf)
    start[0] = 0.0
    start[1] = 0.0 if model.skippable[0] else -np.inf
    current = np.full(states + 2, -np.inf)
    current[2:] = start
    current[2:][low[0] : high[0]] += scores[0, emitted[low[0] : high[0]]]
    current[2:][: low[0]] = -np.inf
    current[2:][high[0] :] = -np.inf
    # Each array's scores are finite from this index up, and nowhere past its band's end: the bands never
    # move back, so a frame's write covers all but what lies under its band (set to -inf there).
    current_from, previous_from = 0, states + 2
    lows, highs = low.tolist(), high.tolist()
    block_length = max(1, VITERBI_BLOCK_CELLS // max(width, 1))
    for block in range(1, frames, block_length):  # each frame's band of scores, a block of frames at a time
        block_frames = np.arange(block, min(block + block_length, frames))
        band_states = np.minimum(low[block_frames, None] + np.arange(width), states - 1)
        band_scores = scores[block_frames[:, None], emitted[band_states]]
        for row, frame in enumerate(block_frames.tolist()):
            previous, current = current, previous
            previous_from, current_from = current_from, previous_from
            first, stop = lows[frame], highs[frame]
            if current_from < first + 2:
                current[current_from : first + 2] = -np.inf
            size = stop - first
            best = previous[first + 2 : stop + 2] + stay[first:stop]
            entered = previous[first + 1 : stop + 1] + enter[first:stop]
            jumped = previous[first:stop] + jump[first:stop]
            np.greater(entered, best, out=entering[frame, :size])
            np.maximum(best, entered, out=best)
            np.putmask(moves[frame, :size], jumped > best, 2)
            np.maximum(best, jumped, out=best)
            np.add(best, band_scores[row, :size], out=current[first + 2 : stop + 2])
            current_from = first + 2
    return current, moves


def _letter_spans(frame_letters: np.ndarray, letters: int) -> tuple[np.ndarray, np.ndarray]:
    """Each letter's first frame along the path and the frame after its last (-1 for a letter the path
    does not visit; letters are visited in order)."""
    starts = np.full(letters, -1, np.int64)
    stops = np.full(letters, -1, np.int64)
    spoken = np.flatnonzero(frame_letters >= 0)
    owners = frame_letters[spoken]
    change = np.flatnonzero(np.diff(owners, prepend=-2) != 0)
    starts[owners[change]] = spoken[change]
    ends = np.flatnonzero(np.diff(owners, append=-2) != 0)
    stops[owners[ends]] = spoken[ends] + 1
    return starts, stops
