"""Transfer quality where the truth is known: the reference head bent into other faces at random.

    .venv/bin/python -m lab.measure.transfer [--faces 24] [--seed 0] [--cuts 1] [--tilt DEGREES]

Each face is the reference head (subdivided `cuts` times) bent smoothly: a wider or narrower jaw, a longer
or shorter chin, a bigger or smaller nose, fuller lips, eyes further apart, a sloping forehead, a midface
pushed forward, taller or shorter, at 1/100, 1 or 10 times the size, and with --tilt rolled, nodding and
turned. The reference's units bent the same
way are the truth. Printed per face: the landmark found furthest from where the reference's own landmark
went (share of the face's size), and the cosine of the transferred units against the truth (mean and
lowest, with the lowest unit's name).
"""

from __future__ import annotations

import argparse

import numpy as np

from lab.kit.bent_faces import reshape_face, subdivide_quads
from turkish_lipsync.core.base.errors import HeadError
from turkish_lipsync.core.faces.landmarks import find_landmarks
from turkish_lipsync.core.faces.measure import displacement_cosine
from turkish_lipsync.core.faces.reference import load_reference_head
from turkish_lipsync.core.faces.transfer import transfer_units

# Each bend's range (metres on the reference, or a factor): drawn uniformly per face.
BEND_RANGES = {
    "jaw": (-0.1, 0.25),  # widening below the mouth, as a share
    "chin": (-0.012, 0.03),  # the chin lowered by
    # The reference's nose tip stands 8 mm ahead of its upper lip: a smaller nose over fuller lips stays a
    # human face within these (lips ahead of the nose would be found as the nose).
    "nose": (-0.003, 0.015),  # the nose pushed forward by
    "lips": (-0.003, 0.004),  # each lip pushed forward by
    "eyes": (-0.005, 0.01),  # each eye moved outward by
    "forehead": (-0.01, 0.02),  # the forehead pushed back by
    "midface": (-0.01, 0.01),  # the middle of the face pushed forward by
    "tall": (0.85, 1.2),  # the face's height, as a factor about the nose tip
}
# With --tilt DEGREES, each face is also rolled (about Y), nodding (about X) and turned (about Z) by up
# to that many degrees each, after the bends.
TILT_NAMES = ("roll", "nod", "turn")
SIZES = (0.01, 1.0, 10.0)


def measure_face(reference, bends: dict[str, float], cuts: int) -> dict:
    """The landmarks' worst error and the units' cosines on one bent face."""
    rest = np.asarray(reference.vertices, np.float64)
    vertices, quads = subdivide_quads(rest, reference.polygons, cuts)
    target = reshape_face(vertices, reference.landmarks, bends)
    own = find_landmarks(rest, reference.polygons)
    bent = reshape_face(np.array(list(own.values())), reference.landmarks, bends)
    expected = dict(zip(own, bent, strict=True))
    found = find_landmarks(target, quads)
    size = float(np.linalg.norm(np.ptp(bent, axis=0)))
    errors = {name: np.linalg.norm(found[name] - expected[name]) / size for name in expected if name in found}
    units = transfer_units(reference, target, quads, found)
    cosines = {}
    for name, deltas in reference.units.items():
        moved, _ = subdivide_quads(rest + deltas, reference.polygons, cuts)
        truth = reshape_face(moved, reference.landmarks, bends) - target
        if np.any(truth):
            cosines[name] = displacement_cosine(units[name], truth)
    worst = max(errors, key=errors.get)
    lowest = min(cosines, key=cosines.get)
    return {"landmark": worst, "error": errors[worst], "mean": float(np.mean(list(cosines.values()))),
            "lowest_unit": lowest, "lowest": cosines[lowest]}  # fmt: skip


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--faces", type=int, default=24, help="how many bent faces (default 24)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random bends")
    parser.add_argument("--cuts", type=int, default=1, help="subdivide the reference this many times first")
    parser.add_argument("--tilt", type=float, default=0.0, help="also tilt each face up to this many degrees")
    arguments = parser.parse_args()
    reference = load_reference_head()
    random = np.random.default_rng(arguments.seed)
    print("face  landmark furthest off     error  mean_cosine  lowest unit              cosine")
    means, failed = [], 0
    for face in range(arguments.faces):
        bends = {name: float(random.uniform(*limits)) for name, limits in BEND_RANGES.items()}
        bends["size"] = float(random.choice(SIZES))
        bends.update({name: float(random.uniform(-arguments.tilt, arguments.tilt)) for name in TILT_NAMES})
        try:
            row = measure_face(reference, bends, arguments.cuts)
        except HeadError as error:
            failed += 1
            print(f"{face:4d}  no landmarks: {error}")
            continue
        means.append(row["mean"])
        print(f"{face:4d}  {row['landmark']:22s} {100 * row['error']:6.1f} %  {row['mean']:11.3f}  "
              f"{row['lowest_unit']:22s} {row['lowest']:6.3f}")  # fmt: skip
    if means:
        print(f"all: mean cosine {np.mean(means):.3f}, lowest face {min(means):.3f}; no landmarks: {failed}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
