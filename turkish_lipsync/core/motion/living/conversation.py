"""The living layers of a character in a conversation: speaking to someone, and listening to the others.

One head alone talks to the camera (living_tracks). In a conversation each character attends to someone
at every moment: while it speaks, the addressee of its line; while another speaks, that speaker (from a
moment before the line starts: listeners look to the next speaker as the turn ends); between turns, who
spoke last. Where it attends, its eyes go (a saccade as the main sequence says) and its head turns part of
the way (head and eyes share a large gaze shift). On top of that:

- speaking, the talking mode of gaze.py (look-aways drawn to phrase starts, back at phrase ends), and a long
  turn starts with a look-away and ends on the addressee (Kendon 1967);
- listening, Eyes Alive's listening mode: long spells on the speaker's face, short look-aways (about 75 %
  mutual gaze), a slow sway, and back-channel nods at the speaker's phrase ends, more where the speaker's
  pitch ends low or falling, a few at low-pitch stretches inside a phrase (Ward & Tsukahara 2000);
- blinks at the pauses and phrase ends of the whole conversation (listeners blink at a speaker's pauses
  too) and with large gaze shifts.

The mouth is not touched here: a character's weight tracks hold only its own lines (core/scene/), so it is
at rest while the others speak.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ...base.model import Timeline, WeightTracks
from ...base.rotations import angles_of
from . import assembled_tracks, measured_prosody
from .easing import minimum_jerk, smoothstep
from .gaze import (
    GazePlan,
    Saccade,
    eye_angles_toward,
    gamma,
    gaze_plan,
    next_place,
    saccade_seconds,
    talking_fixations,
)
from .head import head_angles, sway_motion
from .parameters import living_parameters
from .phrases import SpeechStructure, speech_structure

SPEAKING, LISTENING = "speaking", "listening"


@dataclass(frozen=True)
class Turn:
    """A line on the conversation's timeline: who says it to whom, from its first phone to its last."""

    speaker: str
    addressee: str  # another speaker, or the camera's key
    start: float
    end: float


@dataclass(frozen=True)
class Attention:
    """Whom a character attends to from start to end, and why."""

    start: float
    end: float
    mode: str  # SPEAKING (to the target) or LISTENING (to the target)
    target: str
    listening_to_speech: bool  # the target is speaking now (nods belong here), not just spoke last


@dataclass(frozen=True, eq=False)
class Surroundings:
    """Where a character's targets are: each point in its head's rest frame (x its left, y up, z forward),
    relative to the pivot the head turns about, as GazeSetup's eye positions are: (3,) where it stays, or
    (frames, 3) where it moves (another character's face as its head turns)."""

    points: dict[str, np.ndarray]


def attention_spans(
    who: str, turns: tuple[Turn, ...], duration: float, anticipation: float
) -> list[Attention]:
    """Whom `who` attends to over the conversation, as consecutive spans covering 0..duration."""
    ordered = sorted(turns, key=lambda turn: turn.start)
    own = [turn for turn in ordered if turn.speaker == who]
    edges = sorted(
        {0.0, duration}
        | {max(0.0, t.start - anticipation) for t in ordered}
        | {t.start for t in own}
        | {t.end for t in own}
    )
    spans: list[Attention] = []
    for start, end in zip(edges[:-1], edges[1:], strict=True):
        if end - start <= 1e-9:
            continue
        middle = (start + end) / 2
        speaking = next((t for t in own if t.start - 1e-9 <= middle <= t.end + 1e-9), None)
        if speaking is not None:
            attention = Attention(start, end, SPEAKING, speaking.addressee, False)
        else:
            floor = [t for t in ordered if t.start - anticipation <= middle]
            current = floor[-1] if floor else (ordered[0] if ordered else None)
            if current is None:
                continue
            if current.speaker != who:
                attention = Attention(
                    start, end, LISTENING, current.speaker, current.end >= middle or not floor
                )
            else:  # after its own line: on whom it spoke to, who is expected to answer
                attention = Attention(start, end, LISTENING, current.addressee, False)
        previous = spans[-1] if spans else None
        if previous is not None and _what(previous) == _what(attention):
            spans[-1] = Attention(previous.start, end, *_what(previous))
        else:
            spans.append(attention)
    return spans


def _what(attention: Attention) -> tuple[str, str, bool]:
    return attention.mode, attention.target, attention.listening_to_speech


