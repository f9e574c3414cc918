"""Building the TR_* shape keys on a head from the best basis it has.

Everything is computed first (numpy), then written with foreach_set, so a failure leaves the head as
it was; only the keys this module owns are replaced, so the user's keys, values and animation survive.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import bpy
import numpy as np

from ..core.base.data import load_table
from ..core.base.errors import HeadError, LipSyncError
from ..core.base.model import viseme_key_name
from ..core.faces import head_parts, obj_folder, transfer
from ..core.faces.arkit_names import (
    ARKIT_UNITS,
    has_arkit_basis,
    match_arkit_keys,
    missing_units,
    missing_units_warning,
)
from ..core.faces.conventions import (
    ConventionMatch,
    convention_key_deltas,
    load_conventions,
    match_convention,
    plan_keys,
    read_user_mapping,
    recognise_convention,
    unmatched_names,
)
from ..core.faces.hidden import hidden_face_share
from ..core.faces.landmark_fallbacks import landmarks_from_motion
from ..core.faces.landmarks import find_landmarks
from ..core.faces.recipes import empower, key_deltas, load_recipes
from ..core.faces.reference import ReferenceHead, load_reference_head, reference_vertices_at
from ..core.faces.topology import connected_pieces
from . import mesh
from .eye_keys import plan_look_keys
from .heads import find_head_parts, reference_part_of
from .landmarks import read_landmark_markers
from .owned_keys import LEGACY_ARKIT_PROPERTY, free_name, mark_owned, owned_keys

SOURCES = ("auto", "convention", "arkit", "reference", "transfer", "obj_folder")
# Mesh property: built key name -> where it came from (the panel lists it).
KEY_SOURCES_PROPERTY = "tr_key_sources"
# A build warns when other pieces of the head's mesh hide this share of its face (hidden_face_share).
HIDDEN_FACE_WARNING = 0.3


@dataclass(frozen=True)
class BuildReport:
    """What a build did: shown to the user and checked in tests."""

    head: str
    source: str  # "convention", "arkit", "reference", "transfer" or "obj_folder"
    keys: tuple[str, ...]  # key names written on the head
    objects: tuple[str, ...]  # every object that received the keys (head first)
    missing_units: tuple[str, ...] = ()  # ARKit units the basis lacked (treated as zero)
    warnings: tuple[str, ...] = ()  # what the user must hear about the result (the operator reports them)
    key_sources: Mapping[str, str] = field(default_factory=dict)  # key name -> where it came from
    convention: str = ""  # the title of the convention (or mapping file) the head's own keys follow


# ---------------------------------------------------------------- the ARKit basis, by source


def own_key_names(obj: bpy.types.Object) -> list[str]:
    """The user's own shape keys on obj: neither the rest key nor any key a build wrote (by our mark)."""
    shape_keys = obj.data.shape_keys
    if shape_keys is None:
        return []
    ours = set(owned_keys(obj).values())
    return [
        block.name
        for block in shape_keys.key_blocks
        if block != shape_keys.reference_key and block.name not in ours
    ]


def own_key_deltas(obj: bpy.types.Object, key_names) -> dict[str, np.ndarray]:
    """(N, 3) local deltas of the named keys (those obj has) against each key's relative key."""
    shape_keys = obj.data.shape_keys
    if shape_keys is None:
        return {}
    count = len(obj.data.vertices)
    deltas: dict[str, np.ndarray] = {}
    for key_name in key_names:
        block = shape_keys.key_blocks.get(key_name)
        if block is not None:
            deltas[key_name] = mesh.read_coordinates(block.points, count) - mesh.read_coordinates(
                block.relative_key.points, count
            )
    return deltas


def own_arkit_units(obj: bpy.types.Object) -> dict[str, np.ndarray]:
    """The object's own ARKit-named keys as (N, 3) local deltas against each key's relative key."""
    matched = match_arkit_keys(own_key_names(obj))
    deltas = own_key_deltas(obj, matched.values())
    return {unit: deltas[key_name] for unit, key_name in matched.items()}


