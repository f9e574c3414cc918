"""Time the landmark search and the transfer of the 52 ARKit units onto heads of growing size.

The heads are the reference head cut into finer quads (n x n per quad, the same shape with more
vertices), so the numbers show how the cost grows with the vertex count a user's head brings.

    python -m lab.measure.bench_transfer [--repeat 3]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from lab.kit.bent_faces import subdivide_quads
from turkish_lipsync.core.faces.head_parts import find_parts
from turkish_lipsync.core.faces.landmarks import find_landmarks
from turkish_lipsync.core.faces.reference import load_reference_head
from turkish_lipsync.core.faces.transfer import transfer_units


def best_of(repeat: int, function, *arguments, **keywords):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        result = function(*arguments, **keywords)
        times.append(time.perf_counter() - start)
    return min(times), result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs per measurement; the best is printed")
    arguments = parser.parse_args()
    reference = load_reference_head()
    _ = find_landmarks(reference.vertices, reference.polygons)  # warm the reference's own landmark cache
    transfer_units(reference, reference.vertices, reference.polygons, _)
    print("vertices  landmarks_s  parts_s  transfer_52_units_s")
    for cuts in (1, 2, 3):
        vertices, quads = subdivide_quads(np.asarray(reference.vertices), reference.polygons, cuts)
        landmark_time, landmarks = best_of(arguments.repeat, find_landmarks, vertices, quads)
        parts_time, parts = best_of(arguments.repeat, find_parts, vertices, quads, landmarks)
        transfer_time, units = best_of(
            arguments.repeat, transfer_units, reference, vertices, quads, landmarks, target_parts=parts
        )
        assert len(units) == 52 and units["jawOpen"].shape == vertices.shape
        print(f"{len(vertices):8d}  {landmark_time:11.2f}  {parts_time:7.2f}  {transfer_time:19.2f}")


if __name__ == "__main__":
    main()
