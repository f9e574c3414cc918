"""Where the real test heads live: never copied into the repository, found beside it.

$TURKISH_LIPSYNC_HEADS wins; else ../shared/heads next to the checkout; else the workplace's shared folder
(a clean clone made elsewhere, as CI does, still finds them). Tests that need a head skip when none is found.
"""

import os
from pathlib import Path

import numpy as np

from lab import REPOSITORY
from turkish_lipsync.core.faces import obj_files

_CANDIDATES = (
    os.environ.get("TURKISH_LIPSYNC_HEADS", ""),
    str(REPOSITORY.parent / "shared" / "heads"),
    "/work/shared/heads",
)

HEADS = next((Path(c) for c in _CANDIDATES if c and Path(c).is_dir()), Path(_CANDIDATES[1]))


def read_obj(path: Path) -> tuple[np.ndarray, list[list[int]]]:
    """Vertices (in Blender axes: Z up, face toward -Y, as Blender imports them) and polygons of an OBJ."""
    obj = obj_files.read_obj(path)
    return obj.blender_vertices(), obj.faces