def _reference_units_by_part(obj: bpy.types.Object, reference: ReferenceHead) -> dict[str, np.ndarray] | None:
    """Units of an object made by create_reference_head (its mesh is the part, in the same vertex order)."""
    part = reference_part_of(obj, reference)
    if part is None:
        return None
    indices = reference.parts[part]
    return {unit: deltas[indices] for unit, deltas in reference.units.items()}


def _reference_units_by_position(
    obj: bpy.types.Object, reference: ReferenceHead
) -> dict[str, np.ndarray] | None:
    """Units of a mesh cut from MakeHuman's base mesh (the whole body, or a crop) where it was imported."""
    world = mesh.world_rest_coordinates(obj)
    found = reference_vertices_at(world, reference)
    if found is None:
        return None
    matched, metres_per_unit = found
    units = {}
    for unit, deltas in reference.units.items():
        world_deltas = np.zeros((len(world), 3), dtype=np.float32)
        world_deltas[matched >= 0] = deltas[matched[matched >= 0]] / metres_per_unit
        units[unit] = mesh.world_deltas_to_local(obj, world_deltas)
    return units


def reference_units(obj: bpy.types.Object, reference: ReferenceHead) -> dict[str, np.ndarray] | None:
    return _reference_units_by_part(obj, reference) or _reference_units_by_position(obj, reference)


def _transfer_units(
    head: bpy.types.Object, parts: list[bpy.types.Object], reference: ReferenceHead
) -> tuple[dict[str, dict[str, np.ndarray]], dict[str, np.ndarray]]:
    """The reference's units carried over by landmark registration, in world space, onto head and parts;
    and the head's landmarks (world space) they were registered by."""
    objects = [head, *parts]
    world = [mesh.world_rest_coordinates(obj) for obj in objects]
    offsets = np.cumsum([0] + [len(points) for points in world])
    all_vertices = np.concatenate(world)
    all_triangles = np.concatenate(
        [mesh.triangles(obj) + offset for obj, offset in zip(objects, offsets, strict=False)]
    )
    head_triangles = mesh.triangles(head)
    if len(head_triangles) == 0:
        raise HeadError(f"{head.name!r} has no faces; a head needs a surface to build shape keys on.")
    landmarks = head_landmarks(head, parts)
    # Each object's materials of its own: a part split from the skin by material only is a piece too.
    slots = np.cumsum([0] + [max(len(obj.material_slots), 1) for obj in objects])
    materials = np.concatenate(
        [mesh.triangle_materials(obj) + slot for obj, slot in zip(objects, slots, strict=False)]
    )
    target_parts = head_parts.find_parts(all_vertices, all_triangles, landmarks, materials)
    deltas = transfer.transfer_units(
        reference, all_vertices, all_triangles, landmarks, target_parts=target_parts
    )
    result: dict[str, dict[str, np.ndarray]] = {}
    for index, obj in enumerate(objects):
        start, stop = offsets[index], offsets[index + 1]
        result[obj.name] = {
            unit: mesh.world_deltas_to_local(obj, moved[start:stop]) for unit, moved in deltas.items()
        }
    return result, landmarks


def _mesh_parts(head: bpy.types.Object, parts: list[bpy.types.Object] | None) -> list[bpy.types.Object]:
    """The head's parts that are meshes with vertices (find_head_parts when none are given)."""
    if parts is None:
        parts = find_head_parts(head)
    return [part for part in parts if part is not head and part.type == "MESH" and len(part.data.vertices)]


