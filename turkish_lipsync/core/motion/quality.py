"""The quality report: numbers that say whether lip motion is in sync, closes the lips, and is smooth.

Every measure works on the weights as Blender will show them: the tracks sampled at integer frames.

- onset_error_ms_max: for each phone whose viseme differs from the previous phone's, the moment its viseme
  rises through half of the peak it reaches at that phone (the shape becomes the more visible one), against
  the engine's onset of that phone (Timeline.engine_onsets) or, without an engine, the phone's start.
  Negative errors mean the lips lead the sound, which viewers tolerate far better than lag; the report also
  gives the mean and the latest (most positive) error.
- bilabial_closure_share: share of m, b, p phones whose own viseme reaches full weight (>= 0.99) on a frame
  within one frame of the phone; labiodental_contact_share likewise for f, v.
- min_hold_frames: a frame "shows" a shape when one viseme carries at least half of the viseme weight there;
  the shortest run of frames showing the same shape, closures excepted (they may be a single frame).
- changes_per_second: how often the shown shape changes.
- max_frame_jump: the largest change of one viseme or emotion weight from one frame to the next (blinks and
  brows, which are meant to be quick, are left out).
- max_weight_sum: the largest sum of the viseme weights (neutral included) on any frame.
- vowel_peak_mean: the mean peak weight of the vowels' visemes (a smooth but lazy mouth scores low here).
"""

from __future__ import annotations

import math

import numpy as np

from ..base.model import (
    BLINK_KEYS,
    BROW_RAISE_KEY,
    EMOTION_KEY_PREFIX,
    VISEME_KEY_PREFIX,
    Timeline,
    WeightTracks,
)
from ..base.visemes import BILABIAL_VISEMES, LABIODENTAL_VISEMES
from ..text.syllables import VOWELS
from . import weight_tracks
from .frames import sampled_weights, shape_runs, shown_shapes

CLOSURE_WEIGHT = 0.99
HARD_TARGETS = BILABIAL_VISEMES | LABIODENTAL_VISEMES
REPORT_KEYS = (
    "onset_error_ms_max",
    "bilabial_closure_share",
    "min_hold_frames",
    "changes_per_second",
    "max_frame_jump",
    "max_weight_sum",
)


def quality_report(timeline: Timeline, tracks: WeightTracks) -> dict:
    """The measures of the module docstring for one set of tracks (JSON-ready: plain floats, ints, None)."""
    fps = tracks.fps
    names, values = sampled_weights(tracks)
    viseme_columns = [i for i, n in enumerate(names) if n.startswith(VISEME_KEY_PREFIX)]
    visemes = tuple(names[i][len(VISEME_KEY_PREFIX) :] for i in viseme_columns)
    weights = values[:, viseme_columns]
    column = {v: i for i, v in enumerate(visemes)}

    onset_errors = _onset_errors(timeline, weights, column, fps)
    labels = shown_shapes(weights)
    runs = shape_runs(labels)
    holds = [length for label, _, length in runs if visemes[label] not in HARD_TARGETS]
    changes = sum(1 for a, b in zip(runs, runs[1:], strict=False) if a[0] != b[0])
    smooth_columns = [
        i
        for i, n in enumerate(names)
        if (n.startswith(VISEME_KEY_PREFIX) or n.startswith(EMOTION_KEY_PREFIX))
        and n not in BLINK_KEYS
        and n != BROW_RAISE_KEY
    ]
    jumps = np.abs(np.diff(values[:, smooth_columns], axis=0))
    seconds = max(tracks.frame_count / fps, 1e-9)
    return {
        "mode": tracks.mode,
        "fps": fps,
        "frames": tracks.frame_count,
        "onset_reference": "engine" if timeline.engine_onsets else "timeline",
        "onset_error_ms_max": _rounded(max((abs(e) for e in onset_errors), default=None), 1000),
        "onset_error_ms_mean": _rounded(float(np.mean(onset_errors)) if onset_errors else None, 1000),
        "onset_latest_ms": _rounded(max(onset_errors, default=None), 1000),
        "bilabial_closure_share": _closure_share(timeline, weights, column, fps, BILABIAL_VISEMES),
        "labiodental_contact_share": _closure_share(timeline, weights, column, fps, LABIODENTAL_VISEMES),
        "vowel_peak_mean": _vowel_peak_mean(timeline, weights, column, fps),
        "min_hold_frames": min(holds, default=None),
        "changes_per_second": round(changes / seconds, 3),
        "max_frame_jump": round(float(jumps.max(initial=0.0)), 4),
        "max_weight_sum": round(float(weights.sum(axis=1).max(initial=0.0)), 6),
    }


def _rounded(value: float | None, scale: float) -> float | None:
    return None if value is None else round(value * scale, 1)


def _reference_onsets(timeline: Timeline) -> list[float]:
    """Per phone, its onset in the sound: the engine's (paired in order, or the nearest), else its start."""
    starts = [p.start for p in timeline.phones]
    engine = sorted(timeline.engine_onsets)
    if not engine:
        return starts
    if len(engine) == len(starts):
        return engine
    engine_array = np.asarray(engine)
    return [float(engine_array[np.abs(engine_array - s).argmin()]) for s in starts]


