"""Where the eyes look while the character talks: eye contact, look-aways and the saccades between them.

Lee, Badler and Badler's "Eyes Alive" (2002), talking mode: spells of eye contact with the listener alternate
with look-aways in which the eyes rest on a few places in turn; saccade amplitudes fall off exponentially
(mostly under 15 degrees), mostly along the horizontal or vertical, and each saccade lasts as long as the
main sequence says (about 25 + 2.4 A ms) with a minimum-jerk profile. Speakers look away as a phrase begins
and back to the listener as it ends (Kendon 1967), so gaze shifts are drawn toward phrase boundaries; in a
long pause the eyes hold the listener. Both eyes fixate the same point, so they converge on a near target,
and they keep it while the head moves: the eye-in-head angles are what is left of the gaze after the head.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...base.rotations import angles_of, direction, head_matrices
from .easing import minimum_jerk
from .phrases import SpeechStructure


@dataclass(frozen=True)
class GazeSetup:
    """The target and the eyes, in the head's rest frame (x toward the character's left, y up, z forward)."""

    target_yaw: float = 0.0  # degrees from the head's rest facing, seen from between the eyes
    target_pitch: float = 0.0
    target_distance: float = 1.0  # metres from between the eyes
    eye_separation: float = 0.063  # metres between the eyes' centres
    eyes_above_pivot: float = 0.075  # metres from the head's pivot (the top of the neck) up to the eyes
    eyes_before_pivot: float = 0.085  # ... and forward
    counter_roll: float = 0.15  # share of the head's roll the eyes roll back (ocular counter-roll, 0.1-0.2)

    def eye_positions(self) -> np.ndarray:
        """(2, 3) left and right eye centres relative to the pivot."""
        half = self.eye_separation / 2
        return np.array(
            [
                [half, self.eyes_above_pivot, self.eyes_before_pivot],
                [-half, self.eyes_above_pivot, self.eyes_before_pivot],
            ]
        )

    def target_point(self) -> np.ndarray:
        middle = self.eye_positions().mean(axis=0)
        return middle + self.target_distance * direction(self.target_yaw, self.target_pitch)


@dataclass(frozen=True)
class Saccade:
    start: float  # seconds
    duration: float  # seconds
    amplitude: float  # degrees
    to_contact: bool  # ends on the target


@dataclass(frozen=True, eq=False)
class GazePlan:
    offsets: np.ndarray  # (frames, 2) yaw, pitch of the fixation relative to the target's direction
    saccades: tuple[Saccade, ...]


def plan_gaze(
    structure: SpeechStructure, times: np.ndarray, rng: np.random.Generator, settings: dict, amount: float
) -> GazePlan:
    """Fixations and saccades over the frame times (deterministic for the generator's seed)."""
    duration = float(times[-1]) if times.size else 0.0
    return gaze_plan(talking_fixations(structure, 0.0, duration, rng, settings, amount), times, settings)


def gaze_plan(fixations: list[tuple[float, np.ndarray]], times: np.ndarray, settings: dict) -> GazePlan:
    """The eyes' way over the frame times through the given shifts (time a saccade starts, where it lands
    relative to the target), in order; a shift starting before the last one has landed is dropped."""
    kept: list[tuple[float, np.ndarray]] = []
    for when, where in sorted(fixations, key=lambda shift: shift[0]):
        if kept and when - kept[-1][0] < 0.15:
            continue
        kept.append((when, where))
    fixations = kept
    # Each shift's saccade starts at its time from where the last one landed and lasts as the main sequence
    # says; a frame is on the way of the last shift begun by then (or at rest on the target before any).
    starts = np.array([start for start, _ in fixations])
    targets = np.array([target for _, target in fixations]).reshape(-1, 2)
    sources = np.vstack([np.zeros((1, 2)), targets])[:-1]  # each shift starts where the last one landed
    amplitudes = np.hypot(*(targets - sources).T)
    lengths = saccade_seconds(amplitudes, settings)
    current = np.searchsorted(starts, times, side="right") - 1
    offsets = np.zeros((times.size, 2))
    moving = current >= 0
    shift = current[moving]
    share = minimum_jerk((times[moving] - starts[shift]) / lengths[shift])
    offsets[moving] = sources[shift] + (targets[shift] - sources[shift]) * share[:, None]
    saccades = tuple(
        Saccade(start, length, amplitude, to_contact)
        for start, length, amplitude, to_contact in zip(
            starts.tolist(),
            lengths.tolist(),
            amplitudes.tolist(),
            (~targets.any(axis=1)).tolist(),
            strict=True,
        )
        if amplitude >= 1e-6
    )
    return GazePlan(offsets=offsets, saccades=saccades)


def saccade_seconds(amplitudes, settings: dict):
    """How long saccades of these amplitudes (degrees) last: the main sequence."""
    return (settings["duration_base"] + settings["duration_slope"] * np.asarray(amplitudes)) / 1000.0


def talking_fixations(
    structure, start: float, duration: float, rng, settings: dict, amount: float
) -> list[tuple[float, np.ndarray]]:
    """(time the saccade starts, where it lands relative to the target) for every gaze shift of a speaker
    from start until duration seconds, starting on the target."""
    if amount <= 0 or duration <= start:
        return []
    phrase_starts = np.array([start for start, _ in structure.phrases])
    phrase_ends = np.array([end for _, end in structure.phrases])
    listening = [(s, e) for s, e in structure.pauses if e - s >= settings["listening_pause"]]
    shifts: list[tuple[float, np.ndarray]] = []
    time = start + gamma(rng, settings["contact_mean"] / 2, settings["contact_shape"])
    position = np.zeros(2)
    while time < duration:
        time = _pulled(time, phrase_starts, rng, settings)
        time = _after_listening(time, listening)
        if time >= duration:
            break
        # Look away: a few places in turn, then back to the listener.
        visits = rng.geometric(1.0 / max(settings["away_fixations_mean"], 1.0))
        for _ in range(int(visits)):
            position = next_place(position, rng, settings, amount)
            shifts.append((time, position))
            time += gamma(rng, settings["away_fixation_mean"], settings["away_fixation_shape"])
        time = _pulled(time, phrase_ends, rng, settings)
        pause = next(((s, e) for s, e in listening if s - 0.3 <= time <= e), None)
        if pause is not None:
            time = min(time, pause[0])  # back on the listener as the long pause begins
        if time >= duration:
            break
        position = np.zeros(2)
        shifts.append((time, position))
        time += gamma(rng, settings["contact_mean"], settings["contact_shape"])
    return _thinking(shifts, structure.hesitations, start, duration, rng, settings, amount)


def _thinking(
    shifts: list[tuple[float, np.ndarray]],
    hesitations: tuple[tuple[float, float], ...],
    start: float,
    duration: float,
    rng,
    settings: dict,
    amount: float,
) -> list[tuple[float, np.ndarray]]:
    """The shifts with a look away, up and to a side, through each hesitation said aloud (the speaker
    searching for the next word), and back to the listener as the word comes; the shifts it covers left
    out."""
    for begin, end in hesitations:
        leave = begin + settings["thinking_lead"]
        if not start <= leave < end <= duration:
            continue
        side = 1.0 if rng.random() < 0.5 else -1.0
        place = amount * np.array([side * settings["thinking_yaw"], settings["thinking_pitch"]])
        shifts = [shift for shift in shifts if not leave - 0.15 < shift[0] < end + 0.15]
        shifts += [(leave, place), (end, np.zeros(2))]
    return sorted(shifts, key=lambda shift: shift[0])


def gamma(rng, mean: float, shape: float) -> float:
    return float(rng.gamma(shape, mean / shape))


def _pulled(time: float, boundaries: np.ndarray, rng, settings: dict) -> float:
    """The time moved to the nearest phrase boundary within reach, as often as the settings say."""
    if boundaries.size == 0:
        return time
    nearest = boundaries[np.argmin(np.abs(boundaries - time))]
    if abs(nearest - time) <= settings["phrase_pull"] and rng.random() < settings["phrase_pull_share"]:
        return float(nearest)
    return time


def _after_listening(time: float, listening: list[tuple[float, float]]) -> float:
    for start, end in listening:
        if start <= time < end:
            return end
    return time


def next_place(position: np.ndarray, rng, settings: dict, amount: float) -> np.ndarray:
    """A saccade of an exponentially distributed amplitude, mostly along an axis, kept near the target."""
    low, high = settings["amplitude_min"], settings["amplitude_max"]
    for _ in range(12):
        amplitude = amount * min(max(float(rng.exponential(settings["amplitude_scale"])), low), high)
        if rng.random() < settings["cardinal_share"]:
            angle = rng.integers(4) * np.pi / 2
        else:
            angle = np.pi / 4 + rng.integers(4) * np.pi / 2
        place = position + amplitude * np.array([math.cos(angle), math.sin(angle)])
        vertical_limit = settings["up_limit"] if place[1] > 0 else settings["down_limit"]
        inside = (
            abs(place[0]) <= settings["horizontal_limit"] * amount
            and abs(place[1]) <= vertical_limit * amount
        )
        if inside and math.hypot(*place) >= 0.5 * low * amount:
            return place
    return position * 0.5


def eye_angles(
    plan: GazePlan, head: np.ndarray, setup: GazeSetup
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(left, right eye yaw/pitch relative to the head, gaze direction in the rest frame) per frame, the
    target where the set-up puts it (eye_angles_toward)."""
    count = len(plan.offsets)
    return eye_angles_toward(
        plan.offsets,
        head,
        setup,
        np.full(count, setup.target_yaw),
        np.full(count, setup.target_pitch),
        np.full(count, setup.target_distance),
    )


def eye_angles_toward(
    offsets: np.ndarray,
    head: np.ndarray,
    setup: GazeSetup,
    target_yaw: np.ndarray,
    target_pitch: np.ndarray,
    target_distance: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(left, right eye yaw/pitch relative to the head, gaze direction in the rest frame) per frame.

    Each eye turns toward the fixation point: the target of the frame (its direction from between the eyes,
    in degrees, and distance), or the point a look-away's angles (offsets) from it at the target's
    distance. The head's rotation about its pivot moves the eyes too; what is left is the eyes'.
    """
    eyes = setup.eye_positions()
    middle = eyes.mean(axis=0)
    fixation_direction = direction(target_yaw + offsets[:, 0], target_pitch + offsets[:, 1])
    fixation = middle + np.asarray(target_distance)[:, None] * fixation_direction
    rotations = head_matrices(head)
    # The eyes roll a little against the head's tilt (ocular counter-roll).
    roll = -setup.counter_roll * head[:, 2:3]
    result = []
    for eye in eyes:
        placed = rotations @ eye
        looking = fixation - placed
        in_head = np.einsum("nji,nj->ni", rotations, looking)
        result.append(np.hstack([angles_of(in_head), roll]))
    return result[0], result[1], fixation_direction
