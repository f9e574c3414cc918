"""The 52 ARKit weights per frame as CSV in Live Link Face's layout (Unreal, MetaHuman, face-capture tools).

Every frame's ARKit weights are the built keys' weights times their recipes (shapekeys/visemes.toml and
emotions.toml): what the head shows, expressed in the units every ARKit rig has. The columns are those the
Live Link Face app writes: Timecode, BlendShapeCount, the 52 units in its order, then the head and eye
rotations of the living layers (tracks.head_and_eyes) in Epic's ARKit convention: -1..1 for -180..180
degrees, yaw + toward the character's left, pitch + up, roll + toward its right shoulder; zero when the
layers are off. The eyeLook units are the eyes' angles over the turn faceunits01's units make at weight 1
(shapekeys/living.toml [eyes.arkit_degrees]).
"""

from __future__ import annotations

import csv
import dataclasses
import io
from pathlib import Path

import numpy as np

from ..base.model import Timeline, WeightTracks
from ..faces.eyes import ARKIT_LOOK_UNITS
from ..faces.recipes import Recipes, load_recipes
from ..motion.frames import shown_frame_count
from ..motion.living.parameters import living_parameters
from ..speech.cues import CueFileError
from ..speech.cues.common import read_text
from .formats import ExportFormat, register_export

# The order of ARKit's ARFaceAnchor blend shapes in Live Link Face's CSV and network packets.
LIVE_LINK_UNITS: tuple[str, ...] = (
    "eyeBlinkLeft", "eyeLookDownLeft", "eyeLookInLeft", "eyeLookOutLeft", "eyeLookUpLeft", "eyeSquintLeft",
    "eyeWideLeft", "eyeBlinkRight", "eyeLookDownRight", "eyeLookInRight", "eyeLookOutRight", "eyeLookUpRight",
    "eyeSquintRight", "eyeWideRight", "jawForward", "jawRight", "jawLeft", "jawOpen", "mouthClose",
    "mouthFunnel", "mouthPucker", "mouthRight", "mouthLeft", "mouthSmileLeft", "mouthSmileRight",
    "mouthFrownLeft", "mouthFrownRight", "mouthDimpleLeft", "mouthDimpleRight", "mouthStretchLeft",
    "mouthStretchRight", "mouthRollLower", "mouthRollUpper", "mouthShrugLower", "mouthShrugUpper",
    "mouthPressLeft", "mouthPressRight", "mouthLowerDownLeft", "mouthLowerDownRight", "mouthUpperUpLeft",
    "mouthUpperUpRight", "browDownLeft", "browDownRight", "browInnerUp", "browOuterUpLeft",
    "browOuterUpRight", "cheekPuff", "cheekSquintLeft", "cheekSquintRight", "noseSneerLeft", "noseSneerRight",
    "tongueOut",
)  # fmt: skip
ROTATION_COLUMNS: tuple[str, ...] = (
    "HeadYaw", "HeadPitch", "HeadRoll", "LeftEyeYaw", "LeftEyePitch", "LeftEyeRoll",
    "RightEyeYaw", "RightEyePitch", "RightEyeRoll",
)  # fmt: skip
HEADER: tuple[str, ...] = (
    "Timecode",
    "BlendShapeCount",
    *(unit[0].upper() + unit[1:] for unit in LIVE_LINK_UNITS),
    *ROTATION_COLUMNS,
)


def arkit_weights(tracks: WeightTracks, recipes: Recipes | None = None) -> tuple[np.ndarray, dict[str, int]]:
    """Weights (frame_count, 52) in LIVE_LINK_UNITS order clipped to ARKit's 0..1, and per unit how many
    frames were clipped (recipes draw lip corners in with negative smiles; strong emotions pass 1).

    The built keys mix linearly, so the units are the key weights times the recipe matrix.
    """
    recipes = recipes or load_recipes()
    key_recipes = recipes.key_recipes()
    column = {unit: index for index, unit in enumerate(LIVE_LINK_UNITS)}
    names, key_weights = tracks.sample(np.arange(tracks.frame_count, dtype=np.float64))
    matrix = np.zeros((len(names), len(LIVE_LINK_UNITS)))
    for row, name in enumerate(names):
        for unit, weight in key_recipes.get(name, {}).items():
            matrix[row, column[unit]] = weight
    units = key_weights @ matrix
    if tracks.head_and_eyes is not None:
        _add_eye_looks(units, tracks, column)
    outside = np.count_nonzero((units < -1e-6) | (units > 1 + 1e-6), axis=0)
    clipped = {unit: int(count) for unit, count in zip(LIVE_LINK_UNITS, outside, strict=True) if count}
    return np.clip(units, 0.0, 1.0), clipped