def head_landmarks(
    head: bpy.types.Object, parts: list[bpy.types.Object] | None = None
) -> dict[str, np.ndarray]:
    """The head's landmarks in world space: its markers where the user placed them; else from its shape,
    with its parts (find_head_parts when not given) beside it, so that eyeballs of their own showing between
    the lids mark the lids' margins and the eyes' corners; else from what its own mouth-opening and blink
    keys move (a mouth painted on the texture that only a key opens); else the shape's error, which says to
    place markers."""
    markers = read_landmark_markers(head)
    if markers:
        names = list(markers)
        placed = mesh.to_world(head, np.array([markers[name] for name in names], dtype=np.float32))
        return dict(zip(names, placed.astype(np.float64), strict=True))
    world_vertices, triangles = mesh.world_rest_coordinates(head), mesh.triangles(head)
    with_parts, with_parts_triangles = world_vertices, triangles
    for part in _mesh_parts(head, parts):
        with_parts_triangles = np.concatenate((with_parts_triangles, mesh.triangles(part) + len(with_parts)))
        with_parts = np.concatenate((with_parts, mesh.world_rest_coordinates(part)))
    try:
        return find_landmarks(with_parts, with_parts_triangles)
    except HeadError as error:
        names = load_table("artist_comparisons")["compare"]
        linear = mesh.world_matrix(head)[:3, :3]
        users = set(own_key_names(head))

        def own(*units):
            for unit in units:
                found = own_key_deltas(head, [name for name in names.get(unit, ()) if name in users])
                if found:
                    return next(iter(found.values())).astype(np.float64) @ linear.T
            return None

        mouth = own("jawOpen", viseme_key_name("a"))
        if mouth is None:
            raise
        try:
            return landmarks_from_motion(
                world_vertices, triangles, mouth, own("eyeBlinkLeft"), own("eyeBlinkRight")
            )
        except HeadError:
            raise error from None


# ---------------------------------------------------------------- the thesis path: a folder of OBJ models


def obj_folder_keys(head: bpy.types.Object, folder: str | Path) -> dict[str, np.ndarray]:
    """TR_viseme_* deltas (and TR_emotion_*) from the thesis's homeomorphic OBJ models (obj_folder.py)."""
    return obj_folder.obj_folder_keys(folder, mesh.rest_coordinates(head), head.name)


# ---------------------------------------------------------------- building


def _unit_sets(
    head: bpy.types.Object, parts: list[bpy.types.Object], source: str, reference: ReferenceHead
) -> tuple[str, dict[str, dict[str, np.ndarray]], dict[str, np.ndarray] | None]:
    """(source used, object name -> ARKit unit deltas, the head's landmarks where they were needed) for
    the head and its parts."""
    objects = [head, *parts]
    own = {obj.name: own_arkit_units(obj) for obj in objects}
    if source in ("auto", "arkit") and has_arkit_basis(match_arkit_keys(list(own[head.name]))):
        units = dict(own)
        for part in parts:  # a part without keys of its own may still be a piece of the reference
            if not units[part.name]:
                units[part.name] = reference_units(part, reference) or {}
        return "arkit", units, None
    if source == "arkit":
        found = ", ".join(sorted(own[head.name])) or "none"
        raise HeadError(
            f"{head.name!r} lacks ARKit shape keys (found: {found}); it needs at least jawOpen, mouthClose, "
            "mouthFunnel, mouthPucker and 20 units. Use source 'auto' to transfer them from the reference."
        )
    if source in ("auto", "reference"):
        head_units = reference_units(head, reference)
        if head_units is not None:
            units = {head.name: head_units}
            for part in parts:
                units[part.name] = reference_units(part, reference) or own[part.name]
            return "reference", units, None
        if source == "reference":
            raise HeadError(f"{head.name!r} is not the reference head (or a piece of MakeHuman's base mesh).")
    return "transfer", *_transfer_units(head, parts, reference)


def _validate_head(head: bpy.types.Object) -> None:
    if head is None or head.type != "MESH":
        raise HeadError("Select a mesh object as the head; shape keys can only be built on meshes.")
    if len(head.data.polygons) == 0:
        raise HeadError(f"{head.name!r} has no faces; a head needs a surface to build shape keys on.")
    if head.data.is_editmode or head.mode == "EDIT":
        raise HeadError(f"{head.name!r} is in Edit Mode; switch to Object Mode and build again.")


