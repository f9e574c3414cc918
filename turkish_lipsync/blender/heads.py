"""Heads in Blender: the default reference head, importing a user's head, finding the head among objects."""

from __future__ import annotations

from pathlib import Path

import bpy
import numpy as np

from ..core.base.errors import HeadError
from ..core.faces.arkit_names import has_arkit_basis, match_arkit_keys
from ..core.faces.conventions import recognise_convention
from ..core.faces.reference import ReferenceHead, load_reference_head
from . import head_materials, mesh

# Custom property on objects made by create_reference_head: which part of the reference they are.
REFERENCE_PART_PROPERTY = "tr_reference_part"
PART_OBJECT_SUFFIXES = {
    "upper_teeth": "UpperTeeth",
    "lower_teeth": "LowerTeeth",
    "tongue": "Tongue",
    "left_eye": "EyeLeft",
    "right_eye": "EyeRight",
    "left_eyelashes": "EyelashesLeft",
    "right_eyelashes": "EyelashesRight",
}
IMPORTABLE_SUFFIXES = (".obj", ".glb", ".gltf", ".fbx", ".blend")
UV_MAP = "UVMap"


def mesh_from_arrays(
    name: str, vertices: np.ndarray, polygons, uvs: np.ndarray | None = None
) -> bpy.types.Mesh:
    """A mesh from (N, 3) vertices and polygons ((F, k) or a list of index sequences), with foreach_set.

    uvs: one (u, v) per polygon corner, in the order of the polygons' corners, for the "UVMap" layer.
    """
    if isinstance(polygons, np.ndarray):
        corners = np.asarray(polygons, dtype=np.int32).ravel()
        totals = np.full(len(polygons), polygons.shape[1], dtype=np.int32)
    else:
        corners = np.concatenate([np.asarray(polygon, dtype=np.int32) for polygon in polygons])
        totals = np.array([len(polygon) for polygon in polygons], dtype=np.int32)
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(vertices))
    mesh.vertices.foreach_set("co", np.asarray(vertices, dtype=np.float32).ravel())
    mesh.loops.add(len(corners))
    mesh.loops.foreach_set("vertex_index", corners)
    mesh.polygons.add(len(totals))
    mesh.polygons.foreach_set("loop_start", (np.cumsum(totals) - totals).astype(np.int32))
    if (
        "loop_total" in mesh.polygons.bl_rna.properties
        and not mesh.polygons.bl_rna.properties["loop_total"].is_readonly
    ):
        mesh.polygons.foreach_set("loop_total", totals)
    mesh.polygons.foreach_set("use_smooth", np.ones(len(totals), dtype=bool))
    if uvs is not None:
        add_uv_map(mesh, UV_MAP, uvs)
    mesh.update(calc_edges=True)
    mesh.validate(clean_customdata=False)
    return mesh


def add_uv_map(mesh: bpy.types.Mesh, name: str, uvs: np.ndarray) -> None:
    """A UV layer from one (u, v) per loop."""
    layer = mesh.uv_layers.new(name=name)
    layer.data.foreach_set("uv", np.asarray(uvs, dtype=np.float32).ravel())


def _neck_cap(vertices: np.ndarray, loop: np.ndarray) -> np.ndarray:
    """The neck loop as one polygon closing the cut, wound so that its normal points out of the head."""
    points = vertices[loop]
    following = np.roll(points, -1, axis=0)
    normal = np.cross(points, following).sum(axis=0)  # Newell's method: the loop's area vector
    outward = points.mean(axis=0) - vertices.mean(axis=0)
    return loop if float(normal @ outward) > 0 else loop[::-1]


def _part_mesh(
    reference: ReferenceHead, part: str, object_name: str, origin: np.ndarray, tone=None, tone_name: str = ""
) -> bpy.types.Mesh:
    """One part of the reference as a mesh: UVs, materials (the skin in the tone given, if one is); the
    skin also gets its neck cap and brow UVs."""
    indices, vertices, quads, corner_uvs = reference.part_mesh_with_uvs(part)
    polygons: list | np.ndarray = quads
    uvs = corner_uvs.reshape(-1, 2)
    if part == "skin":
        local = np.full(len(reference.vertices), -1, dtype=np.int64)
        local[indices] = np.arange(len(indices))
        cap = _neck_cap(vertices, local[reference.neck_loop])
        polygons = [*quads, cap]
        uvs = np.concatenate([uvs, np.zeros((len(cap), 2), dtype=np.float32)])
    mesh = mesh_from_arrays(object_name, vertices - origin, polygons, uvs)
    if part == "skin":
        corner_vertices = np.zeros(len(mesh.loops), dtype=np.int32)
        mesh.loops.foreach_get("vertex_index", corner_vertices)
        add_uv_map(mesh, head_materials.EYEBROW_UV, reference.eyebrow_uvs(indices)[corner_vertices])
        hair = mesh.attributes.new(head_materials.HAIR_ATTRIBUTE, "FLOAT", "POINT")
        hair.data.foreach_set("value", reference.hair[indices])
        smooth = np.ones(len(mesh.polygons), dtype=bool)
        smooth[-1] = False  # the cap is flat
        mesh.polygons.foreach_set("use_smooth", smooth)
        mesh.materials.append(head_materials.skin_material(reference, UV_MAP, tone, tone_name))
    elif part in ("left_eye", "right_eye"):
        mesh.materials.append(head_materials.eye_material())
    elif part.endswith("eyelashes"):
        mesh.materials.append(head_materials.eyelash_material(UV_MAP))
    else:
        mesh.materials.append(head_materials.plain_material("tongue" if part == "tongue" else "teeth"))
    return mesh


