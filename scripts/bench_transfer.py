"""Time the landmark search and the transfer of the 52 ARKit units onto heads of growing size.

The heads are the reference head cut into finer quads (n x n per quad, the same shape with more
vertices), so the numbers show how the cost grows with the vertex count a user's head brings.

    python scripts/bench_transfer.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from turkish_lipsync.core.faces.head_parts import find_parts  # noqa: E402
from turkish_lipsync.core.faces.landmarks import find_landmarks  # noqa: E402
from turkish_lipsync.core.faces.reference import load_reference_head  # noqa: E402
from turkish_lipsync.core.faces.transfer import transfer_units  # noqa: E402


def subdivide_quads(vertices: np.ndarray, quads: np.ndarray, cuts: int) -> tuple[np.ndarray, np.ndarray]:
    """Each quad split bilinearly into cuts x cuts quads; points on shared edges are merged."""
    steps = np.linspace(0.0, 1.0, cuts + 1)
    u, v = np.meshgrid(steps, steps, indexing="ij")
    a, b, c, d = (vertices[quads[:, i]][:, None, None, :] for i in range(4))
    u, v = u[None, :, :, None], v[None, :, :, None]
    grid = (1 - u) * (1 - v) * a + u * (1 - v) * b + u * v * c + (1 - u) * v * d  # (F, n+1, n+1, 3)
    points = grid.reshape(-1, 3)
    _, first, index = np.unique(np.round(points, 9), axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first)  # keep the original vertex order stable for readability
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    new_vertices = points[first[order]]
    index = rank[index.ravel()].reshape(len(quads), cuts + 1, cuts + 1)
    i, j = np.meshgrid(np.arange(cuts), np.arange(cuts), indexing="ij")
    new_quads = np.stack(
        (index[:, i, j], index[:, i + 1, j], index[:, i + 1, j + 1], index[:, i, j + 1]), axis=-1
    ).reshape(-1, 4)
    return new_vertices, new_quads


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