def _onset_errors(timeline: Timeline, weights: np.ndarray, column: dict[str, int], fps: float) -> list[float]:
    """Seconds from each phone's reference onset to its viseme's half-rise (see the module docstring)."""
    errors = []
    frame_count = weights.shape[0]
    phones = timeline.phones
    for index, (phone, reference) in enumerate(zip(phones, _reference_onsets(timeline), strict=True)):
        previous = phones[index - 1] if index else None
        if (previous is not None and previous.viseme == phone.viseme) or phone.viseme not in column:
            continue  # the same shape continues: no onset of its own
        curve = weights[:, column[phone.viseme]]
        first = max(0, math.floor(phone.start * fps))
        last = min(frame_count - 1, math.ceil(phone.end * fps))
        if last < first:
            continue
        peak_frame = first + int(curve[first : last + 1].argmax())
        half = curve[peak_frame] / 2
        if curve[peak_frame] <= 0.05:
            continue  # the phone left no visible trace of its own
        floor_frame = max(0, math.floor(previous.start * fps)) if previous else 0
        frame = peak_frame
        while frame > floor_frame and curve[frame - 1] >= half:
            frame -= 1
        if frame == 0:
            onset = 0.0
        elif curve[frame - 1] >= half or frame == floor_frame:
            continue  # the shape was already up when the previous phone began: no onset of its own
        else:
            below, above = curve[frame - 1], curve[frame]
            onset = (frame - 1 + (half - below) / (above - below)) / fps
        errors.append(onset - reference)
    return errors


def _closure_share(
    timeline: Timeline, weights: np.ndarray, column: dict[str, int], fps: float, visemes: frozenset[str]
) -> float | None:
    """Share of the phones with these visemes whose viseme reaches full weight within a frame of the phone."""
    targets = [p for p in timeline.phones if p.viseme in visemes]
    if not targets:
        return None
    frame_count = weights.shape[0]
    reached = 0
    for phone in targets:
        if phone.viseme not in column:
            continue
        first = max(0, math.ceil(phone.start * fps - 1))
        last = min(frame_count - 1, math.floor(phone.end * fps + 1))
        if last >= first and weights[first : last + 1, column[phone.viseme]].max() >= CLOSURE_WEIGHT:
            reached += 1
    return round(reached / len(targets), 4)


def _vowel_peak_mean(
    timeline: Timeline, weights: np.ndarray, column: dict[str, int], fps: float
) -> float | None:
    """Mean over the vowels of the peak weight their viseme reaches within a frame of them.

    Smoothness is cheap if the mouth stops moving; this says how much of each vowel is still seen.
    """
    peaks = []
    for phone in timeline.phones:
        if phone.letter not in VOWELS or phone.viseme not in column:
            continue
        first = max(0, math.ceil(phone.start * fps - 1))
        last = min(weights.shape[0] - 1, math.floor(phone.end * fps + 1))
        if last >= first:
            peaks.append(float(weights[first : last + 1, column[phone.viseme]].max()))
    return round(float(np.mean(peaks)), 3) if peaks else None


def compare_modes(timeline: Timeline, fps: float, emotion_strength: float = 1.0) -> dict:
    """{"thesis": report, "default": report} for the same timeline."""

    return {
        "thesis": quality_report(timeline, weight_tracks(timeline, fps, "thesis", emotion_strength)),
        "default": quality_report(timeline, weight_tracks(timeline, fps, "natural", emotion_strength)),
    }


_LABELS = (
    ("onset_error_ms_max", "largest onset error (ms)"),
    ("onset_error_ms_mean", "mean onset error (ms, < 0: lips lead)"),
    ("bilabial_closure_share", "m b p reaching closure"),
    ("labiodental_contact_share", "f v reaching contact"),
    ("vowel_peak_mean", "mean peak weight of the vowels"),
    ("min_hold_frames", "shortest hold (frames, closures aside)"),
    ("changes_per_second", "shape changes per second"),
    ("max_frame_jump", "largest frame-to-frame jump"),
    ("max_weight_sum", "largest viseme weight sum"),
)


def format_quality(report: dict) -> str:
    """A two-column table of the reports of compare_modes, one measure a line."""
    modes = list(report)
    any_report = report[modes[0]]
    header = f"{timeline_header(any_report)}\n{'measure':40}" + "".join(f"{mode:>12}" for mode in modes)
    lines = [header]
    for key, label in _LABELS:
        cells = "".join(f"{_cell(report[mode].get(key)):>12}" for mode in modes)
        lines.append(f"{label:40}{cells}")
    return "\n".join(lines)


def timeline_header(single: dict) -> str:
    return (
        f"# {single['frames']} frames at {single['fps']:g} fps; onsets measured against the "
        f"{'engine' if single['onset_reference'] == 'engine' else 'timeline'}"
    )


def _cell(value) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)