def build_shape_keys(
    head: bpy.types.Object,
    *,
    parts: list[bpy.types.Object] | None = None,
    source: str = "auto",
    obj_folder: str | Path | None = None,
    mapping_file: str | Path | None = None,
    empowered: bool = False,
    rho: float = 3.0,
    arkit_keys: bool = False,
) -> BuildReport:
    """Write TR_viseme_* (37), TR_emotion_* (6 + 6 mouth releases), blinks and brow raise on head and parts.

    source: "auto" (the head's own visemes of a known convention or of mapping_file, else its own ARKit
    keys, else the reference head's units when the mesh is a piece of it, else a transfer), "convention",
    "arkit", "reference", "transfer", or "obj_folder" (the thesis's homeomorphic OBJ models).
    empowered stores emotions as rho * (E - N) (thesis eq. 5.2). arkit_keys also writes the 52 units
    under Apple's names where the object has no such keys of its own.
    """
    _validate_head(head)
    _check_source(source, obj_folder)
    parts = _mesh_parts(head, parts)
    objects = [head, *parts]
    # Compute every array first: nothing is written until all of them exist and are sound.
    plan = _plan_keys(head, parts, source, obj_folder, mapping_file, arkit_keys)
    planned, warnings, key_sources = plan.planned, plan.warnings, plan.key_sources
    looks = plan_look_keys(head, parts, planned, plan.unit_sets, own_key_names(head))
    key_sources.update(looks.sources)
    warnings.extend(looks.warnings)
    missing = (
        ()
        if plan.source in ("obj_folder", "convention")
        else missing_units(plan.unit_sets.get(head.name, {}))
    )
    if missing:
        warnings.append(missing_units_warning(head.name, missing))
    if empowered:  # the emotions stored for keying by hand, thesis eq. 5.2
        planned = {name: empower(keys, rho) for name, keys in planned.items()}
    _check_planned(objects, planned)
    for obj in objects:
        for name in _write_keys(obj, planned[obj.name]):
            warnings.append(
                f"{obj.name!r} has a key of its own named {name!r}: it was left as it is, and ours was "
                f"built beside it as {owned_keys(obj)[name]!r}."
            )
    head.data[KEY_SOURCES_PROPERTY] = {
        key: key_sources[key] for key in planned[head.name] if key in key_sources
    }
    return BuildReport(
        head=head.name,
        source=plan.source,
        keys=tuple(planned[head.name]),
        objects=tuple(obj.name for obj in objects),
        missing_units=missing,
        warnings=tuple(warnings),
        key_sources=key_sources,
        convention=plan.convention,
    )


@dataclass(frozen=True, eq=False)
class _KeyPlan:
    """What the build writes: per object its keys' deltas, the units they came from, the warnings so far and
    where each key came from (and the convention's title, where a convention gave them)."""

    source: str
    planned: dict
    unit_sets: dict
    warnings: list
    key_sources: dict
    convention: str = ""


def _check_source(source: str, obj_folder) -> None:
    if source not in SOURCES:
        raise HeadError(f"Unknown shape-key source {source!r}; use one of {', '.join(SOURCES)}.")
    if source == "obj_folder" and obj_folder is None:
        raise HeadError(
            "The OBJ-folder source needs a folder of viseme models (a.obj, bpa.obj, ..., Neutral.obj)."
        )


