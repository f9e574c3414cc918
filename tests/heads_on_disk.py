"""Where the real test heads live: never copied into the repository, found beside it.

$TURKISH_LIPSYNC_HEADS wins; else ../shared/heads next to the checkout; else the workplace's shared folder
(a clean clone made elsewhere, as CI does, still finds them). Tests that need a head skip when none is found.
"""

import os
from pathlib import Path

import numpy as np

_CANDIDATES = (
    os.environ.get("TURKISH_LIPSYNC_HEADS", ""),
    str(Path(__file__).resolve().parents[1].parent / "shared" / "heads"),
    "/work/shared/heads",
)

HEADS = next((Path(c) for c in _CANDIDATES if c and Path(c).is_dir()), Path(_CANDIDATES[1]))


def read_obj(path: Path) -> tuple[np.ndarray, list[list[int]]]:
    """Vertices (in Blender axes: Z up, face toward -Y, as Blender imports them) and polygons of an OBJ."""
    vertices, polygons = [], []
    with open(path, encoding="utf-8") as handle:
        for line in handle:
            if line.startswith("v "):
                vertices.append([float(value) for value in line.split()[1:4]])
            elif line.startswith("f "):
                polygons.append([int(corner.split("/")[0]) - 1 for corner in line.split()[1:]])
    points = np.array(vertices)
    return np.stack((points[:, 0], -points[:, 2], points[:, 1]), axis=1), polygons