def conversation_living_tracks(
    tracks: WeightTracks,
    timeline: Timeline,
    options,
    who: str,
    turns: tuple[Turn, ...],
    surroundings: Surroundings,
    own_voice: tuple[np.ndarray, int] | None,
    heard_voice: tuple[np.ndarray, int] | None,
    scene_timeline: Timeline,
) -> WeightTracks:
    """A character's tracks with its living layers in the conversation.

    timeline: the character's own lines on the conversation's timeline; own_voice: its voice alone there
    (samples, rate), heard_voice: everyone's (None without audio); scene_timeline: every line's phones, for
    the pauses of the conversation where there is no audio. options: LivingOptions (its setup's eyes).
    """
    if not options.any:
        return tracks
    settings = living_parameters()
    times = np.arange(tracks.frame_count) / tracks.fps
    duration = float(times[-1]) if times.size else 0.0
    own = speech_structure(timeline, measured_prosody(*own_voice) if own_voice else None)
    heard = speech_structure(scene_timeline, measured_prosody(*heard_voice) if heard_voice else None)
    listening, addressing = settings["listening"], settings["addressing"]
    spans = attention_spans(who, turns, duration, listening["anticipation"])

    directions = _span_directions(spans, surroundings, options)
    target_yaw, target_pitch, distance, switches = _target_directions(
        spans, directions, surroundings, options, times, settings
    )
    shifts = _conversation_fixations(spans, own, options.rng("gaze"), settings, options.gaze)
    plan = gaze_plan(shifts, times, settings["gaze"]) if times.size else GazePlan(np.zeros((0, 2)), ())
    plan = GazePlan(plan.offsets, tuple(sorted((*plan.saccades, *switches), key=lambda s: s.start)))

    head_rng = options.rng("head")
    head = head_angles(own, times, head_rng, settings["head"], options.head)
    if options.head > 0:
        listening_share = _listening_share(spans, times)
        head += options.head * sway_motion(times, head_rng, listening["sway"]) * listening_share[:, None]
        head[:, 1] += options.head * back_channel_nods(spans, heard, times, options.rng("nods"), listening)
        head[:, :2] += options.head * _orientation(spans, directions, times, addressing)
    left, right, _direction = eye_angles_toward(
        plan.offsets, head, options.setup, target_yaw, target_pitch, distance
    )
    result = assembled_tracks(tracks, timeline, options, own, heard, head, plan, left, right)
    extra = dict(result.extra)
    extra["attention"] = tuple((a.start, a.end, a.mode, a.target) for a in spans)
    return dataclasses.replace(result, extra=extra)


# ---------------------------------------------------------------- where the eyes go


def _span_directions(spans, surroundings: Surroundings, options) -> list[np.ndarray | None]:
    """(yaw, pitch, distance) of each span's target from between the eyes, where it mostly is (None: a
    target not in the scene, where the eyes keep the last one): what the head turns toward."""
    middle = options.setup.eye_positions().mean(axis=0)
    directions = []
    for attention in spans:
        point = surroundings.points.get(attention.target)
        if point is None:
            directions.append(directions[-1] if directions else None)
            continue
        seen = np.asarray(point, np.float64).reshape(-1, 3).mean(axis=0) - middle
        directions.append(np.array([*angles_of(seen[None])[0], max(float(np.linalg.norm(seen)), 0.05)]))
    return directions


def _target_directions(spans, directions, surroundings: Surroundings, options, times: np.ndarray, settings):
    """(yaw, pitch, distance) of the attended target at every frame (a face that moves is followed), moving
    from one target to the next as a saccade does; and those moves as saccades (for the blinks they
    carry)."""
    middle = options.setup.eye_positions().mean(axis=0)
    known = [d for d in directions if d is not None]
    values = np.tile(known[0] if known else np.array([0.0, 0.0, 1.0]), (times.size, 1))
    switches = []
    previous = None
    for attention, here in zip(spans, directions, strict=True):
        if here is None:
            continue
        after = times >= attention.start
        # Where the target is at each frame from the span's start on (later spans overwrite their frames).
        point = np.asarray(surroundings.points[attention.target], np.float64)
        seen = (point[after] if point.ndim == 2 else np.broadcast_to(point, (after.sum(), 3))) - middle
        target = np.column_stack([angles_of(seen), np.maximum(np.linalg.norm(seen, axis=1), 0.05)])
        if previous is None:
            values[after] = target
            values[~after] = target[0] if len(target) else here
        else:
            start_value = values[after][0] if after.any() else previous
            amplitude = float(np.hypot(*(here[:2] - previous[:2])))
            length = max(float(saccade_seconds(amplitude, settings["gaze"])), 1e-3)
            if amplitude > 1e-6:
                switches.append(Saccade(attention.start, length, amplitude, True))
            share = minimum_jerk((times[after] - attention.start) / length)[:, None]
            values[after] = start_value + (target - start_value) * share
        previous = here
    return values[:, 0], values[:, 1], values[:, 2], tuple(switches)


