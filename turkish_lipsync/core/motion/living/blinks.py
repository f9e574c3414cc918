"""Blinks at today's rate and shape, placed where people blink: at pauses, phrase ends and large gaze shifts.

Speakers blink as a phrase ends and in pauses (Nakano and Kitazawa 2010), and nearly every gaze shift over
30 degrees carries a blink (Evinger 1994). So the blinks the rate calls for are moved to the nearest pause
or gaze shift within reach, large shifts bring their own, no two come closer than min_gap and none is
further than max_interval from the last while speaking. None while the emotions on the face narrow the
eyes (a smile half-closes them already).
"""

from __future__ import annotations

import numpy as np

from .gaze import Saccade
from .phrases import SpeechStructure


def place_blinks(
    structure: SpeechStructure,
    saccades: tuple[Saccade, ...],
    duration: float,
    rng: np.random.Generator,
    settings: dict,
    amount: float,
) -> list[float]:
    """Start times of the blinks, in order."""
    if amount <= 0 or duration <= settings["first_after"]:
        return []
    forced, candidates = [], []
    low, high = settings["gaze_shift_blink"], settings["gaze_shift_always"]
    for saccade in saccades:
        if saccade.amplitude >= high:
            forced.append(saccade.start)
        elif saccade.amplitude >= low:
            chance = settings["gaze_shift_share"] + (1 - settings["gaze_shift_share"]) * (
                (saccade.amplitude - low) / max(high - low, 1e-6)
            )
            (forced if rng.random() < chance * amount else candidates).append(saccade.start)
    for start, end in structure.pauses:
        if start > 0.0 and end - start >= 0.25:
            candidates.append(start + settings["pause_lead"])
    for _start, end in structure.phrases:
        candidates.append(end + settings["pause_lead"])
    candidates = np.unique(np.array([c for c in candidates if c >= settings["first_after"]]))

    times = sorted(t for t in forced if settings["first_after"] <= t < duration)
    mean = settings["mean_interval"] / amount
    shape = 4.0  # gamma shape: intervals cluster around the mean without being regular
    last = settings["first_after"] - mean / 2
    blinks: list[float] = []
    while True:
        interval = float(rng.gamma(shape, mean / shape))
        due = last + min(max(interval, settings["min_interval"]), settings["max_interval"])
        upcoming = next((t for t in times if t > last + settings["min_gap"]), None)
        reachable = min(due + settings["pause_pull"], last + settings["max_interval"])
        if upcoming is not None and upcoming <= reachable:
            when = upcoming  # a large gaze shift's own blink comes first
        else:
            reach = (candidates >= max(last + settings["min_interval"], due - settings["pause_pull"])) & (
                candidates <= min(due + settings["pause_pull"], last + settings["max_interval"])
            )
            near = candidates[reach]
            when = float(near[np.argmin(np.abs(near - due))]) if near.size else due
        if when >= duration - settings["max_duration"]:
            break
        blinks.append(when)
        last = when
    return blinks


def blink_durations(starts: list[float], rng: np.random.Generator, settings: dict) -> np.ndarray:
    """How long each placed blink lasts (closing, shut and opening together), seconds."""
    return rng.uniform(settings["min_duration"], settings["max_duration"], len(starts))


def blink_curve(
    blinks: tuple[tuple[float, float], ...],
    fps: float,
    frame_count: int,
    eye_closure: np.ndarray,
    settings: dict,
) -> tuple[np.ndarray, list[tuple[float, float]]]:
    """The lids' closure at each frame and the (start, end) of each blink kept, from the planned (start,
    duration) of each; every blink is shut on a frame (its start moves by less than half a frame so that one
    falls where the lids meet), none where the emotions already narrow the eyes."""
    curve = np.zeros(frame_count)
    spans = []
    for planned, duration in blinks:
        closing = duration * settings["close_share"]
        hold = duration * settings["hold_share"]
        opening = duration - closing - hold
        start = round((planned + closing) * fps) / fps - closing
        first, last = max(0, int(np.ceil(start * fps - 1e-9))), int(np.floor((start + duration) * fps + 1e-9))
        last = min(last, frame_count - 1)
        if last < first or eye_closure[first : last + 1].max() >= settings["blink_suppress_closure"]:
            continue
        local = np.arange(first, last + 1) / fps - start
        profile = np.minimum(local / closing, (duration - local) / opening)
        profile[np.abs(local - closing) < 1e-9] = 1.0
        curve[first : last + 1] = np.maximum(curve[first : last + 1], np.minimum(profile, 1.0))  # >= 0
        spans.append((float(start), float(start + duration)))
    return curve, spans
