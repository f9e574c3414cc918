"""The thesis's path to a head's keys: a folder of homeomorphic OBJ models, one per viseme (a.obj, bpa.obj,
..., Neutral.obj) and optionally per emotion, whose differences from the neutral model are the keys."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..base.errors import HeadError
from ..base.model import EMOTIONS, emotion_key_name, viseme_key_name
from .obj_files import read_obj
from .recipes import VISEME_NAMES


def obj_folder_keys(folder: str | Path, basis: np.ndarray, head_name: str) -> dict[str, np.ndarray]:
    """TR_viseme_* deltas (and TR_emotion_* where <emotion>.obj exists) on a head whose rest shape is
    basis (its vertices, in the order of the models'), scaled from the models' size to the head's."""
    folder = Path(folder)
    if not folder.is_dir():
        raise HeadError(
            f"OBJ folder not found: {folder}. Choose the folder holding a.obj, bpa.obj, ..., Neutral.obj."
        )
    files = {path.stem.lower(): path for path in folder.glob("*.obj")}
    files.update({path.stem: path for path in folder.glob("*.obj")})
    if "neutral" not in files:
        raise HeadError(f"{folder} has no Neutral.obj; the visemes are measured against the neutral model.")
    neutral = read_obj(files["neutral"]).blender_vertices()
    if len(neutral) != len(basis):
        raise HeadError(
            f"{files['neutral']} has {len(neutral)} vertices but {head_name!r} has {len(basis)}; "
            "the models must be homeomorphic to the head (same vertices in the same order)."
        )
    scale = float(np.ptp(basis, axis=0).sum() / max(np.ptp(neutral, axis=0).sum(), 1e-12))
    missing = [name for name in VISEME_NAMES if name != "neutral" and name not in files]
    if missing:
        raise HeadError(f"{folder} lacks the viseme models {', '.join(m + '.obj' for m in missing)}.")
    keys: dict[str, np.ndarray] = {viseme_key_name("neutral"): np.zeros_like(basis, dtype=np.float32)}
    for name in [*VISEME_NAMES, *EMOTIONS]:
        if name == "neutral" or name not in files:
            continue
        shape = read_obj(files[name]).blender_vertices()
        if len(shape) != len(neutral):
            raise HeadError(
                f"{files[name]} has {len(shape)} vertices, Neutral.obj {len(neutral)}; they must match."
            )
        key_name = viseme_key_name(name) if name in VISEME_NAMES else emotion_key_name(name)
        keys[key_name] = ((shape - neutral) * scale).astype(np.float32)
    return keys
