"""Where the face-rig mappings' figures come from (shapekeys/rigs/*.toml): the default head's own units.

    .venv/bin/python -m lab.measure.rig_mappings

Prints the hinge and turn of the default head's jawOpen (fitted to the vertices it moves most, as
lab/kit/rigged_heads.py fits a jaw bone), then, per ARKit unit, how far it moves each landmark of the mouth,
brows and nose, in mouth widths of the character's frame [left, up, forward]: the moves the Rigify mapping
gives the controls that sit at those landmarks. Needs no Blender.
"""

from __future__ import annotations

import sys

import numpy as np

from lab.kit.rigged_heads import LANDMARKS, jaw_hinge
from turkish_lipsync.core.faces.reference import load_reference_head


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