def _plan_keys(head, parts, source: str, obj_folder, mapping_file, arkit_keys: bool) -> _KeyPlan:
    """The keys planned from the source the build uses: the head's own visemes of a convention, the
    thesis's OBJ models, or ARKit units (its own, the reference's, or transferred)."""
    objects = [head, *parts]
    recipes = load_recipes()
    match = _convention_match(head, source, mapping_file, obj_folder)
    if match is not None:
        planned, unit_sets, warnings, key_sources = _plan_from_convention(head, parts, match, recipes)
        return _KeyPlan("convention", planned, unit_sets, warnings, key_sources, match.convention.title)
    if source == "obj_folder" or (source == "auto" and obj_folder is not None):
        used_source, planned, unit_sets, warnings, key_sources = _plan_from_obj_folder(
            head, parts, obj_folder, recipes
        )
        return _KeyPlan(used_source, planned, unit_sets, warnings, key_sources)
    used_source, unit_sets, landmarks = _unit_sets(head, parts, source, load_reference_head())
    planned = {obj.name: _keys(unit_sets.get(obj.name, {}), obj, recipes) for obj in objects}
    if arkit_keys:
        _plan_arkit_keys(objects, unit_sets, planned)
    warnings = _hidden_face_warnings(head, parts, landmarks) if used_source != "arkit" else []
    return _KeyPlan(used_source, planned, unit_sets, warnings, dict.fromkeys(planned[head.name], used_source))


def _convention_match(head, source: str, mapping_file, obj_folder) -> ConventionMatch | None:
    """The head's own keys as a convention's shapes (or the user's mapping), when that is the source."""
    if source not in ("auto", "convention") or (source == "auto" and obj_folder is not None):
        return None
    names = own_key_names(head)
    if mapping_file:
        mapping = read_user_mapping(mapping_file)
        match = match_convention(names, mapping)
        if not match.shapes and not match.expressions:
            raise HeadError(
                f"None of the keys named in {mapping_file} is on {head.name!r}; check their spelling "
                "against the head's shape keys (names must match exactly)."
            )
        return match
    match = recognise_convention(names)
    if match is None and source == "convention":
        titles = ", ".join(convention.title for convention in load_conventions())
        raise HeadError(
            f"The shape keys of {head.name!r} follow none of the known viseme conventions ({titles}); "
            "give a mapping file (TOML) naming its keys, or choose another source."
        )
    return match


def _plan_from_convention(head, parts, match: ConventionMatch, recipes):
    """TR keys as weighted sums of the head's own keys; what the convention lacks from the other basis."""
    plans = plan_keys(match, recipes)
    warnings: list[str] = list(unmatched_names(match))
    fallback, unit_sets = None, {}
    if any(plan.units for plan in plans.values()):
        try:
            fallback, unit_sets, _ = _unit_sets(head, parts, "auto", load_reference_head())
        except LipSyncError as error:
            lacking = sorted(key for key, plan in plans.items() if plan.units)
            warnings.append(
                f"{len(lacking)} keys of {head.name!r} need what its {match.convention.title} lack "
                f"({', '.join(lacking[:4])}...), but no other basis could be built, so that part stays at "
                f"rest: {error}"
            )
    own_names = {name for plan in plans.values() for name in (*plan.shapes, *plan.release_of)}
    planned = {}
    for obj in [head, *parts]:
        own = own_key_deltas(obj, own_names)
        planned[obj.name] = convention_key_deltas(
            plans, own, unit_sets.get(obj.name, {}), len(obj.data.vertices)
        )
    key_sources = {key: plan.describe(fallback) for key, plan in plans.items()}
    return planned, unit_sets, warnings, key_sources


def _keys(units: dict[str, np.ndarray], obj: bpy.types.Object, recipes) -> dict[str, np.ndarray]:
    """The TR keys of obj from its ARKit units, by the recipes."""
    return key_deltas(units, len(obj.data.vertices), recipes=recipes)


def _plan_from_obj_folder(head, parts, obj_folder, recipes):
    """Visemes (and emotions) from the thesis's OBJ models; blinks and brows from an ARKit basis if any."""
    obj_keys = obj_folder_keys(head, obj_folder)
    warnings: list[str] = []
    try:
        basis, unit_sets, _ = _unit_sets(head, parts, "auto", load_reference_head())
    except HeadError as error:
        basis, unit_sets = "nothing", {}
        warnings.append(f"No ARKit basis on {head.name!r} for blinks and brows, so they stay still: {error}")
    planned = {
        obj.name: _keys(unit_sets[obj.name], obj, recipes) if unit_sets.get(obj.name) else {}
        for obj in [head, *parts]
    }
    planned[head.name].update(obj_keys)
    for part in parts:  # the models move the head only; parts keep the visemes' names at rest
        for key_name in obj_keys:
            planned[part.name].setdefault(key_name, np.zeros((len(part.data.vertices), 3), np.float32))
    key_sources = {key: "obj_folder" if key in obj_keys else basis for key in planned[head.name]}
    return "obj_folder", planned, unit_sets, warnings, key_sources


