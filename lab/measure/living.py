"""Measure the living face on the evaluated scene: gaze, saccades, blinks, head motion, the CSV's rotations.

    .venv/bin/python -m lab.measure.living [--head PATH] [--seconds 60] [--fps 60] [--seed 0] [--json]

Builds the head (default: the reference head), adds the render's camera, generates about --seconds of
Turkish speech, then steps every frame (frame_set and the evaluated depsgraph) and fits a rotation to the
evaluated eyeball vertices (each eye) and to the skull (head vertices no key moves). The gaze is each
eyeball's turned forward axis, against the direction from the eye to the camera; pauses come from the
speech WAV's own silences and F0 from Praat's tracker on the WAV (parselmouth), not from ours. Prints every
figure of issue 19's "Done when" with its range.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from lab.kit.living_scene import measure

DONE_WHEN = {
    "gaze_p95_deg": (3, np.inf),
    "contact_share": (0.25, 0.60),
    "saccades_per_min": (6, 90),
    "saccades_under_15_share": (0.8, 1.0),
    "saccade_duration_vs_main_sequence": (0.6, 1.7),
    "blinks_per_min": (10, 35),
    "blink_gap_max_s": (0, 10),
    "blink_closing_ms": (0, 120),
    "blinks_near_pause_or_shift_share": (0.5, 1.0),
    "head_rms_deg": (0.7, 6),
    "head_max_deg": (0, 15),
    "csv_rotation_columns_nonzero": (6, 9),
}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--head", type=Path)
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--fps", type=float, default=60.0)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args([a for a in sys.argv[sys.argv.index("--") + 1 :]] if "--" in sys.argv else None)
    result = measure(args.head, args.seconds, args.fps, args.seed)
    shown = {k: v for k, v in result.items() if isinstance(v, int | float | str)}
    if args.json:
        print(json.dumps(shown, indent=1))
        return 0
    for name, value in shown.items():
        bounds = DONE_WHEN.get(name)
        verdict = "" if bounds is None else ("  ok" if bounds[0] <= value <= bounds[1] else "  OUT OF RANGE")
        if name == "head_pitch_f0_r":
            verdict = "  ok" if abs(value) >= 0.25 else "  OUT OF RANGE"
        if name == "csv_head_pitch_vs_scene_r":
            verdict = "  ok" if abs(value) >= 0.8 else "  OUT OF RANGE"
        text = f"{value:.3f}" if isinstance(value, float) else str(value)
        print(
            f"{name:38s} {text:>10s}{'' if bounds is None else f'   [{bounds[0]:g}, {bounds[1]:g}]'}{verdict}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
