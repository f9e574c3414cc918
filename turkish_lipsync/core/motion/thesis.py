"""The thesis's motion model: linear morphing between letter models with emotion cross-fade (eq. 5.3, 5.4)."""

from __future__ import annotations

import numpy as np

from ..base.data import DATA_DIR, load_table, require
from ..base.errors import DataError
from ..base.model import Timeline, WeightTracks, emotion_key_name, viseme_key_name
from ..base.visemes import NEUTRAL
from .base import MOTION_MODELS, MotionModel
from .frames import frame_count_for, sparse_track


def thesis_weight_tracks(timeline: Timeline, fps: float, emotion_strength: float = 1.0) -> WeightTracks:
    """The thesis's weighted morphing (eq. 5.3, 5.4), one key per letter onset (and per hesitation said
    aloud in a recording's pauses).

    Lips morph linearly from letter to letter at weight (1 - w); the empowered emotion of each letter's word
    is keyed at w (the emotion key, which holds E - N, at rho * w), so consecutive words in different emotions
    cross-fade over the letters between them. w is the thesis's constant (shapekeys/motion.toml [thesis])
    times the JSML weight and the emotion strength. The face starts and ends on the neutral model.
    """
    emotion_weight, empowering = _thesis_constants()
    word_weight = _word_emotion_weights(timeline, emotion_strength * emotion_weight)
    # A hesitation said aloud is keyed as a letter is, in the emotion of the letter before it.
    sounds = sorted(
        [(p.start, p.viseme, p.word_index) for p in timeline.phones]
        + [(h.start, h.viseme, None) for h in timeline.hesitations],
        key=lambda sound: sound[0],
    )
    word = None
    emotions_said = []
    for _, _, index in sounds:
        word = word if index is None else index
        emotions_said.append(word_weight.get(word))
    last = max([timeline.duration] + [p.end for p in timeline.phones] + [h.end for h in timeline.hesitations])
    times = [0.0] + [sound[0] for sound in sounds] + [last]
    visemes = [NEUTRAL] + [sound[1] for sound in sounds] + [NEUTRAL]
    emotions = [None] + emotions_said + [None]

    names = sorted({viseme_key_name(v) for v in visemes})
    names += sorted({emotion_key_name(e[0]) for e in emotions if e})
    column = {name: i for i, name in enumerate(names)}
    values = np.zeros((len(times), len(names)))
    for row, (viseme, emotion) in enumerate(zip(visemes, emotions, strict=True)):
        weight = emotion[1] if emotion else 0.0
        values[row, column[viseme_key_name(viseme)]] = 1.0 - weight
        if emotion:
            values[row, column[emotion_key_name(emotion[0])]] = weight * empowering
    frames = np.asarray(times) * fps
    tracks = tuple(sparse_track(name, frames, values[:, column[name]]) for name in names)
    return WeightTracks(
        fps=fps,
        frame_count=frame_count_for(timeline.duration, fps),
        interpolation="LINEAR",
        tracks=tracks,
        mode="thesis",
    )


def _thesis_constants() -> tuple[float, float]:
    """(w, rho): the thesis's emotion weight and empowering constant, from shapekeys/motion.toml."""
    table = require(load_table("motion"), "thesis", dict, "motion")
    weight, empowering = table.get("emotion_weight"), table.get("empowering")
    if not isinstance(weight, int | float) or not 0 < weight <= 1:
        raise DataError(f"{DATA_DIR / 'motion.toml'}: [thesis] emotion_weight must be in (0, 1]")
    if not isinstance(empowering, int | float) or empowering < 1:
        raise DataError(f"{DATA_DIR / 'motion.toml'}: [thesis] empowering must be at least 1")
    return float(weight), float(empowering)


def _word_emotion_weights(timeline: Timeline, emotion_strength: float) -> dict[int, tuple[str, float]]:
    """Word index -> (emotion, weight w) from the emotion spans."""
    result = {}
    for word in timeline.words:
        for span in timeline.emotions:
            if span.start <= word.start and word.end <= span.end:
                result[word.index] = (span.emotion, min(1.0, max(0.0, span.weight * emotion_strength)))
    return result


@MOTION_MODELS.register
class ThesisMotion(MotionModel):
    name = "thesis"
    label = "Thesis"
    description = "The thesis's weighted morphing from letter to letter (eq. 5.3, 5.4)"

    def weight_tracks(self, timeline: Timeline, fps: float, emotion_strength: float = 1.0) -> WeightTracks:
        return thesis_weight_tracks(timeline, fps, emotion_strength)
