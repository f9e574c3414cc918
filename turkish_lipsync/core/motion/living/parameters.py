"""The validated contents of shapekeys/living.toml (read once per process)."""

from __future__ import annotations

import math
from functools import cache

from ...base.data import DATA_DIR, load_table, require
from ...base.errors import DataError
from ...base.model import EMOTIONS

TABLE = "living"
SECTIONS = ("gaze", "blinks", "head", "brows", "expression", "eyes", "listening", "addressing")
SHARES = {"cardinal_share", "phrase_pull_share", "close_share", "hold_share", "blink_suppress_closure"}
SHARES |= {"gaze_shift_share", "depth", "loudness", "amplitude_share", "nod_spread", "double_nod_share"}
SHARES |= {"nod_chance_low", "nod_chance_level", "nod_chance_region", "low_pitch_share", "emotion_share"}
SHARES |= {"head_yaw_share", "head_pitch_share"}
# What each section must hold (the modules read these).
REQUIRED = {
    "gaze": "contact_mean contact_shape away_fixation_mean away_fixation_shape away_fixations_mean "
    "amplitude_scale amplitude_min amplitude_max cardinal_share horizontal_limit up_limit down_limit "
    "duration_base duration_slope phrase_pull phrase_pull_share listening_pause thinking_yaw thinking_pitch "
    "thinking_lead",
    "blinks": "mean_interval min_interval max_interval min_gap first_after min_duration max_duration "
    "close_share hold_share blink_suppress_closure pause_pull pause_lead gaze_shift_blink gaze_shift_always "
    "gaze_shift_share",
    "head": "pitch_per_semitone nod nod_width posture_yaw posture_roll posture_pitch posture_limit "
    "posture_ease sway still_pause smoothing limit",
    "brows": "weight accent_weight accent_rise accent_gap lead rise fall",
    "expression": "depth tempo loudness",
    "eyes": "painted_key_degrees",
    "listening": "contact_mean contact_shape away_fixation_mean away_fixations_mean amplitude_share "
    "anticipation sway nod nod_spread nod_width double_nod_share nod_delay nod_min_gap nod_chance_low "
    "nod_chance_level nod_chance_region low_pitch_share low_pitch_length low_pitch_after emotion_share",
    "addressing": "long_turn turn_start_away turn_end_contact head_yaw_share head_pitch_share "
    "head_turn_limit head_ease head_lag away_min contact_mean away_fixations_mean",
}


def _number(section: dict, key: str, where: str) -> float:
    value = section.get(key)
    high = 1.0 if key in SHARES else math.inf
    if isinstance(value, bool) or not isinstance(value, int | float) or not 0.0 <= value <= high:
        raise DataError(
            f"data file {DATA_DIR / (TABLE + '.toml')}: [{where}] {key} must be a number in [0, {high}], "
            f"got {value!r}; fix the entry or reinstall the extension"
        )
    return float(value)


@cache
def living_parameters() -> dict[str, dict[str, float]]:
    """Section -> {name: number}; blinks also has "eye_closure": {emotion: share}, eyes "arkit_degrees"."""
    table = load_table(TABLE)
    result: dict[str, dict] = {}
    for name in SECTIONS:
        section = require(table, name, dict, TABLE)
        missing = sorted(set(REQUIRED[name].split()) - set(section))
        if missing:
            raise DataError(
                f"data file {DATA_DIR / (TABLE + '.toml')}: [{name}] lacks {', '.join(missing)}; "
                "add them or reinstall the extension"
            )
        result[name] = {
            key: _number(section, key, name) for key, value in section.items() if not isinstance(value, dict)
        }
    closure = require(table["blinks"], "eye_closure", dict, TABLE)
    unknown = sorted(set(closure) - set(EMOTIONS))
    if unknown:
        raise DataError(f"data file {DATA_DIR / 'living.toml'}: [blinks.eye_closure] names unknown {unknown}")
    result["blinks"]["eye_closure"] = {e: _number(closure, e, "blinks.eye_closure") for e in closure}
    arkit = require(table["eyes"], "arkit_degrees", dict, TABLE)
    result["eyes"]["arkit_degrees"] = {
        w: _number(arkit, w, "eyes.arkit_degrees") for w in ("out", "in", "up", "down")
    }
    blinks = result["blinks"]
    if blinks["close_share"] + blinks["hold_share"] >= 1.0:
        raise DataError(
            f"data file {DATA_DIR / 'living.toml'}: [blinks] close_share + hold_share must stay below 1"
        )
    return result
