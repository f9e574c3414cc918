"""Transfer quality where the truth is known: the reference head bent into other faces at random.

    .venv/bin/python scripts/measure_transfer.py [--faces 24] [--seed 0] [--cuts 1] [--tilt DEGREES]

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
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from scripts.bench_transfer import subdivide_quads  # noqa: E402
from turkish_lipsync.core.base.errors import HeadError  # noqa: E402
from turkish_lipsync.core.faces.landmarks import axis_rotation, find_landmarks  # noqa: E402
from turkish_lipsync.core.faces.measure import displacement_cosine  # noqa: E402
from turkish_lipsync.core.faces.reference import load_reference_head  # noqa: E402
from turkish_lipsync.core.faces.transfer import transfer_units  # noqa: E402

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


def reshape_face(points: np.ndarray, landmarks, bends: dict[str, float]) -> np.ndarray:
    """points (on the reference, metres) bent into another face; landmarks: the reference's."""
    points = np.asarray(points, np.float64)
    mouth_z = 0.5 * (landmarks["upper_lip"][2] + landmarks["lower_lip"][2])
    eye = 0.5 * (landmarks["eye_inner_left"] + landmarks["eye_outer_left"])
    nose_tip, chin, brow_z = landmarks["nose_tip"], landmarks["chin"], landmarks["brow_left"][2]
    x, y, z = points.T
    out = points.copy()
    out[:, 0] *= 1 + bends.get("jaw", 0.0) * np.clip((mouth_z + 0.02 - z) / 0.06, 0, 1)
    out[:, 2] -= bends.get("chin", 0.0) * np.clip((mouth_z - z) / 0.04, 0, 1)
    nose = np.linalg.norm(points - nose_tip, axis=1)
    out[:, 1] -= bends.get("nose", 0.0) * np.exp(-((nose / 0.02) ** 2))
    for lip in ("upper_lip", "lower_lip"):  # each lip fuller on its own: the crease between them stays
        centre = [0.0, landmarks[lip][1], landmarks[lip][2]]
        lips = np.linalg.norm((points - centre) * [1.0, 1.0, 3.0], axis=1)
        out[:, 1] -= bends.get("lips", 0.0) * np.exp(-((lips / 0.02) ** 2))
    around_eye = ((np.abs(x) - abs(eye[0])) ** 2 + (z - eye[2]) ** 2) / 0.025**2
    out[:, 0] += bends.get("eyes", 0.0) * np.sign(x) * np.exp(-around_eye)
    out[:, 1] += bends.get("forehead", 0.0) * np.clip((z - eye[2] - 0.03) / 0.05, 0, 1)
    middle = np.exp(-((x / 0.05) ** 2)) * np.clip((z - chin[2]) / 0.1, 0, 1)
    out[:, 1] -= bends.get("midface", 0.0) * middle * np.clip((brow_z + 0.02 - z) / 0.03, 0, 1)
    out[:, 2] = nose_tip[2] + (out[:, 2] - nose_tip[2]) * bends.get("tall", 1.0)
    turn = tilt(bends)
    return ((out - nose_tip) @ turn.T + nose_tip) * bends.get("size", 1.0)


def tilt(bends: dict[str, float]) -> np.ndarray:
    """The rotation of the bends' roll, nod and turn (degrees; none when absent)."""
    turn = np.eye(3)
    for axis, name in ((1, "roll"), (0, "nod"), (2, "turn")):
        turn = axis_rotation(axis, bends.get(name, 0.0)) @ turn
    return turn


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
