"""The one reader of Wavefront OBJ files in the tree: MakeHuman's base mesh at build time, the thesis's folder
of homeomorphic viseme models, and the shared test heads all go through it."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..base.errors import HeadError


@dataclass(frozen=True)
class ObjMesh:
    """An OBJ's contents as written (the file's own axes and units; 0-based indices)."""

    vertices: np.ndarray  # (N, 3)
    faces: list[list[int]]  # vertex indices of each face's corners
    face_uvs: list[list[int]]  # texture-coordinate indices of each face's corners (empty where none)
    uvs: np.ndarray  # (K, 2)
    face_groups: list[str]  # the group ("g") each face was written in

    def blender_vertices(self) -> np.ndarray:
        """The vertices in Blender's axes, as its OBJ importer gives them by default (Y up becomes Z up)."""
        return blender_axes(self.vertices)


def blender_axes(points: np.ndarray) -> np.ndarray:
    """OBJ axes (Y up, face toward +Z) -> Blender's (Z up, face toward -Y)."""
    points = np.asarray(points, np.float64)
    return np.stack([points[..., 0], -points[..., 2], points[..., 1]], axis=-1)


def read_obj(path: Path) -> ObjMesh:
    """Vertices, faces, texture coordinates and groups of an OBJ file; a HeadError naming the file and
    line when it cannot be read."""
    vertices: list[str] = []
    uvs: list[str] = []
    faces: list[list[int]] = []
    face_uvs: list[list[int]] = []
    groups: list[str] = []
    group = ""
    try:
        with open(path, encoding="utf-8", errors="replace") as handle:
            for number, line in enumerate(handle, 1):
                if line.startswith("v "):
                    vertices.append(line[2:])
                elif line.startswith("vt "):
                    uvs.append(line[3:])
                elif line.startswith("f "):
                    corners = [corner.split("/") for corner in line[2:].split()]
                    try:
                        faces.append([int(corner[0]) - 1 for corner in corners])
                        face_uvs.append(
                            [int(corner[1]) - 1 for corner in corners if len(corner) > 1 and corner[1]]
                        )
                    except ValueError as error:
                        raise HeadError(f"{path}:{number}: unreadable face line ({error}).") from error
                    groups.append(group)
                elif line.startswith("g "):
                    group = line[2:].strip()
    except OSError as error:
        raise HeadError(f"Cannot read {path}: {error.strerror or error}.") from error
    try:
        vertex_array = np.array([row.split()[:3] for row in vertices], dtype=np.float64).reshape(-1, 3)
        uv_array = np.array([row.split()[:2] for row in uvs], dtype=np.float64).reshape(-1, 2)
    except ValueError as error:
        raise HeadError(
            f"{path}: unreadable vertex line ({error}); export the model again as OBJ."
        ) from error
    return ObjMesh(vertex_array, faces, face_uvs, uv_array, groups)
