"""The TR_eye_<eye>_look_<way> keys: each turns one eye 20 degrees one way at full weight and lets its lids
follow (eyeLookDown lowers the upper lid).

Built with the other keys, from the best the head has: its own look keys (ARKit eyeLook*, CharMorph
Look_*, VRM look_*; a key that turns both eyes is split at the head's midline), else the ARKit units the
build used (the reference's, transferred, or the head's own). Each key is scaled by the turn measured on
the eyeball it moves, so weight 1 means 20 degrees on every head; painted eyes show no ball and are taken
to turn painted_key_degrees. An eye that is an object of its own turns as an object (blender/living.py),
so its key moves only the lids; an eyeball that is an island of the head's mesh is turned rigidly about
its fitted centre.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import bpy
import numpy as np

from ..core.base.model import EYE_SIDES, LOOK_DIRECTIONS, LOOK_KEY_DEGREES, look_key_name
from ..core.faces.eyes import ARKIT_LOOK_UNITS, own_look_keys, rigid_turn, round_pieces, turn_degrees
from ..core.motion.living.parameters import living_parameters
from . import mesh
from .living_rig import LivingRig, find_rig

MEASURABLE_TURN = 1.0  # degrees: a key turning its eyeball less than this has painted eyes, for our purpose


@dataclass
class LookKeys:
    sources: dict[str, str] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)


def plan_look_keys(
    head: bpy.types.Object,
    parts: list[bpy.types.Object],
    planned: dict[str, dict[str, np.ndarray]],
    unit_sets: dict[str, dict[str, np.ndarray]],
    own_names: list[str],
) -> LookKeys:
    """Add the eight look keys to planned (object name -> key -> local deltas); say where they came from."""
    result = LookKeys()
    rig = find_rig(head, parts)
    if not rig.eyes:
        result.warnings.extend(rig.warnings)
        return result
    objects = [head, *parts]
    world = {obj.name: mesh.world_rest_coordinates(obj).astype(np.float64) for obj in objects}
    islands = _islands(rig, world[head.name], head)
    own = own_look_keys(own_names)
    painted = living_parameters()["eyes"]["painted_key_degrees"]
    for eye in EYE_SIDES:
        for way in LOOK_DIRECTIONS:
            key = look_key_name(eye, way)
            deltas, source = _source_deltas(rig, objects, world, unit_sets, own, eye, way)
            if deltas is None and rig.eyes_turn_by != "objects" and eye not in islands:
                continue
            if deltas is None:
                deltas = {obj.name: np.zeros_like(world[obj.name]) for obj in objects}
                source = "rigid turn" if eye in islands else "the eye object turns"
            measured = _measured_turn(rig, world, deltas, islands, eye, way)
            scale = LOOK_KEY_DEGREES / (measured if measured > MEASURABLE_TURN else painted)
            for obj in objects:
                moved = deltas[obj.name] * scale
                eye_object = rig.eyes[eye].object_name
                if obj.name in (rig.eyes[other].object_name for other in EYE_SIDES) and eye_object:
                    continue  # eye objects turn as objects: no key of theirs
                if obj is head and eye in islands:
                    indices = islands[eye]
                    local = rig.to_head(world[head.name][indices])
                    centre = rig.to_head(rig.eyes[eye].centre)
                    moved[indices] = rigid_turn(local, centre, way) @ rig.frame.T
                planned.setdefault(obj.name, {})[key] = mesh.world_deltas_to_local(obj, moved)
            how = (
                f"{measured:.1f} degrees at 1, measured"
                if measured > MEASURABLE_TURN
                else f"{painted:g} taken"
            )
            result.sources[key] = f"{source} x{scale:.2f} ({how})"
    return result


def _islands(rig: LivingRig, vertices: np.ndarray, head: bpy.types.Object) -> dict[str, np.ndarray]:
    """Vertex indices of each eyeball that is an island of the head's own mesh."""
    if rig.eyes_turn_by != "keys":
        return {}
    size = float(np.max(vertices.max(axis=0) - vertices.min(axis=0)))
    balls = round_pieces(vertices, mesh.triangles(head), size)
    found = {}
    for side, eye in rig.eyes.items():
        near = [ball for ball in balls if np.linalg.norm(ball.centre - eye.centre) < 0.5 * ball.radius]
        if near:
            found[side] = near[0].indices
    return found


def _source_deltas(rig, objects, world, unit_sets, own, eye: str, way: str):
    """(object name -> world deltas of the key to start from, its description), or (None, "")."""
    if (eye, way) in own:
        name, both = own[(eye, way)]
        deltas = {}
        for obj in objects:
            deltas[obj.name] = _own_world_deltas(obj, name, world[obj.name])
            if both:
                across = rig.to_head(world[obj.name])[:, 0]
                deltas[obj.name][(across > 0) != (eye == "left")] = 0.0
        if any(np.abs(d).max(initial=0.0) > 0 for d in deltas.values()):
            return deltas, f"own keys: {name}" + (f" ({eye} half)" if both else "")
    unit = ARKIT_LOOK_UNITS[(eye, way)]
    if any(unit in unit_sets.get(obj.name, {}) for obj in objects):
        deltas = {}
        for obj in objects:
            local = unit_sets.get(obj.name, {}).get(unit)
            linear = mesh.world_matrix(obj)[:3, :3]
            deltas[obj.name] = (
                np.zeros_like(world[obj.name]) if local is None else np.asarray(local, np.float64) @ linear.T
            )
        return deltas, f"{unit} of the build's ARKit basis"
    return None, ""


def _own_world_deltas(obj: bpy.types.Object, name: str, world: np.ndarray) -> np.ndarray:
    keys = obj.data.shape_keys
    block = keys.key_blocks.get(name) if keys is not None else None
    if block is None:
        return np.zeros_like(world)
    count = len(obj.data.vertices)
    local = mesh.read_coordinates(block.points, count) - mesh.read_coordinates(
        block.relative_key.points, count
    )
    return local.astype(np.float64) @ mesh.world_matrix(obj)[:3, :3].T


def _measured_turn(rig: LivingRig, world, deltas, islands, eye: str, way: str) -> float:
    """Degrees the key turns the eye's ball toward `way` (0 where no ball moves with it)."""
    target = rig.eyes[eye]
    if target.object_name and target.object_name in deltas:
        points, moved = world[target.object_name], deltas[target.object_name]
    elif eye in islands:
        points, moved = world[rig.head][islands[eye]], deltas[rig.head][islands[eye]]
    else:
        return 0.0
    if np.abs(moved).max(initial=0.0) < 1e-9:
        return 0.0
    centre = rig.to_head(target.centre)
    return turn_degrees(rig.to_head(points), moved @ rig.frame, centre, way)
