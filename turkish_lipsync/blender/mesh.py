"""The one mesh reader of the Blender layer: rest shapes, triangles and transforms as numpy arrays.

Buffers are read in Blender's own dtypes (float32 coordinates, int32 indices) with foreach_get; every caller
that needs a head's geometry, in local or world space, goes through here.
"""

from __future__ import annotations

import bpy
import numpy as np

from ..core.base.errors import HeadError


def rest_coordinates(obj: bpy.types.Object) -> np.ndarray:
    """(N, 3) float32 local coordinates of the shape keys' rest shape (the reference key, else the mesh)."""
    mesh = obj.data
    source = mesh.shape_keys.reference_key.points if mesh.shape_keys is not None else mesh.vertices
    return read_coordinates(source, len(mesh.vertices))


def read_coordinates(points, count: int) -> np.ndarray:
    """(count, 3) float32 'co' of a vertex or shape-key point collection.

    A shape key's is its `points`, never its `data`: `data` may hold curve points as well, so Blender reads
    it point by point (0.3 ms for 4,000 vertices against 2 microseconds for `points`).
    """
    flat = np.empty(count * 3, dtype=np.float32)
    points.foreach_get("co", flat)
    return flat.reshape(-1, 3)


def triangles(obj: bpy.types.Object) -> np.ndarray:
    """(T, 3) int32 vertex indices of the mesh's loop triangles (quads and n-gons triangulated by Blender)."""
    mesh = obj.data
    mesh.calc_loop_triangles()
    flat = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", flat)
    return flat.reshape(-1, 3)


def triangle_materials(obj: bpy.types.Object) -> np.ndarray:
    """(T,) int32 material slot of each loop triangle (the order triangles() gives)."""
    mesh = obj.data
    mesh.calc_loop_triangles()
    materials = np.empty(len(mesh.loop_triangles), dtype=np.int32)
    mesh.loop_triangles.foreach_get("material_index", materials)
    return materials


def world_matrix(obj: bpy.types.Object) -> np.ndarray:
    return np.array(obj.matrix_world, dtype=np.float64)


def to_world(obj: bpy.types.Object, local: np.ndarray) -> np.ndarray:
    """Local points of obj in world space (float32, like Blender's own buffers)."""
    matrix = world_matrix(obj).astype(np.float32)
    return np.asarray(local, dtype=np.float32) @ matrix[:3, :3].T + matrix[:3, 3]


def world_rest_coordinates(obj: bpy.types.Object) -> np.ndarray:
    return to_world(obj, rest_coordinates(obj))


def world_to_local_linear(obj: bpy.types.Object, doing: str) -> np.ndarray:
    """The inverse of obj's linear transform; a HeadError saying what failed when its scale is zero."""
    linear = world_matrix(obj)[:3, :3]
    if abs(np.linalg.det(linear)) < 1e-12:
        raise HeadError(f"Object {obj.name!r} has a zero scale; apply or fix its scale, then {doing} again.")
    return np.linalg.inv(linear)


def world_points_to_local(obj: bpy.types.Object, points: np.ndarray, doing: str) -> np.ndarray:
    matrix = world_matrix(obj)
    inverse = world_to_local_linear(obj, doing)
    return (np.asarray(points, dtype=np.float64) - matrix[:3, 3]) @ inverse.T


def world_deltas_to_local(obj: bpy.types.Object, deltas: np.ndarray, doing: str = "build") -> np.ndarray:
    """World-space displacements of obj's vertices as float32 local ones (what a shape key stores)."""
    inverse = world_to_local_linear(obj, doing).astype(np.float32)
    return np.asarray(deltas, dtype=np.float32) @ inverse.T


def world_bounds(obj: bpy.types.Object) -> tuple[np.ndarray, np.ndarray]:
    """World-space box of the object's bounding-box corners."""
    box = np.array([tuple(corner) for corner in obj.bound_box], dtype=np.float32)
    world = to_world(obj, box)
    return world.min(axis=0), world.max(axis=0)
