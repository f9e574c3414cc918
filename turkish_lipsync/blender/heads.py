"""Heads in Blender: the default reference head, importing a user's head, finding the head among objects."""

from __future__ import annotations

from pathlib import Path

import bpy
import numpy as np

from ..core.errors import HeadError
from ..core.faces.reference import ReferenceHead, load_reference_head
from . import compat, mesh

# Custom property on objects made by create_reference_head: which part of the reference they are.
REFERENCE_PART_PROPERTY = "tr_reference_part"
PART_OBJECT_SUFFIXES = {
    "upper_teeth": "UpperTeeth",
    "lower_teeth": "LowerTeeth",
    "tongue": "Tongue",
    "left_eye": "EyeLeft",
    "right_eye": "EyeRight",
}
# Plain colours that read as a face in Cycles, EEVEE and Workbench (base colour, roughness).
_MATERIALS = {
    "skin": ((0.80, 0.56, 0.45, 1.0), 0.55),
    "teeth": ((0.90, 0.87, 0.78, 1.0), 0.3),
    "tongue": ((0.62, 0.22, 0.24, 1.0), 0.4),
    "sclera": ((0.92, 0.92, 0.90, 1.0), 0.15),
    "iris": ((0.22, 0.13, 0.07, 1.0), 0.15),
    "pupil": ((0.01, 0.01, 0.01, 1.0), 0.1),
}
IMPORTABLE_SUFFIXES = (".obj", ".glb", ".gltf", ".fbx", ".blend")


def _material(name: str) -> bpy.types.Material:
    """A plain Principled material, reused when it already exists."""
    material_name = f"TR_{name}"
    material = bpy.data.materials.get(material_name)
    if material is not None:
        return material
    color, roughness = _MATERIALS[name]
    material = bpy.data.materials.new(material_name)
    material.diffuse_color = color  # Workbench and the viewport
    material.roughness = roughness
    compat.enable_material_nodes(material)
    shader = next((node for node in material.node_tree.nodes if node.type == "BSDF_PRINCIPLED"), None)
    if shader is not None:
        shader.inputs["Base Color"].default_value = color
        shader.inputs["Roughness"].default_value = roughness
    return material


def mesh_from_arrays(name: str, vertices: np.ndarray, polygons: np.ndarray) -> bpy.types.Mesh:
    """A mesh from (N, 3) vertices and (F, k) polygons, filled with foreach_set."""
    mesh = bpy.data.meshes.new(name)
    polygons = np.asarray(polygons, dtype=np.int32)
    corners = polygons.shape[1]
    mesh.vertices.add(len(vertices))
    mesh.vertices.foreach_set("co", np.asarray(vertices, dtype=np.float32).ravel())
    mesh.loops.add(polygons.size)
    mesh.loops.foreach_set("vertex_index", polygons.ravel())
    mesh.polygons.add(len(polygons))
    mesh.polygons.foreach_set("loop_start", np.arange(0, polygons.size, corners, dtype=np.int32))
    if (
        "loop_total" in mesh.polygons.bl_rna.properties
        and not mesh.polygons.bl_rna.properties["loop_total"].is_readonly
    ):
        mesh.polygons.foreach_set("loop_total", np.full(len(polygons), corners, dtype=np.int32))
    mesh.polygons.foreach_set("use_smooth", np.ones(len(polygons), dtype=bool))
    mesh.update(calc_edges=True)
    mesh.validate(clean_customdata=False)
    return mesh


def _eye_material_indices(vertices: np.ndarray, polygons: np.ndarray) -> np.ndarray:
    """0 sclera, 1 iris, 2 pupil: by how squarely each face looks forward (-Y) from the eye's centre."""
    centre = (vertices.min(axis=0) + vertices.max(axis=0)) / 2
    directions = vertices[polygons].mean(axis=1) - centre
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    forward = -directions[:, 1]
    return np.select([forward > 0.97, forward > 0.82], [2, 1], 0).astype(np.int32)


