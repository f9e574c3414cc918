"""From frame posteriors to a sequence of letters with their spans: Viterbi over a hidden Markov model.

Each class (a letter or silence, labels.py) is a chain of states as long as its shortest duration in the
training speech (scaled by duration_scale, since people speak faster than eSpeak's slowest), so no letter
flickers in for a frame; its last state loops. Leaving a class for another costs the log of how often
the one follows the other in Turkish (the training texts' transitions, language_weight) plus a fixed
price per letter (insertion_cost), which keeps the mouth from chattering. The posteriors are divided by
the classes' priors (a hybrid network-HMM's scaled likelihoods). The state scores and back-pointers are
one small array per frame, so a take of any length decodes in memory proportional to its frames.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .settings import DEFAULT_RECOGNISER, RecogniserSettings

EMISSION_BLOCK = 2048  # frames whose per-state scores are laid out at a time


@dataclass(frozen=True)
class Segment:
    """A run of frames decoded as one class."""

    label: int  # index into CLASSES
    first: int  # frame
    stop: int  # frame after the last


def decode(
    log_posteriors: np.ndarray,
    priors: np.ndarray,
    transitions: np.ndarray,
    shortest: np.ndarray,
    settings: RecogniserSettings = DEFAULT_RECOGNISER,
):
    """The best segmentation of the frames into classes (tuple of Segment, in order)."""
    frames, classes = log_posteriors.shape
    if frames == 0:
        return ()
    scores = (log_posteriors - settings.prior_weight * np.log(priors)[None, :]).astype(np.float64)
    follows = transitions / transitions.sum(axis=1, keepdims=True)
    switch = settings.language_weight * np.log(follows) - settings.insertion_cost
    np.fill_diagonal(switch, -np.inf)  # a class follows itself by its loop, not by a new segment
    lengths = np.maximum(1, np.round(shortest * settings.duration_scale).astype(np.int64))
    firsts = np.concatenate(([0], np.cumsum(lengths)[:-1]))
    lasts = firsts + lengths - 1
    owner = np.repeat(np.arange(classes), lengths)
    columns = np.arange(classes)
    state = np.full(lengths.sum(), -np.inf)
    state[firsts] = scores[0] + np.log(1.0 / classes)
    entered_from = np.zeros((frames, classes), np.int8)  # class left to enter each class's first state
    stayed = np.zeros((frames, classes), bool)  # whether each class's last state looped
    new = np.empty_like(state)
    for begin in range(1, frames, EMISSION_BLOCK):
        emissions = scores[begin : begin + EMISSION_BLOCK][:, owner]  # per state, a block of frames at a time
        for offset, emission in enumerate(emissions):
            leaving = state[lasts]
            options = leaving[:, None] + switch
            origin = options.argmax(axis=0)
            new[1:] = state[:-1]  # every state but a class's first is fed by the one before it
            new[firsts] = options[origin, columns]
            arriving = new[lasts]  # from the chain, or (a one-state class) entered from another class
            loops = leaving >= arriving
            new[lasts] = np.maximum(leaving, arriving)
            new += emission
            state, new = new, state
            entered_from[begin + offset] = origin
            stayed[begin + offset] = loops
    return _trace_back(state, entered_from, stayed, lengths, lasts)


def _trace_back(state, entered_from, stayed, lengths, lasts) -> tuple[Segment, ...]:
    frames = len(entered_from)
    label = int(np.argmax(state[lasts]))  # the take ends in some class's last state
    segments = []
    stop = frames
    frame = frames - 1
    while frame >= 0:
        # Walk back through the loop of the last state, then the chain, to the class's entry frame.
        while frame > 0 and stayed[frame, label]:
            frame -= 1
        first = max(0, frame - (lengths[label] - 1))
        segments.append(Segment(label, first, stop))
        if first == 0:
            break
        label, stop, frame = int(entered_from[first, label]), first, first - 1
    return tuple(reversed(segments))
