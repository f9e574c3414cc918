"""The default motion model: co-articulated lips, hard closures, layered emotions, blinks and brows.

The thesis morphs linearly from one letter's model to the next and gives the emotion weight w by taking it
from the lips (eq. 5.3, 5.4). That pops on short phones, misses closures that fall between frames, and a
smile weakens every m, b and p. Here instead:

- every phone has a dominance over the face (Cohen and Massaro): a plateau over the middle of the phone,
  decaying exponentially before it (anticipation) and after it (carry-over), strong and far-reaching for
  rounded vowels, weak for consonants whose lips follow the vowel. Each frame shows the visemes in proportion
  to their dominances, so the viseme weights sum to exactly 1 (neutral is one of them, it holds the silences);
- bilabials (m, b, p) and labiodentals (f, v) are hard targets: each gets a frame of its own at full weight,
  however short the phone, with a ramp around it;
- a shape that would be shown for a single frame (and is not a closure) is lowered below half weight, so it
  blends into its neighbours instead of flashing;
- emotions are separate layers at full strength with onset, apex and offset ramps; their mouth part gives
  way (TR_emotion_<e>_mouth_release) exactly as much as the lips need to close.

Blinks, gaze, head motion, brows and the life of an emotion's apex are the living layers over either model
(motion/living/).

Parameters live in shapekeys/motion.toml.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

import numpy as np

from ..base.data import DATA_DIR, load_table, require
from ..base.errors import DataError
from ..base.model import (
    Timeline,
    WeightTracks,
    emotion_key_name,
    emotion_release_key_name,
    viseme_key_name,
)
from ..base.visemes import BILABIAL_VISEMES, LABIODENTAL_VISEMES, NEUTRAL, VISEME_NAMES, visemes_of_kind
from .base import MOTION_MODELS, MotionModel
from .frames import frame_count_for, shape_runs, shown_shapes, sparse_track

HARD_TARGETS = BILABIAL_VISEMES | LABIODENTAL_VISEMES
TABLE = "motion"


@dataclass(frozen=True)
class VisemeClass:
    name: str
    dominance: float
    anticipation: float  # seconds
    carryover: float  # seconds
    lip_need: float  # 0..1: how far the emotion's mouth part must give way


@dataclass(frozen=True)
class MotionParameters:
    hold_fraction: float
    shape_exponent: float
    min_weight: float
    min_rest_gap: float
    closure_ramp: float
    blend_ceiling: float
    classes: dict[str, VisemeClass]  # viseme name -> its class
    emotion_onset: float
    emotion_offset: float
    emotion_merge_gap: float


def _number(section: dict, key: str, where: str, low: float = 0.0, high: float = math.inf) -> float:
    value = section.get(key)
    if isinstance(value, bool) or not isinstance(value, int | float) or not low <= value <= high:
        raise DataError(
            f"data file {DATA_DIR / (TABLE + '.toml')}: [{where}] {key} must be a number in [{low}, {high}], "
            f"got {value!r}; fix the entry or reinstall the extension"
        )
    return float(value)


@cache
def motion_parameters() -> MotionParameters:
    """The validated contents of shapekeys/motion.toml (read once per process)."""
    table = load_table(TABLE)
    path = DATA_DIR / (TABLE + ".toml")
    co = require(table, "coarticulation", dict, TABLE)
    classes_table = require(table, "classes", dict, TABLE)
    emotions = require(table, "emotions", dict, TABLE)

    classes: dict[str, VisemeClass] = {}
    for name, entry in classes_table.items():
        where = f"classes.{name}"
        visemes = entry.get("visemes") if isinstance(entry, dict) else None
        if not isinstance(visemes, list) or not visemes:
            raise DataError(f"data file {path}: [{where}] needs a non-empty list 'visemes'")
        viseme_class = VisemeClass(
            name=name,
            dominance=_number(entry, "dominance", where, 1e-6),
            anticipation=_number(entry, "anticipation", where, 1e-4),
            carryover=_number(entry, "carryover", where, 1e-4),
            lip_need=_number(entry, "lip_need", where, 0.0, 1.0),
        )
        for viseme in visemes:
            if viseme in classes:
                raise DataError(f"data file {path}: viseme {viseme!r} is in two classes; keep it in one")
            classes[viseme] = viseme_class
    missing = sorted(set(VISEME_NAMES) - set(classes))
    unknown = sorted(set(classes) - set(VISEME_NAMES))
    if missing or unknown:
        raise DataError(
            f"data file {path}: every viseme needs exactly one class "
            f"(missing: {', '.join(missing) or 'none'}; unknown: {', '.join(unknown) or 'none'})"
        )
    for kind in ("rest", "bilabial", "labiodental"):  # the classes the motion holds to, as the set says
        named = {viseme for viseme, viseme_class in classes.items() if viseme_class.name == kind}
        if named != visemes_of_kind(kind):
            raise DataError(
                f"data file {path}: [classes.{kind}] must hold the visemes viseme_set.toml calls {kind}: "
                f"{', '.join(sorted(visemes_of_kind(kind)))}"
            )
    return MotionParameters(
        hold_fraction=_number(co, "hold_fraction", "coarticulation", 0.0, 1.0),
        shape_exponent=_number(co, "shape_exponent", "coarticulation", 0.25, 4.0),
        min_weight=_number(co, "min_weight", "coarticulation", 0.0, 0.1),
        min_rest_gap=_number(co, "min_rest_gap", "coarticulation", 0.0),
        closure_ramp=_number(co, "closure_ramp", "coarticulation", 0.0),
        blend_ceiling=_number(co, "blend_ceiling", "coarticulation", 0.0, 0.499),
        classes=classes,
        emotion_onset=_number(emotions, "onset", "emotions", 1e-3),
        emotion_offset=_number(emotions, "offset", "emotions", 1e-3),
        emotion_merge_gap=_number(emotions, "merge_gap", "emotions", 0.0),
    )


# ---------------------------------------------------------------- public entry point


def natural_weight_tracks(
    timeline: Timeline,
    fps: float,
    emotion_strength: float = 1.0,
) -> WeightTracks:
    """Weight tracks of the default motion model, keyed at integer frames (linear in between)."""
    if fps <= 0:
        raise ValueError(f"frame rate must be positive, got {fps}")
    params = motion_parameters()
    frame_count = frame_count_for(timeline.duration, fps)
    times = np.arange(frame_count) / fps

    visemes, weights, closure_frames = viseme_weights(timeline, fps, frame_count, params)
    columns: dict[str, np.ndarray] = {viseme_key_name(v): weights[:, i] for i, v in enumerate(visemes)}

    # einsum, not a matrix product: that wakes BLAS threads that spin a tenth of a second on the other cores
    lip_need = np.einsum("fv,v->f", weights, np.array([params.classes[v].lip_need for v in visemes]))
    emotion_curves = _emotion_curves(timeline, times, emotion_strength, params)
    for emotion, curve in emotion_curves.items():
        columns[emotion_key_name(emotion)] = curve
        columns[emotion_release_key_name(emotion)] = curve * np.clip(lip_need, 0.0, 1.0)

    key_frames = np.arange(frame_count, dtype=np.float64)
    tracks = tuple(sparse_track(name, key_frames, values) for name, values in columns.items())
    return WeightTracks(
        fps=fps,
        frame_count=frame_count,
        interpolation="LINEAR",
        tracks=tracks,
        mode="natural",
        extra={"closure_frames": tuple(closure_frames)},
    )


# ---------------------------------------------------------------- visemes: co-articulation


@dataclass(frozen=True)
class _Segment:
    start: float
    end: float
    viseme: str
    phone_index: int  # -1 for a rest; a hesitation said aloud numbered on after the phones


def _segments(timeline: Timeline, params: MotionParameters) -> list[_Segment]:
    """The phones and the hesitations said aloud, with rests before, after, and in every silence long
    enough to relax the face."""
    sounds = [(p.start, p.end, p.viseme, p.letter_index) for p in timeline.phones]
    after = len(timeline.phones)
    sounds += [(h.start, h.end, h.viseme, after + k) for k, h in enumerate(timeline.hesitations)]
    sounds.sort(key=lambda sound: sound[0])
    end_of_time = max(timeline.duration, sounds[-1][1] if sounds else 0.0)
    if not sounds:
        return [_Segment(-1.0, end_of_time + 1.0, NEUTRAL, -1)]
    segments = [_Segment(-1.0, sounds[0][0], NEUTRAL, -1)]
    for previous, (start, end, viseme, index) in zip([None, *sounds[:-1]], sounds, strict=True):
        if previous is not None and start - previous[1] >= params.min_rest_gap:
            segments.append(_Segment(previous[1], start, NEUTRAL, -1))
        segments.append(_Segment(start, max(end, start), viseme, index))
    segments.append(_Segment(sounds[-1][1], end_of_time + 1.0, NEUTRAL, -1))
    return segments


def viseme_weights(
    timeline: Timeline, fps: float, frame_count: int, params: MotionParameters | None = None
) -> tuple[tuple[str, ...], np.ndarray, list[tuple[int, int]]]:
    """(visemes, weights[frame, viseme] summing to 1 per frame, [(phone index, closure frame)])."""
    params = params or motion_parameters()
    segments = _segments(timeline, params)
    visemes = tuple(sorted({s.viseme for s in segments}))
    column = {v: i for i, v in enumerate(visemes)}

    # Hard targets get a frame of their own first, so their dominance can be centred on it.
    closures = _closure_frames(segments, fps, frame_count)
    closure_frame_of = dict(closures)

    weights = _summed_dominance(segments, closure_frame_of, column, fps, frame_count, params)
    weights = _normalised(weights, column[NEUTRAL])
    weights[weights < params.min_weight] = 0.0
    weights = _normalised(weights, column[NEUTRAL])

    weights = _apply_closures(weights, segments, closures, column, fps, params)
    claimed = np.zeros(frame_count, dtype=bool)
    claimed[[frame for _, frame in closures]] = True
    weights = _blend_single_frame_shapes(weights, visemes, claimed, params)
    return visemes, weights, closures


def _summed_dominance(
    segments: list[_Segment],
    closure_frame_of: dict[int, int],
    column: dict[str, int],
    fps: float,
    frame_count: int,
    params: MotionParameters,
) -> np.ndarray:
    """Each viseme's summed dominance per frame: array[frame, viseme].

    A dominance is evaluated only where it exceeds 1e-5 of its peak (its window), so the cost grows with the
    number of phones, not with phones times frames.
    """
    count = len(segments)
    classes = [params.classes[s.viseme] for s in segments]
    peak = np.array([c.dominance for c in classes])
    anticipation = np.array([c.anticipation for c in classes])
    carryover = np.array([c.carryover for c in classes])
    start = np.array([s.start for s in segments])
    end = np.array([s.end for s in segments])
    rest = np.array([s.phone_index < 0 for s in segments])
    center = (start + end) / 2
    half_hold = (end - start) / 2 * np.where(rest, 1.0, params.hold_fraction)
    for k, segment in enumerate(segments):
        if segment.phone_index in closure_frame_of:
            center[k] = closure_frame_of[segment.phone_index] / fps
    reach = math.log(1e5) ** (1.0 / params.shape_exponent)
    first = np.floor((center - half_hold - anticipation * reach) * fps)
    last = np.ceil((center + half_hold + carryover * reach) * fps)
    first = np.clip(first, 0, frame_count - 1).astype(int)
    last = np.clip(last, 0, frame_count - 1).astype(int)
    lengths = np.maximum(last - first + 1, 0)
    owner = np.repeat(np.arange(count), lengths)
    position = np.arange(owner.size) - np.repeat(np.cumsum(lengths) - lengths, lengths)
    frames = first[owner] + position
    offset = frames / fps - center[owner]
    distance = np.maximum(np.abs(offset) - half_hold[owner], 0.0)
    time_constant = np.where(offset < 0, anticipation[owner], carryover[owner])
    dominance = peak[owner] * np.exp(-((distance / time_constant) ** params.shape_exponent))
    viseme_column = np.array([column[s.viseme] for s in segments])
    flat = np.bincount(
        frames * len(column) + viseme_column[owner], weights=dominance, minlength=frame_count * len(column)
    )
    return flat.reshape(frame_count, len(column))


def _normalised(weights: np.ndarray, neutral: int) -> np.ndarray:
    """Rows scaled to sum to 1; an empty row becomes the rest pose."""
    totals = weights.sum(axis=1, keepdims=True)
    empty = totals[:, 0] <= 0
    weights = np.divide(weights, totals, out=np.zeros_like(weights), where=totals > 0)
    weights[empty, neutral] = 1.0
    return weights


def _closure_frames(segments: list[_Segment], fps: float, frame_count: int) -> list[tuple[int, int]]:
    """A distinct frame for every hard-target phone: inside the phone if a frame falls there, else nearest.

    Phones shorter than a frame (fast speech) still get one; two such phones in a row get neighbouring frames.
    """
    taken: set[int] = set()
    result = []
    for segment in segments:
        if segment.phone_index < 0 or segment.viseme not in HARD_TARGETS:
            continue
        center = (segment.start + segment.end) / 2 * fps
        inside = range(math.ceil(segment.start * fps), math.floor(segment.end * fps) + 1)
        candidates = sorted(inside, key=lambda f: (abs(f - center), f)) or [round(center)]
        nearest = candidates[0]
        candidates += sorted(range(nearest - 3, nearest + 4), key=lambda f: (abs(f - center), f))
        frame = next((f for f in candidates if f not in taken and 0 <= f < frame_count), None)
        if frame is None:
            frame = min((f for f in range(frame_count) if f not in taken), key=lambda f: abs(f - center))
        taken.add(frame)
        result.append((segment.phone_index, frame))
    return result


def _apply_closures(
    weights: np.ndarray,
    segments: list[_Segment],
    closures: list[tuple[int, int]],
    column: dict[str, int],
    fps: float,
    params: MotionParameters,
) -> np.ndarray:
    """Pull each hard target to full weight on its frame, with a linear ramp on both sides."""
    weights = weights.copy()
    viseme_of = {s.phone_index: s.viseme for s in segments}
    ramp_frames = max(1.0, params.closure_ramp * fps)
    claimed = {frame for _, frame in closures}
    frames = np.arange(weights.shape[0])
    # Weaker pulls first, so where two ramps overlap the nearer closure has the last word.
    pulls = []
    for phone_index, frame in closures:
        strength = np.clip(1.0 - np.abs(frames - frame) / ramp_frames, 0.0, 1.0)
        for f in np.flatnonzero(strength > 0):
            if f == frame or f not in claimed:
                pulls.append((strength[f], int(f), column[viseme_of[phone_index]]))
    for strength, f, target in sorted(pulls):
        weights[f] *= 1.0 - strength
        weights[f, target] += strength
    return weights


def _blend_single_frame_shapes(
    weights: np.ndarray, visemes: tuple[str, ...], claimed: np.ndarray, params: MotionParameters
) -> np.ndarray:
    """Lower every non-closure shape shown for a single frame below half weight: it blends, never flashes."""
    weights = weights.copy()
    labels = shown_shapes(weights)
    ceiling = params.blend_ceiling
    for label, start, length in shape_runs(labels):
        if length != 1 or visemes[label] in HARD_TARGETS or claimed[start]:
            continue
        weights[start] = _capped(weights[start], ceiling)
    return weights


def _capped(row: np.ndarray, ceiling: float) -> np.ndarray:
    """The row with no entry above the ceiling, the excess spread over the others in proportion."""
    row = row.copy()
    for _ in range(row.size):
        over = row > ceiling
        excess = float((row[over] - ceiling).sum())
        if excess <= 1e-15:
            break
        row[over] = ceiling
        room = np.where(row < ceiling, ceiling - row, 0.0)
        share = np.where(row < ceiling, row + 1e-6, 0.0)
        share = np.minimum(share / share.sum() * excess, room)
        row += share
    return row


# ---------------------------------------------------------------- emotions


def _smoothstep(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def _emotion_curves(
    timeline: Timeline, times: np.ndarray, strength: float, params: MotionParameters
) -> dict[str, np.ndarray]:
    """Per emotion, its weight over the frames: ramps centred on span edges, so neighbours cross-fade."""
    curves: dict[str, np.ndarray] = {}
    spans = sorted(timeline.emotions, key=lambda s: s.start)
    for index, span in enumerate(spans):
        start, end = span.start, span.end
        # Same emotion again shortly after: meet in the middle of the gap instead of dipping to nothing.
        following = next((s for s in spans[index + 1 :] if s.emotion == span.emotion), None)
        if following is not None and following.start - end < params.emotion_merge_gap:
            end = (end + following.start) / 2
        preceding = next((s for s in reversed(spans[:index]) if s.emotion == span.emotion), None)
        if preceding is not None and start - preceding.end < params.emotion_merge_gap:
            start = (start + preceding.end) / 2
        length = max(end - start, 1e-6)
        scale = min(1.0, length / (params.emotion_onset / 2 + params.emotion_offset / 2))
        onset, offset = params.emotion_onset * scale, params.emotion_offset * scale
        rising = _smoothstep((times - (start - onset / 2)) / onset)
        falling = 1.0 - _smoothstep((times - (end - offset / 2)) / offset)
        level = float(np.clip(span.weight * strength, 0.0, 1.0))
        curve = curves.setdefault(span.emotion, np.zeros_like(times))
        curve += level * np.minimum(rising, falling)
    return {emotion: np.clip(curve, 0.0, 1.0) for emotion, curve in curves.items()}


@MOTION_MODELS.register
class NaturalMotion(MotionModel):
    name = "natural"
    label = "Natural"
    description = "Co-articulation, hard lip closures and layered emotions"

    def weight_tracks(self, timeline: Timeline, fps: float, emotion_strength: float = 1.0) -> WeightTracks:
        return natural_weight_tracks(timeline, fps, emotion_strength)