def create_reference_head(context: bpy.types.Context, name: str = "TR_Head") -> dict[str, bpy.types.Object]:
    """The default head: skin object with teeth, tongue and eyes as children, in metres, facing -Y.

    Returns {"head", "upper_teeth", "lower_teeth", "tongue", "left_eye", "right_eye"} -> object.
    World coordinates equal MakeHuman's (origin at the hips); the head object's origin is the head's centre.
    """
    reference = load_reference_head()
    skin = reference.parts["skin"]
    lower, upper = reference.vertices[skin].min(axis=0), reference.vertices[skin].max(axis=0)
    origin = np.array([0.0, (lower[1] + upper[1]) / 2, (lower[2] + upper[2]) / 2])
    collection = context.collection if context.collection is not None else context.scene.collection

    objects: dict[str, bpy.types.Object] = {}
    for part in ("skin", *PART_OBJECT_SUFFIXES):
        _, vertices, quads = reference.part_mesh(part)
        object_name = name if part == "skin" else f"{name}_{PART_OBJECT_SUFFIXES[part]}"
        mesh = mesh_from_arrays(object_name, vertices - origin, quads)
        if part in ("left_eye", "right_eye"):
            for material_name in ("sclera", "iris", "pupil"):
                mesh.materials.append(_material(material_name))
            mesh.polygons.foreach_set("material_index", _eye_material_indices(vertices, quads))
        else:
            mesh.materials.append(_material({"skin": "skin", "tongue": "tongue"}.get(part, "teeth")))
        obj = bpy.data.objects.new(object_name, mesh)
        obj[REFERENCE_PART_PROPERTY] = part
        collection.objects.link(obj)
        objects["head" if part == "skin" else part] = obj
    head = objects["head"]
    head.location = origin
    for part in PART_OBJECT_SUFFIXES:
        objects[part].parent = head
    context.view_layer.update()  # matrix_world is stale until the view layer updates
    return objects


def reference_part_of(obj: bpy.types.Object, reference: ReferenceHead | None = None) -> str | None:
    """The reference part an object was created as, if its mesh still has that part's vertex count."""
    part = obj.get(REFERENCE_PART_PROPERTY)
    if not isinstance(part, str) or obj.type != "MESH":
        return None
    reference = reference or load_reference_head()
    if part not in reference.parts or len(obj.data.vertices) != len(reference.parts[part]):
        return None
    return part


def import_head(filepath: str | Path) -> list[bpy.types.Object]:
    """Import a head file with Blender's own importers; returns the new objects."""
    path = Path(filepath)
    suffix = path.suffix.lower()
    if suffix not in IMPORTABLE_SUFFIXES:
        raise HeadError(f"Cannot import {path}: use one of {', '.join(IMPORTABLE_SUFFIXES)}.")
    if not path.is_file():
        raise HeadError(f"Head file not found: {path}. Check the path.")
    before = set(bpy.data.objects)
    try:
        if suffix == ".obj":
            bpy.ops.wm.obj_import(filepath=str(path))
        elif suffix in (".glb", ".gltf"):
            bpy.ops.import_scene.gltf(filepath=str(path))
        elif suffix == ".fbx":
            bpy.ops.import_scene.fbx(filepath=str(path))
        else:
            _append_blend_objects(path)
    except RuntimeError as error:
        raise HeadError(f"Blender could not import {path}: {error}".strip()) from error
    new_objects = [obj for obj in bpy.data.objects if obj not in before]
    if not new_objects:
        raise HeadError(f"{path} holds no objects to use as a head.")
    return new_objects


def _append_blend_objects(path: Path) -> None:
    with bpy.data.libraries.load(str(path), link=False) as (source, target):
        target.objects = list(source.objects)
    collection = bpy.context.scene.collection
    for obj in target.objects:
        if obj is not None and obj.name not in collection.objects:
            collection.objects.link(obj)


def find_head(objects) -> bpy.types.Object:
    """The head among imported objects: the mesh with the most faces (a whole body counts as the head).

    Raises HeadError when no object has faces. Whether a face can be recognised on it is checked when
    the keys are built (the landmarks are found there).
    """
    meshes = [obj for obj in objects if obj is not None and obj.type == "MESH" and len(obj.data.polygons) > 0]
    if not meshes:
        raise HeadError("None of the objects is a mesh with faces; import or select a head mesh.")
    referenced = [obj for obj in meshes if obj.get(REFERENCE_PART_PROPERTY) == "skin"]
    if referenced:
        return referenced[0]
    return max(meshes, key=lambda obj: (len(obj.data.polygons), obj.name))


def find_head_parts(head: bpy.types.Object, objects=None) -> list[bpy.types.Object]:
    """Meshes of the head's mouth and eyes: its mesh children, or small meshes inside its bounds."""
    children = [child for child in head.children if child.type == "MESH"]
    if children:
        return children
    if objects is None:
        objects = head.users_collection[0].objects if head.users_collection else []
    lower, upper = mesh.world_bounds(head)
    size = float(np.max(upper - lower))
    parts = []
    for obj in objects:
        if obj is head or obj.type != "MESH" or len(obj.data.vertices) == 0:
            continue
        obj_lower, obj_upper = mesh.world_bounds(obj)
        centre = (obj_lower + obj_upper) / 2
        inside = bool(np.all(centre > lower) and np.all(centre < upper))
        if inside and float(np.max(obj_upper - obj_lower)) < 0.5 * size:
            parts.append(obj)
    return parts