def _conversation_fixations(spans, own: SpeechStructure, rng, settings: dict, amount: float):
    """The look-aways from the attended target: a speaker's (Kendon's turn rule on top) while speaking, a
    listener's while listening; every span starts and ends on its target."""
    shifts: list[tuple[float, np.ndarray]] = []
    if amount <= 0:
        return shifts
    gaze, listening, addressing = settings["gaze"], settings["listening"], settings["addressing"]
    away = addressing["away_min"]
    talking = dict(
        gaze, contact_mean=addressing["contact_mean"], away_fixations_mean=addressing["away_fixations_mean"]
    )
    for attention in spans:
        start, end = attention.start, attention.end
        if attention.mode == SPEAKING:
            found = talking_fixations(own, start, end, rng, talking, amount)
            found = _off_the_face(found, rng, gaze, away, amount)
            if end - start >= addressing["long_turn"]:
                found = _kendon(found, start, end, rng, addressing, gaze, amount)
        else:
            found = _listening_fixations(start, end, rng, gaze, listening, away, amount)
        found = [(when, where) for when, where in found if start <= when < end]
        if found and found[-1][1].any():
            found.append((end, np.zeros(2)))  # back on the target as the span ends
        if shifts and shifts[-1][1].any() and not (found and found[0][0] <= start + 1e-9):
            shifts.append((start, np.zeros(2)))
        shifts.extend(found)
    return shifts


def away_place(position: np.ndarray, rng, gaze: dict, amount: float, away: float) -> np.ndarray:
    """A look-away's next place (gaze.next_place) at least `away` degrees from the face looked away from:
    in a conversation a look-away leaves the other's face (a glance within it is still mutual gaze)."""
    place = next_place(position, rng, gaze, amount)
    for _ in range(8):
        if np.hypot(*place) >= away:
            return place
        place = next_place(position, rng, gaze, amount)
    length = float(np.hypot(*place))
    return place * (away / length) if length > 1e-9 else np.array([away, 0.0])


def _off_the_face(shifts, rng, gaze: dict, away: float, amount: float):
    """A speaker's look-aways moved off the addressee's face where they land on it."""
    moved, position = [], np.zeros(2)
    for when, where in shifts:
        if where.any() and np.hypot(*where) < away * min(amount, 1.0):
            where = away_place(position, rng, gaze, amount, away * min(amount, 1.0))
        moved.append((when, where))
        position = where
    return moved


def _kendon(found, start: float, end: float, rng, addressing: dict, gaze: dict, amount: float):
    """A long turn looks away as it starts and is back on the addressee for its last seconds."""
    first_away = start + float(rng.uniform(0.0, addressing["turn_start_away"]))
    last_contact = end - addressing["turn_end_contact"]
    kept = [(when, where) for when, where in found if first_away + 0.3 < when < last_contact]
    opening = away_place(np.zeros(2), rng, gaze, amount, addressing["away_min"])
    shifts = [(first_away, opening), *kept]
    if shifts[-1][1].any():
        shifts.append((max(last_contact, shifts[-1][0] + 0.3), np.zeros(2)))
    return shifts


def _listening_fixations(
    start: float, end: float, rng, gaze: dict, listening: dict, away: float, amount: float
):
    """Long spells on the speaker's face, each ended by a short look-away of one place or a few."""
    shifts = []
    time = start + gamma(rng, listening["contact_mean"] / 2, listening["contact_shape"])
    smaller = amount * listening["amplitude_share"]
    while time < end - 0.5:
        position = np.zeros(2)
        for _ in range(int(rng.geometric(1.0 / max(listening["away_fixations_mean"], 1.0)))):
            position = away_place(position, rng, gaze, smaller, away * min(amount, 1.0))
            shifts.append((time, position))
            time += max(gamma(rng, listening["away_fixation_mean"], gaze["away_fixation_shape"]), 0.2)
        if time >= end:
            break
        shifts.append((time, np.zeros(2)))
        time += gamma(rng, listening["contact_mean"], listening["contact_shape"])
    return shifts


# ---------------------------------------------------------------- the head


def _orientation(spans, directions, times: np.ndarray, addressing: dict) -> np.ndarray:
    """(frames, 2) yaw and pitch the head takes toward the attended target: a share of the target's
    direction, reached over head_ease seconds from a little after the eyes set off (the head follows)."""
    shares = np.array([addressing["head_yaw_share"], addressing["head_pitch_share"]])
    limit = addressing["head_turn_limit"]
    result = np.zeros((times.size, 2))
    current = None
    for attention, here in zip(spans, directions, strict=True):
        if here is None:
            continue
        goal = np.clip(shares * here[:2], -limit, limit)
        if current is None:
            result[:] = goal
        else:
            begin = attention.start + addressing["head_lag"]
            after = times >= begin
            share = smoothstep((times[after] - begin) / max(addressing["head_ease"], 1e-3))[:, None]
            result[after] = current + (goal - current) * share
        current = goal
    return result


