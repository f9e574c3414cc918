"""The living layers over either motion model: gaze, blinks, head motion, brows and the life of expressions.

`living_tracks(tracks, timeline, options, samples, sample_rate)` adds to the weight tracks of the natural
or the thesis model what makes a face alive rather than a mannequin's: eyes that hold the listener and
dart away (gaze.py), blinks where people blink (blinks.py), a head that moves with the voice's pitch and
loudness (head.py, measured from the audio by prosody.py), brows that rise on accents (brows.py) and
emotions that breathe at their apex (expression.py). The rotations go into `tracks.head_and_eyes`; the
lids, brows and the eyes of heads that turn them by keys are ordinary TR_* tracks. Every layer draws from
its own generator seeded by (seed, layer), so turning one off leaves the others as they were.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ...base.model import (
    BLINK_KEYS,
    BROW_RAISE_KEY,
    EMOTION_KEY_PREFIX,
    EMOTIONS,
    LOOK_KEY_DEGREES,
    LOOK_KEYS,
    HeadAndEyes,
    Timeline,
    Track,
    WeightTracks,
    emotion_key_name,
    emotion_release_key_name,
    look_key_name,
)
from ..frames import decimated_keys, sparse_track
from .blinks import blink_curve, blink_durations, place_blinks
from .brows import brow_curve
from .expression import emotion_life
from .gaze import GazePlan, GazeSetup, eye_angles, plan_gaze
from .head import head_angles
from .parameters import living_parameters
from .phrases import SpeechStructure, speech_structure
from .prosody import Prosody, measure_prosody

__all__ = ["GazeSetup", "LivingOptions", "living_tracks", "speech_structure"]
LOOK_TOLERANCE = 0.1 / LOOK_KEY_DEGREES
_LAYER_SEEDS = {"gaze": 1, "blinks": 2, "head": 3, "expression": 4, "nods": 5}


@dataclass(frozen=True)
class LivingOptions:
    """Which layers run and how strongly (1 is the model's; 0 turns a layer off), and their seed."""

    gaze: float = 1.0
    blinks: float = 1.0
    head: float = 1.0
    expression: float = 1.0
    seed: int = 0
    setup: GazeSetup = field(default_factory=GazeSetup)
    character: int = 0  # which character of a conversation (each draws its own); 0 for one head alone

    @property
    def any(self) -> bool:
        return max(self.gaze, self.blinks, self.head, self.expression) > 0

    def rng(self, layer: str) -> np.random.Generator:
        """The layer's own generator: turning one layer off leaves the others as they were."""
        seed = [self.seed, _LAYER_SEEDS[layer]] + ([self.character] if self.character else [])
        return np.random.default_rng(seed)


def living_tracks(
    tracks: WeightTracks,
    timeline: Timeline,
    options: LivingOptions,
    samples: np.ndarray | None = None,
    sample_rate: int = 0,
) -> WeightTracks:
    """The tracks with the living layers added (the emotions of the natural model given their life)."""
    if not options.any:
        return tracks
    settings = living_parameters()
    times = np.arange(tracks.frame_count) / tracks.fps
    structure = speech_structure(timeline, measured_prosody(samples, sample_rate))
    head = head_angles(structure, times, options.rng("head"), settings["head"], options.head)
    plan = plan_gaze(structure, times, options.rng("gaze"), settings["gaze"], options.gaze)
    left, right, _direction = eye_angles(plan, head, options.setup)
    return assembled_tracks(tracks, timeline, options, structure, structure, head, plan, left, right)


def measured_prosody(samples: np.ndarray | None, sample_rate: int) -> Prosody | None:
    return measure_prosody(samples, sample_rate) if samples is not None and len(samples) else None


def assembled_tracks(
    tracks: WeightTracks,
    timeline: Timeline,
    options: LivingOptions,
    structure: SpeechStructure,
    heard: SpeechStructure,
    head: np.ndarray,
    plan: GazePlan,
    left: np.ndarray,
    right: np.ndarray,
) -> WeightTracks:
    """The tracks with the layers' motion: the head's and eyes' rotations (and the look keys), blinks at
    the pauses and phrase ends of the speech heard (`heard`: the character's own, or a whole conversation's)
    and the gaze's saccades, brows and the life of emotions on the character's own speech (`structure`)."""
    settings = living_parameters()
    fps, frame_count = tracks.fps, tracks.frame_count
    times = np.arange(frame_count) / fps
    columns: dict[str, np.ndarray] = {}
    if options.gaze > 0 or options.head > 0:  # the eyes keep the target while the head moves
        for eye, angles in (("left", left), ("right", right)):
            columns.update(_look_columns(eye, angles))

    blink_spans: list[tuple[float, float]] = []
    if options.blinks > 0:
        curve, blink_spans = _blinks(tracks, timeline, options, heard, plan, settings["blinks"])
        for name in BLINK_KEYS:
            columns[name] = curve
    if options.expression > 0:
        brows = brow_curve(timeline.emphases, structure, times, settings["brows"], options.expression)
        if brows.any():
            columns[BROW_RAISE_KEY] = brows

    replaced = dict.fromkeys(columns)
    kept = [track for track in tracks.tracks if track.name not in replaced]
    if options.expression > 0 and tracks.mode == "natural":
        factor = emotion_life(
            structure, times, options.rng("expression"), settings["expression"], options.expression
        )
        kept = _with_life(kept, factor)
    key_frames = np.arange(frame_count, dtype=np.float64)
    added = tuple(_track(name, key_frames, values) for name, values in columns.items())
    extra = dict(tracks.extra)
    extra.update(
        blinks=tuple(blink_spans),
        saccades=tuple((s.start, s.duration, s.amplitude) for s in plan.saccades),
        pauses=structure.pauses,
    )
    return dataclasses.replace(
        tracks,
        tracks=(*kept, *added),
        extra=extra,
        head_and_eyes=HeadAndEyes(head=head, left_eye=left, right_eye=right)
        if options.gaze > 0 or options.head > 0
        else None,
    )


def _blinks(
    tracks: WeightTracks,
    timeline: Timeline,
    options: LivingOptions,
    heard: SpeechStructure,
    plan: GazePlan,
    settings: dict,
) -> tuple[np.ndarray, list[tuple[float, float]]]:
    """The lids' curve and the blinks it keeps (blink_curve), placed at the pauses and phrase ends of the
    speech heard and with the gaze's saccades."""
    rng = options.rng("blinks")
    starts = place_blinks(heard, plan.saccades, timeline.duration, rng, settings, options.blinks)
    planned = tuple(zip(starts, blink_durations(starts, rng, settings), strict=True))
    closure = _eye_closure(tracks, settings["eye_closure"])
    return blink_curve(planned, tracks.fps, tracks.frame_count, closure, settings)


def _track(name: str, frames: np.ndarray, values: np.ndarray) -> Track:
    """A look key keyed where its motion needs it (within LOOK_TOLERANCE, a tenth of a degree); the
    blinks and brows exactly (sparse_track)."""
    if name in LOOK_KEYS:
        keep = decimated_keys(values, LOOK_TOLERANCE)
        return Track(name=name, frames=frames[keep], values=values[keep])
    return sparse_track(name, frames, values)


def _look_columns(eye: str, angles: np.ndarray) -> dict[str, np.ndarray]:
    """The eye's four look keys from its yaw and pitch (weight 1 = LOOK_KEY_DEGREES)."""
    yaw, pitch = angles[:, 0] / LOOK_KEY_DEGREES, angles[:, 1] / LOOK_KEY_DEGREES
    return {
        look_key_name(eye, "left"): np.maximum(yaw, 0.0),
        look_key_name(eye, "right"): np.maximum(-yaw, 0.0),
        look_key_name(eye, "up"): np.maximum(pitch, 0.0),
        look_key_name(eye, "down"): np.maximum(-pitch, 0.0),
    }


def _eye_closure(tracks: WeightTracks, closure: dict[str, float]) -> np.ndarray:
    """How far the emotions on the face close the eyes at each frame."""
    frames = np.arange(tracks.frame_count, dtype=np.float64)
    total = np.zeros(tracks.frame_count)
    for emotion in EMOTIONS:
        track = tracks.track(emotion_key_name(emotion))
        if track is not None and closure.get(emotion, 0.0):
            total += closure[emotion] * np.interp(frames, track.frames, track.values)
    return total


def _with_life(tracks: list[Track], factor: np.ndarray) -> list[Track]:
    """Emotion tracks (and their mouth releases, by the same factor) multiplied by the life factor."""
    frames = np.arange(factor.size, dtype=np.float64)
    result = []
    for track in tracks:
        if track.name.startswith(EMOTION_KEY_PREFIX) and _is_emotion_or_release(track.name):
            values = np.interp(frames, track.frames, track.values) * factor
            result.append(sparse_track(track.name, frames, values))
        else:
            result.append(track)
    return result


def _is_emotion_or_release(name: str) -> bool:
    return any(name in (emotion_key_name(e), emotion_release_key_name(e)) for e in EMOTIONS)
