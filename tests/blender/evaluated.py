"""The tests' one reading of what Blender shows: an object's evaluated mesh, in world space."""

import bpy
import numpy as np


def evaluated_world(obj: bpy.types.Object) -> np.ndarray:
    """(N, 3) world coordinates of obj's evaluated mesh (shape keys, modifiers and all)."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    shape = evaluated.to_mesh()
    flat = np.empty(len(shape.vertices) * 3, np.float32)
    shape.vertices.foreach_get("co", flat)
    evaluated.to_mesh_clear()
    matrix = np.array(obj.matrix_world, np.float64)
    return flat.reshape(-1, 3).astype(np.float64) @ matrix[:3, :3].T + matrix[:3, 3]
