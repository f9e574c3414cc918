"""Where the face-rig mappings' figures come from (shapekeys/rigs/*.toml): the default head's own units.

    .venv/bin/python scripts/rig_mapping_figures.py

Prints the hinge and turn of the default head's jawOpen (fitted to the vertices it moves most, as
scripts/rigged_heads.py fits a jaw bone), then, per ARKit unit, how far it moves each landmark of the mouth,
brows and nose, in mouth widths of the character's frame [left, up, forward]: the moves the Rigify mapping
gives the controls that sit at those landmarks. Needs no Blender.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from turkish_lipsync.core.faces.reference import load_reference_head  # noqa: E402

LANDMARKS = ("mouth_corner_left", "upper_lip", "lower_lip", "upper_lip_inner", "lower_lip_inner", "chin",
             "brow_left", "nose_tip")  # fmt: skip


def jaw_hinge(vertices: np.ndarray, deltas: np.ndarray) -> tuple[np.ndarray, float]:
    """The hinge (on the middle plane) and angle of the turn about the left-right axis that best gives the
    vertices the unit moves most their motion: d_y = -a z + b, d_z = a y - c, a the angle."""
    size = np.linalg.norm(deltas, axis=1)
    moving = size > 0.5 * size.max()
    y, z = vertices[moving, 1], vertices[moving, 2]
    ones, zeros = np.ones_like(y), np.zeros_like(y)
    system = np.vstack([np.column_stack([-z, ones, zeros]), np.column_stack([y, zeros, -ones])])
    observed = np.concatenate([deltas[moving, 1], deltas[moving, 2]])
    (angle, b, c), *_ = np.linalg.lstsq(system, observed, rcond=None)
    return np.array([0.0, c / angle, b / angle]), float(angle)


def main() -> int:
    reference = load_reference_head()
    skin = reference.parts["skin"]
    points = {name: reference.vertices[index] for name, index in reference.landmark_vertices.items()}
    width = float(np.linalg.norm(points["mouth_corner_left"] - points["mouth_corner_right"]))
    hinge, angle = jaw_hinge(reference.vertices[skin].astype(np.float64), reference.units["jawOpen"][skin])
    above, behind = (hinge[2] - points["lower_lip"][2]) * 1000, (hinge[1] - points["lower_lip"][1]) * 1000
    print(
        f"mouth width {width * 1000:.1f} mm; jawOpen turns {np.degrees(angle):.1f} degrees about a hinge "
        f"{above:.0f} mm above and {behind:.0f} mm behind the lower lip"
    )
    for unit in sorted(reference.units):
        deltas = reference.units[unit]
        moved = []
        for name in LANDMARKS:
            x, y, z = deltas[reference.landmark_vertices[name]] / width
            if max(abs(x), abs(y), abs(z)) > 0.005:
                moved.append(f"{name} [{x:+.2f}, {z:+.2f}, {-y:+.2f}]")  # Blender's -y is the face's forward
        if moved:
            print(f"{unit}: " + "; ".join(moved))
    return 0


if __name__ == "__main__":
    sys.exit(main())