def _add_eye_looks(units: np.ndarray, tracks: WeightTracks, column: dict[str, int]) -> None:
    """The eyeLook units from the eyes' yaw and pitch (their turn over the units' turn at weight 1)."""
    degrees = living_parameters()["eyes"]["arkit_degrees"]
    for (eye, way), unit in ARKIT_LOOK_UNITS.items():
        angles = getattr(tracks.head_and_eyes, f"{eye}_eye")
        turn = {"left": angles[:, 0], "right": -angles[:, 0], "up": angles[:, 1], "down": -angles[:, 1]}[way]
        kind = way if way in ("up", "down") else ("out" if way == eye else "in")
        units[: len(turn), column[unit]] = np.maximum(turn, 0.0)[: units.shape[0]] / degrees[kind]


def rotation_columns(tracks: WeightTracks) -> np.ndarray:
    """(frame_count, 9) head yaw, pitch, roll and each eye's yaw, pitch, roll in -1..1 (180 degrees = 1)."""
    rotations = np.zeros((tracks.frame_count, len(ROTATION_COLUMNS)))
    motion = tracks.head_and_eyes
    if motion is not None:
        count = min(tracks.frame_count, len(motion.head))
        rotations[:count, 0:3] = motion.head[:count]
        eyes = motion.left_eye.shape[1]
        rotations[:count, 3 : 3 + eyes] = motion.left_eye[:count]
        rotations[:count, 6 : 6 + eyes] = motion.right_eye[:count]
    return rotations / 180.0


def timecode(frame: int, fps: float) -> str:
    """SMPTE non-drop timecode HH:MM:SS:FF.mmm at the nominal rate (30 for 29.97), from 00:00:00:00."""
    nominal = max(1, round(fps))
    seconds, frames = divmod(int(frame), nominal)
    minutes, seconds = divmod(seconds, 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours:02d}:{minutes:02d}:{seconds:02d}:{frames:02d}.000"


def frame_of_timecode(text: str, fps: float) -> float:
    """The frame a timecode names (its sub-frame part kept as a fraction)."""
    hours, minutes, seconds, frames = text.strip().split(":")
    return ((int(hours) * 60 + int(minutes)) * 60 + int(seconds)) * max(1, round(fps)) + float(frames)


def live_link_csv(weights: np.ndarray, fps: float, rotations: np.ndarray | None = None) -> str:
    """The CSV text: one row per frame, Live Link Face's columns, six decimals."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(HEADER)
    count = len(LIVE_LINK_UNITS) + len(ROTATION_COLUMNS)
    if rotations is None:
        rotations = np.zeros((len(weights), len(ROTATION_COLUMNS)))
    for frame, row in enumerate(weights):
        values = (f"{value:.6f}" for value in (*row, *rotations[frame]))
        writer.writerow([timecode(frame, fps), count, *values])
    return out.getvalue()


def read_arkit_csv(path: Path, fps: float) -> tuple[np.ndarray, np.ndarray]:
    """Frames (from the first row's timecode) and weights (rows, 52 in LIVE_LINK_UNITS order) of a CSV in
    Live Link Face's layout; columns are matched by name in any case, so other writers' files read too."""
    rows = list(csv.reader(io.StringIO(read_text(path))))
    if not rows or not rows[0] or rows[0][0].strip().lower() != "timecode":
        raise CueFileError(f"{path}: line 1 must start with 'Timecode': is this a Live Link Face CSV?")
    header = [name.strip().lower() for name in rows[0]]
    try:
        columns = [header.index(unit.lower()) for unit in LIVE_LINK_UNITS]
    except ValueError as error:
        raise CueFileError(f"{path}: line 1 lacks an ARKit column ({error})") from None
    frames = np.empty(len(rows) - 1)
    weights = np.empty((len(rows) - 1, len(LIVE_LINK_UNITS)))
    for number, row in enumerate(rows[1:], start=2):
        try:
            frames[number - 2] = frame_of_timecode(row[0], fps)
            weights[number - 2] = [float(row[index]) for index in columns]
        except (ValueError, IndexError):
            raise CueFileError(
                f"{path}: line {number}: expected a timecode and {len(header) - 1} numbers"
            ) from None
    return frames - (frames[0] if len(frames) else 0.0), weights


@register_export
class ArkitCsv(ExportFormat):
    name = "arkit-csv"
    order = 10
    suffix = ".csv"
    label = "ARKit CSV"
    description = "52 ARKit weights per frame, Live Link Face layout (Unreal, MetaHuman)"

    def write(self, timeline: Timeline, tracks: WeightTracks, *, sound_file: str = "", text: str = ""):
        # One row per frame that shows the speech (the scene's frames after Generate), not per frame the
        # motion was computed over, which reaches a frame past the last sound.
        shown = shown_frame_count(timeline.duration, tracks.fps)
        tracks = dataclasses.replace(tracks, frame_count=min(tracks.frame_count, shown))
        weights, clipped = arkit_weights(tracks)
        warnings = ()
        if clipped:
            units = ", ".join(f"{unit} ({count})" for unit, count in sorted(clipped.items()))
            warnings = (
                "ARKit weights lie in 0..1, so the CSV clips the frames where our keys drive a unit outside "
                f"that range (negative for lip corners drawn in, above 1 in strong emotions): {units}.",
            )
        return live_link_csv(weights, tracks.fps, rotation_columns(tracks)), warnings
