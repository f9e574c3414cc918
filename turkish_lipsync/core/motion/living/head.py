"""Head motion from the voice: small rotations that follow its pitch and loudness.

The head rises and falls with F0 (Yehia, Kuratate and Vatikiotis-Bateson 2002 find head motion and F0
strongly coupled; Busso et al. 2005 drive heads with it), lifts into each accented syllable and settles
after it (a nod whose apex falls on the accent, Graf et al. 2002), takes a new turn and tilt at each phrase
and sways a little while the voice is loud; in a long pause it stills. Without audio (table timing) the
pitch term is absent and the nods fall on the text's stressed syllables.
"""

from __future__ import annotations

import numpy as np

from .easing import smoothstep
from .phrases import SpeechStructure


def head_angles(
    structure: SpeechStructure, times: np.ndarray, rng: np.random.Generator, settings: dict, amount: float
) -> np.ndarray:
    """(frames, 3) yaw, pitch, roll in degrees (HeadAndEyes' conventions)."""
    angles = np.zeros((times.size, 3))
    if amount <= 0 or times.size == 0:
        return angles
    fps = 1.0 / (times[1] - times[0]) if times.size > 1 else 25.0
    speaking = ~structure.in_pause(times)
    loudness = _loudness(structure, times, speaking)
    still = structure.pause_length_at(times) >= settings["still_pause"]

    pitch = np.zeros(times.size)
    if structure.prosody is not None:
        semitones = _bridged(structure.prosody.semitones(), structure.prosody.rate, 0.25)
        pitch += settings["pitch_per_semitone"] * np.nan_to_num(structure.prosody.at(times, semitones))
        pitch *= _eased(speaking.astype(float), fps, 0.15)
    pitch += settings["nod"] * _nods(structure.accents, times, fps, settings["nod_width"])

    postures = _postures(structure, times, rng, settings)
    sway = sway_motion(times, rng, settings["sway"]) * (loudness * ~still)[:, None]
    angles[:, 0] = postures[:, 0] + sway[:, 0]
    angles[:, 1] = pitch + postures[:, 1] + sway[:, 1]
    angles[:, 2] = postures[:, 2] + sway[:, 2]
    angles = _smoothed(angles, fps, settings["smoothing"])
    return np.clip(amount * angles, -settings["limit"], settings["limit"])


def _loudness(structure: SpeechStructure, times: np.ndarray, speaking: np.ndarray) -> np.ndarray:
    """0 (silence) .. 1 (the take's loud end), from the energy where there is audio, else from speaking."""
    if structure.prosody is None:
        return speaking.astype(float)
    energy = structure.prosody.at(times, structure.prosody.energy)
    return np.clip((energy + 30.0) / 30.0, 0.0, 1.0)


def _bridged(values: np.ndarray, rate: float, longest: float) -> np.ndarray:
    """NaN gaps up to `longest` seconds filled by linear interpolation (voiceless consonants in a phrase)."""
    finite = np.flatnonzero(np.isfinite(values))
    if finite.size < 2:
        return values
    filled = np.interp(np.arange(values.size), finite, values[finite])
    gap = np.zeros(values.size)
    previous = np.maximum.accumulate(np.where(np.isfinite(values), np.arange(values.size), -1))
    following = np.minimum.accumulate(
        np.where(np.isfinite(values), np.arange(values.size), values.size)[::-1]
    )[::-1]
    gap = (following - previous) / rate
    return np.where(np.isfinite(values) | (gap <= longest), filled, np.nan)


def _nods(accents, times: np.ndarray, fps: float, width: float) -> np.ndarray:
    """The sum of every accent's nod (its strength high) over the frames, all accents at once."""
    if not accents or times.size == 0:
        return np.zeros(times.size)
    at = np.array([accent.time for accent in accents])
    strength = np.array([accent.strength for accent in accents])
    first = np.searchsorted(times, at - 0.5 * width)
    frames = first[:, None] + np.arange(int(np.ceil(1.75 * width * fps)) + 2)
    reached = times[np.minimum(frames, times.size - 1)]
    inside = (frames < times.size) & (reached < (at + 1.25 * width)[:, None])
    nods = strength[:, None] * _nod((reached - at[:, None]) / width)
    return np.bincount(frames[inside], weights=nods[inside], minlength=times.size)


def _nod(x: np.ndarray) -> np.ndarray:
    """Up into the accent (apex at 0), then a little below rest as the head settles."""
    rise = np.where(np.abs(x) < 0.5, 0.5 + 0.5 * np.cos(2 * np.pi * x), 0.0)
    settle = np.where((x > 0.25) & (x < 1.25), -0.25 * np.sin(np.pi * (x - 0.25)), 0.0)
    return rise + settle


def _postures(structure: SpeechStructure, times: np.ndarray, rng, settings: dict) -> np.ndarray:
    """A turn, a nod offset and a tilt taken at each phrase's start and held through it."""
    spread = np.array([settings["posture_yaw"], settings["posture_pitch"], settings["posture_roll"]])
    ease = max(settings["posture_ease"], 1e-3)
    begins = np.array([start - 0.3 * ease for start, _end in structure.phrases])
    limit = settings["posture_limit"]
    targets = np.clip(rng.normal(0.0, spread, (begins.size, 3)), -limit, limit)
    sources = np.vstack([np.zeros((1, 3)), targets])[:-1]
    # Each frame eases from the last phrase's posture toward that of the phrase begun by then.
    current = np.searchsorted(begins, times, side="right") - 1
    postures = np.zeros((times.size, 3))
    moving = current >= 0
    phrase = current[moving]
    share = smoothstep((times[moving] - begins[phrase]) / ease)
    postures[moving] = sources[phrase] + (targets[phrase] - sources[phrase]) * share[:, None]
    return postures


def sway_motion(times: np.ndarray, rng, amplitude: float) -> np.ndarray:
    """A slow, irregular sway on each axis (degrees about amplitude): a few sinusoids of 0.15-0.6 Hz with
    random phases."""
    sway = np.zeros((times.size, 3))
    for axis in range(3):
        frequencies = rng.uniform(0.15, 0.6, 3)
        phases = rng.uniform(0, 2 * np.pi, 3)
        wave = sum(np.sin(2 * np.pi * f * times + p) for f, p in zip(frequencies, phases, strict=True))
        sway[:, axis] = amplitude * wave / np.sqrt(1.5)
    return sway


def _eased(values: np.ndarray, fps: float, seconds: float) -> np.ndarray:
    return _smoothed(values[:, None], fps, seconds)[:, 0]


def _smoothed(values: np.ndarray, fps: float, seconds: float) -> np.ndarray:
    """A Gaussian of `seconds` standard deviation over the frames (zero phase: nothing lags the voice)."""
    sigma = seconds * fps
    if sigma < 0.3:
        return values
    radius = int(np.ceil(3 * sigma))
    kernel = np.exp(-0.5 * (np.arange(-radius, radius + 1) / sigma) ** 2)
    kernel /= kernel.sum()
    padded = np.pad(values, ((radius, radius), (0, 0)), mode="edge")
    return np.stack(
        [np.convolve(padded[:, axis], kernel, mode="valid") for axis in range(values.shape[1])], 1
    )