def _plan_arkit_keys(objects, unit_sets, planned) -> None:
    """The 52 units under Apple's names, where an object has no such key of its own."""
    for obj in objects:
        own_names = set(own_arkit_units(obj))
        units = unit_sets.get(obj.name, {})
        zeros = np.zeros((len(obj.data.vertices), 3), np.float32)
        for unit in ARKIT_UNITS:
            if unit not in own_names:
                planned[obj.name][unit] = units.get(unit, zeros)


def _hidden_face_warnings(
    head: bpy.types.Object, parts: list[bpy.types.Object], landmarks: dict[str, np.ndarray] | None
) -> list[str]:
    """A warning when other pieces of the head's mesh stand over much of its face (helper geometry)."""
    world_vertices, triangles = mesh.world_rest_coordinates(head), mesh.triangles(head)
    if landmarks is None:
        if len(np.unique(connected_pieces(len(world_vertices), triangles)[triangles[:, 0]])) < 2:
            return []  # one piece: nothing else of the mesh can hide the face, no landmarks needed
        try:
            landmarks = head_landmarks(head, parts)
        except HeadError:
            return []
    share = hidden_face_share(world_vertices, triangles, landmarks)
    if share < HIDDEN_FACE_WARNING:
        return []
    return [
        f"{share:.0%} of {head.name!r}'s face is hidden behind other pieces of its mesh (helper, hair or "
        "clothing geometry?): renders will not show it speaking. Delete those pieces, or separate them "
        "(Edit Mode, Mesh > Separate > By Loose Parts) and hide them."
    ]


def _check_planned(objects, planned) -> None:
    for obj in objects:
        for key_name, deltas in planned[obj.name].items():
            if deltas.shape != (len(obj.data.vertices), 3) or not np.isfinite(deltas).all():
                raise HeadError(f"Key {key_name} for {obj.name!r} came out malformed; nothing was changed.")


def _write_keys(obj: bpy.types.Object, deltas_by_key: dict[str, np.ndarray]) -> list[str]:
    """Replace our keys on obj (those our mark lists); keep every other key, its value, drivers and
    animation. A user's own key already holding one of our names keeps it, and ours is written beside it
    under a free name; returns those names."""
    mesh = obj.data
    owned = owned_keys(obj)
    if mesh.shape_keys is None:
        obj.shape_key_add(name="Basis", from_mix=False)
    shape_keys = mesh.shape_keys
    blocks = shape_keys.key_blocks
    # Drop our own keys that this build does not write (e.g. ARKit keys no longer asked for).
    for ours, name in owned.items():
        block = blocks.get(name)
        if ours not in deltas_by_key and block is not None and block != shape_keys.reference_key:
            obj.shape_key_remove(block)
    basis = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    shape_keys.reference_key.points.foreach_get("co", basis)
    written, taken = {}, []
    for ours, deltas in deltas_by_key.items():
        name = owned.get(ours)
        if name is None or name not in blocks:
            if ours in blocks:
                taken.append(ours)  # the user's own key of that name
            name = free_name(blocks, ours)
        block = blocks.get(name)
        if block is None:
            block = obj.shape_key_add(name=name, from_mix=False)
            block.value = 0.0  # Blender 5.0 adds new keys at full weight
        block.relative_key = shape_keys.reference_key
        block.points.foreach_set("co", basis + deltas.astype(np.float32).ravel())
        written[ours] = block.name
    mark_owned(obj, written)
    mesh.pop(LEGACY_ARKIT_PROPERTY, None)
    mesh.update()
    return taken