def create_reference_head(
    context: bpy.types.Context, name: str = "TR_Head", tone=None, tone_name: str = ""
) -> dict[str, bpy.types.Object]:
    """The default head: skin object with teeth, tongue, eyes and eyelashes as children, in metres, facing -Y
    (its skin and hair in the tone given, for a conversation's characters).

    Returns {"head", "upper_teeth", "lower_teeth", "tongue", "left_eye", "right_eye", "left_eyelashes",
    "right_eyelashes"} -> object. World coordinates equal MakeHuman's (origin at the hips); the head
    object's origin is the head's centre. Every part keeps the reference's vertex order, so its keys are
    the reference's units.
    """
    reference = load_reference_head()
    skin = reference.parts["skin"]
    lower, upper = reference.vertices[skin].min(axis=0), reference.vertices[skin].max(axis=0)
    origin = np.array([0.0, (lower[1] + upper[1]) / 2, (lower[2] + upper[2]) / 2])
    collection = context.collection if context.collection is not None else context.scene.collection

    objects: dict[str, bpy.types.Object] = {}
    for part in ("skin", *PART_OBJECT_SUFFIXES):
        object_name = name if part == "skin" else f"{name}_{PART_OBJECT_SUFFIXES[part]}"
        obj = bpy.data.objects.new(
            object_name, _part_mesh(reference, part, object_name, origin, tone, tone_name)
        )
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
    """The head among imported objects: the mesh with mouth shapes of its own (a face object beside the
    body, as VRM avatars have), else the mesh with the most faces (a whole body counts as the head).

    Raises HeadError when no object has faces. Whether a face can be recognised on it is checked when
    the keys are built (the landmarks are found there).
    """
    meshes = [obj for obj in objects if obj is not None and obj.type == "MESH" and len(obj.data.polygons) > 0]
    if not meshes:
        raise HeadError("None of the objects is a mesh with faces; import or select a head mesh.")
    referenced = [obj for obj in meshes if obj.get(REFERENCE_PART_PROPERTY) == "skin"]
    if referenced:
        return referenced[0]
    speaking = [obj for obj in meshes if has_mouth_shapes(obj)]
    return max(speaking or meshes, key=lambda obj: (len(obj.data.polygons), obj.name))


def has_mouth_shapes(obj: bpy.types.Object) -> bool:
    """True when the mesh's own keys are visemes of a known convention or an ARKit basis."""
    keys = obj.data.shape_keys
    if keys is None:
        return False
    names = [block.name for block in keys.key_blocks if block != keys.reference_key]
    return recognise_convention(names) is not None or has_arkit_basis(match_arkit_keys(names))


def find_head_parts(head: bpy.types.Object, objects=None) -> list[bpy.types.Object]:
    """Meshes of the head's mouth and eyes: its mesh children, and small meshes inside its bounds that
    are nobody's children (teeth or lashes a user imported beside a head whose eyes are parented)."""
    children = [child for child in head.children if child.type == "MESH"]
    if objects is None:
        objects = head.users_collection[0].objects if head.users_collection else []
    lower, upper = mesh.world_bounds(head)
    size = float(np.max(upper - lower))
    parts = list(children)
    for obj in objects:
        if obj is head or obj in parts or obj.type != "MESH" or len(obj.data.vertices) == 0:
            continue
        if obj.parent is not None and obj.parent.type == "MESH":
            continue  # a part of another mesh
        obj_lower, obj_upper = mesh.world_bounds(obj)
        centre = (obj_lower + obj_upper) / 2
        inside = bool(np.all(centre > lower) and np.all(centre < upper))
        if inside and float(np.max(obj_upper - obj_lower)) < 0.5 * size:
            parts.append(obj)
    return parts