def _listening_share(spans, times: np.ndarray) -> np.ndarray:
    share = np.zeros(times.size)
    for attention in spans:
        if attention.mode == LISTENING:
            share[(times >= attention.start) & (times <= attention.end)] = 1.0
    fps = 1.0 / (times[1] - times[0]) if times.size > 1 else 25.0
    width = max(int(0.4 * fps), 1)
    return np.convolve(np.pad(share, width, mode="edge"), np.ones(2 * width + 1) / (2 * width + 1), "valid")


def back_channel_nods(
    spans, heard: SpeechStructure, times: np.ndarray, rng: np.random.Generator, listening: dict
) -> np.ndarray:
    """Head pitch (degrees, down negative) of a listener's nods: at the speaker's phrase ends, most often
    where the pitch ends low or falls, and at low-pitch stretches inside phrases; a nod never runs into the
    listener's own line and never comes within nod_min_gap of the last."""
    pitch = np.zeros(times.size)
    heard_spans = [(a.start, a.end) for a in spans if a.mode == LISTENING and a.listening_to_speech]
    speaking = [(a.start, a.end) for a in spans if a.mode == SPEAKING]
    if not heard_spans or times.size == 0:
        return pitch
    candidates = sorted(_nod_cues(heard, listening))
    width = listening["nod_width"]
    last = -np.inf
    for time, chance in candidates:
        onset = time + listening["nod_delay"] + float(rng.uniform(-0.05, 0.05))
        double = rng.random() < listening["double_nod_share"]
        length = width * (1.8 if double else 1.0)
        draw = rng.random()
        if onset - last < listening["nod_min_gap"] or draw >= chance:
            continue
        if not any(start <= onset and onset + length <= end + 0.3 for start, end in heard_spans):
            continue
        if any(start < onset + length + 0.2 and onset < end for start, end in speaking):
            continue
        depth = listening["nod"] * (1.0 + listening["nod_spread"] * float(rng.uniform(-1, 1)))
        local = (times - onset) / width
        dip = np.where((local >= 0) & (local <= 1), 0.5 - 0.5 * np.cos(2 * np.pi * local), 0.0)
        if double:
            second = local - 0.8
            dip += 0.6 * np.where((second >= 0) & (second <= 1), 0.5 - 0.5 * np.cos(2 * np.pi * second), 0.0)
        pitch -= depth * dip
        last = onset
    return pitch


def _nod_cues(heard: SpeechStructure, listening: dict) -> list[tuple[float, float]]:
    """(time, chance of a nod) of every back-channel cue of the speech heard: each phrase end (a better
    chance where its pitch ends low or falls) and each low-pitch stretch inside a phrase."""
    cues = []
    prosody = heard.prosody
    semitones = prosody.semitones() if prosody is not None else None
    voiced = semitones[np.isfinite(semitones)] if semitones is not None else np.zeros(0)
    low = float(np.quantile(voiced, listening["low_pitch_share"])) if voiced.size > 10 else None
    for start, end in heard.phrases:
        # Without the pitch (table timing has no audio) every phrase end is as likely as an average one.
        chance = listening["nod_chance_level"]
        if low is None:
            chance = (listening["nod_chance_low"] + listening["nod_chance_level"]) / 2
        else:
            first, last = int(max(end - 0.3, start) * prosody.rate), int(np.ceil(end * prosody.rate))
            tail = semitones[first:last]
            tail = tail[np.isfinite(tail)]
            middle = semitones[int(start * prosody.rate) : last]
            middle = middle[np.isfinite(middle)]
            falling = (
                tail.size >= 2 and middle.size and float(np.median(tail)) < float(np.median(middle)) - 1.0
            )
            if tail.size and (float(np.median(tail)) <= low or falling):
                chance = listening["nod_chance_low"]
            cues += _low_stretches(semitones, prosody.rate, start, end, low, listening)
        cues.append((end, chance))
    return cues


def _low_stretches(semitones, rate: float, start: float, end: float, low: float, listening: dict):
    """Ward & Tsukahara's cue inside a phrase: pitch in the speaker's lowest share for low_pitch_length,
    after low_pitch_after seconds of the phrase (and not at its end: that is the phrase end's own cue)."""
    first = int((start + listening["low_pitch_after"]) * rate)
    last = int(max(end - 0.5, 0) * rate)
    if last <= first:
        return []
    is_low = np.nan_to_num(semitones[first:last], nan=np.inf) <= low
    needed = max(int(round(listening["low_pitch_length"] * rate)), 1)
    found, run = [], 0
    for index, flag in enumerate(is_low):
        run = run + 1 if flag else 0
        if run == needed:
            found.append(((first + index) / rate, listening["nod_chance_region"]))
    return found
