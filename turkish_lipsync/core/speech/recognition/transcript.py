"""What was heard, as the rest of the pipeline takes it: an Utterance of the heard letters and its Timeline.

Each phrase (letters between pauses) becomes one word: the recogniser hears no word boundaries inside
fluent speech, and a phrase is what a pause delimits in the exports too. The words go through the text
stage's last step (text/utterance.py's assemble_utterance), so their syllables and the vowel-context
visemes of Table 5.1 come from the same tables as a typed text's, and each letter keeps the span in which
it was heard.
"""

from __future__ import annotations

import numpy as np

from ...base.model import Pause, SpokenWord, Style, Timeline, Utterance
from ...text.utterance import assemble_utterance
from ..timing import build_timeline
from .recogniser import Recognition
from .settings import DEFAULT_RECOGNISER, RecogniserSettings

RECOGNISED_TIMING = "recognised"
# The network learnt eSpeak NG's phones, which start a voiceless stop at its burst: the closure before it
# is heard as the end of the letter before, and given back to the stop (closure_share), as the
# aligned timelines do (timewarp.with_closures).
VOICELESS_STOPS = frozenset("çkpt")


def heard_utterance(recognition: Recognition) -> Utterance:
    """The heard phrases as words of an utterance; its source is their text, one word per phrase."""
    items: list[SpokenWord | Pause] = []
    position = 0
    previous_end = 0.0
    texts = []
    for phrase in recognition.phrases:
        text = "".join(letter.letter for letter in phrase)
        if items:
            items.append(Pause(phrase[0].start - previous_end, position - 1, "break"))
        items.append(SpokenWord(text, tuple(range(position, position + len(text))), Style()))
        texts.append(text)
        position += len(text) + 1
        previous_end = phrase[-1].end
    return assemble_utterance(" ".join(texts), items)


def heard_timeline(
    utterance: Utterance,
    recognition: Recognition,
    duration: float,
    settings: RecogniserSettings = DEFAULT_RECOGNISER,
) -> Timeline:
    """Each letter of the heard utterance timed where it was heard, a voiceless stop from its closure."""
    starts, ends = [], []
    for phrase in recognition.phrases:
        for number, letter in enumerate(phrase):
            start = letter.start
            if number and letter.letter in VOICELESS_STOPS:
                before = phrase[number - 1]
                start -= settings.closure_share * (before.end - before.start)
                ends[-1] = min(ends[-1], start)
            starts.append(start)
            ends.append(letter.end)
    return build_timeline(utterance, np.array(starts), np.array(ends), duration, RECOGNISED_TIMING)
