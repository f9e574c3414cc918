"""Characters whose faces bones move, built from the shared heads, for the face-rig tests and the manual's
pictures (the heads are read where they are, never copied).

- jaw_bone_character: MakeHuman's expression-units head with its own shape keys taken off, on a game
  armature (neck, head, jaw): the jaw's vertex weights and hinge are fitted to the artist's own mouth-open
  key before it is removed, so the jaw opens as that artist's mouth does; the lower teeth and tongue
  follow the jaw, the upper teeth the head, and the eyes are bone children of the head.
  default_jaw_bone_character: the same armature on the default head (fitted to its own jawOpen unit).
- rigify_face_character: the default head on Rigify's face rig, generated from Rigify's human meta-rig after
  its face bones are fitted to the head's landmarks (a similarity, then a smooth warp); the skin's weights
  come from nearness to the deform bones, with the jaw's and the lids' shares of every vertex read from
  the default head's own jawOpen and blink units; teeth, tongue and eyes are bone children of Rigify's
  ORG bones, the lashes weighted as the skin beside them.

Run alone, it saves both characters as .blend files to look at: python -m lab.kit.rigged_heads OUT_FOLDER
"""

from __future__ import annotations

import contextlib
import io
import sys
from pathlib import Path

import bpy
import numpy as np

from lab.kit.heads_on_disk import HEADS
from turkish_lipsync.blender import heads, mesh, shapekeys
from turkish_lipsync.core.faces.closest import nearest_vertices
from turkish_lipsync.core.faces.measure import FaceMeasure
from turkish_lipsync.core.faces.reference import load_reference_head

MAKEHUMAN_UNITS_HEAD = HEADS / "makehuman" / "mh_head_expression_units.glb"


# ---------------------------------------------------------------- a game character with a jaw bone


def jaw_bone_character(context, path: Path = MAKEHUMAN_UNITS_HEAD) -> dict[str, bpy.types.Object]:
    """{"head", "armature", "teeth_upper", "teeth_lower", "tongue", "eye_L", "eye_R"} of the imported head on
    its armature, with no shape keys left on any of them."""
    objects = {obj.name: obj for obj in heads.import_head(path)}
    opened = _key_deltas(objects["head"], "mouth-open")
    for obj in objects.values():
        if obj.type == "MESH" and obj.data.shape_keys is not None:
            obj.shape_key_clear()
    armature = _on_game_armature(
        context,
        objects["head"],
        opened,
        {"jaw": [objects["teeth_lower"], objects["tongue"]], "head": [objects["teeth_upper"]]},
        [objects["eye_L"], objects["eye_R"]],
    )
    return {**objects, "armature": armature}


def makehuman_with_our_keys(path: Path = MAKEHUMAN_UNITS_HEAD) -> bpy.types.Object:
    """The same head speaking through shape keys instead: its own keys taken off, ours built on it (the
    shape-key path the jaw bone is measured against)."""
    objects = heads.import_head(path)
    for obj in objects:
        if obj.type == "MESH" and obj.data.shape_keys is not None:
            obj.shape_key_clear()
    head = heads.find_head(objects)
    shapekeys.build_shape_keys(head)
    return head


def default_jaw_bone_character(context) -> dict[str, bpy.types.Object]:
    """The default head (its skin, eyes, teeth and lashes; no shape keys) on the same game armature, its jaw
    fitted to the default head's own jawOpen unit: for pictures, as it has skin and eyes to show."""
    parts = heads.create_reference_head(context)
    reference = load_reference_head()
    opened = reference.units["jawOpen"][reference.parts["skin"]].astype(np.float64)
    armature = _on_game_armature(
        context,
        parts["head"],
        opened,
        {"jaw": [parts["lower_teeth"], parts["tongue"]], "head": [parts["upper_teeth"]]},
        [parts["left_eye"], parts["right_eye"]],
    )
    for lashes in ("left_eyelashes", "right_eyelashes"):
        _weigh(parts[lashes], armature, {"head": np.ones(len(parts[lashes].data.vertices))})
    return {**parts, "armature": armature}


def _on_game_armature(context, head, opened: np.ndarray, followers: dict, eyes: list) -> bpy.types.Object:
    """A neck, head and jaw armature under the head: the jaw's hinge and the skin's jaw weights fitted to the
    mouth opening given (world displacements of the head's vertices); followers weighted wholly to a bone,
    eyes bone children of the head."""
    rest = mesh.world_rest_coordinates(head).astype(np.float64)
    hinge, angle = jaw_hinge(rest, opened)
    jaw_share = _rotation_share(rest, opened, hinge, angle)
    low, high = rest.min(axis=0), rest.max(axis=0)
    chin = rest[np.argmax(np.linalg.norm(opened, axis=1))]
    pivot = np.array([0.0, hinge[1] + 0.3 * (high[1] - hinge[1]), hinge[2] - 0.01])
    armature = _armature(
        context,
        "GameRig",
        {
            "neck": (np.array([0.0, pivot[1], low[2]]), pivot, None),
            "head": (pivot, np.array([0.0, pivot[1], high[2]]), "neck"),
            "jaw": (hinge, chin, "head"),
        },
    )
    neck_share = np.clip((chin[2] - 0.03 - rest[:, 2]) / max(chin[2] - 0.03 - low[2], 1e-6), 0.0, 1.0)
    neck_share *= 1.0 - jaw_share
    _weigh(head, armature, {"jaw": jaw_share, "neck": neck_share, "head": 1.0 - jaw_share - neck_share})
    for bone, objects in followers.items():
        for obj in objects:
            _weigh(obj, armature, {bone: np.ones(len(obj.data.vertices))})
    for eye in eyes:
        _bone_child(eye, armature, "head")
    context.view_layer.update()
    return armature


def _key_deltas(obj: bpy.types.Object, name: str) -> np.ndarray:
    """World displacements of one of the object's own shape keys."""
    keys = obj.data.shape_keys
    count = len(obj.data.vertices)
    moved = mesh.read_coordinates(keys.key_blocks[name].points, count)
    return (moved - mesh.read_coordinates(keys.reference_key.points, count)).astype(
        np.float64
    ) @ mesh.world_matrix(obj)[:3, :3].T


def _rotation_share(rest: np.ndarray, deltas: np.ndarray, hinge: np.ndarray, angle: float) -> np.ndarray:
    """How much of the turn each vertex makes: its motion over the motion a vertex turning fully makes."""
    radius = np.linalg.norm((rest - hinge)[:, 1:], axis=1)
    return np.clip(np.linalg.norm(deltas, axis=1) / np.maximum(abs(angle) * radius, 1e-9), 0.0, 1.0)


# ---------------------------------------------------------------- Rigify's face rig on the default head

# Landmarks of the default head and the meta-rig's points at the same places of the face: (bone, end).
RIGIFY_LANDMARKS = {
    "mouth_corner_left": ("lip.T.L.001", "tail"),
    "mouth_corner_right": ("lip.T.R.001", "tail"),
    "upper_lip": ("lip.T.L", "head"),
    "lower_lip": ("lip.B.L", "head"),
    "nose_tip": ("nose.002", "head"),
    "chin": ("chin.001", "head"),
    "eye_outer_left": ("lid.T.L", "head"),
    "eye_inner_left": ("lid.B.L", "head"),
    "eye_outer_right": ("lid.T.R", "head"),
    "eye_inner_right": ("lid.B.R", "head"),
    "brow_left": ("brow.T.L.002", "head"),
    "brow_right": ("brow.T.R.002", "head"),
}
# Deform bones of the lower face (they follow the jaw) and of each upper lid.
LOWER_FACE = ("DEF-jaw", "DEF-chin", "DEF-lip.B")
UPPER_LIDS = {"left": "DEF-lid.T.L", "right": "DEF-lid.T.R"}


def rigify_available() -> bool:
    import addon_utils

    try:
        addon_utils.enable("rigify", default_set=True, handle_error=None)
    except Exception:  # not shipped with this Blender
        return False
    return hasattr(bpy.ops.pose, "rigify_generate")


def rigify_face_character(context) -> dict[str, bpy.types.Object]:
    """The default head (no shape keys) on a Rigify rig generated for it: {"head", "rig", parts...}."""
    if not rigify_available():
        raise RuntimeError("this Blender does not ship the Rigify add-on")
    parts = heads.create_reference_head(context)
    head = parts["head"]
    reference = load_reference_head()
    skin = reference.parts["skin"]
    landmarks = {name: reference.vertices[index] for name, index in reference.landmark_vertices.items()}
    hinge, _angle = jaw_hinge(reference.vertices[skin].astype(np.float64), reference.units["jawOpen"][skin])
    bpy.ops.object.armature_human_metarig_add()
    metarig = context.active_object
    _fit_metarig(metarig, landmarks, hinge)
    with contextlib.redirect_stdout(io.StringIO()):
        bpy.ops.pose.rigify_generate()
    rig = next(obj for obj in bpy.data.objects if obj.type == "ARMATURE" and obj is not metarig)
    metarig.hide_set(True)
    metarig.hide_render = True
    rest = mesh.world_rest_coordinates(head).astype(np.float64)
    jaw_share = _reference_share(reference.units["jawOpen"][skin])
    lid_shares = {
        side: _reference_share(reference.units[f"eyeBlink{side.title()}"][skin]) for side in ("left", "right")
    }
    groups = _weights_from_bones(rig, rest, jaw_share, lid_shares)
    _weigh(head, rig, groups)
    for lashes in ("left_eyelashes", "right_eyelashes"):
        _follow_skin(parts[lashes], rest, groups, rig)
    for part, bone in (
        ("upper_teeth", "ORG-teeth.T"),
        ("lower_teeth", "ORG-teeth.B"),
        ("tongue", "ORG-teeth.B"),
        ("left_eye", "ORG-eye.L"),
        ("right_eye", "ORG-eye.R"),
    ):
        _bone_child(parts[part], rig, bone)
    context.view_layer.update()
    return {**parts, "rig": rig, "metarig": metarig}


def _fit_metarig(metarig: bpy.types.Object, landmarks: dict[str, np.ndarray], hinge: np.ndarray) -> None:
    """The meta-rig scaled and moved onto the face (a similarity on the landmarks), then its face bones
    warped the rest of the way (Gaussian radial basis over the landmarks' residuals), its jaw's joints
    (jaw.L and jaw.R, the heads Rigify hinges the jaw at) onto the hinge of the head's own jawOpen."""
    bones = metarig.data.bones
    names = [name for name in RIGIFY_LANDMARKS if name in landmarks]
    ends = [RIGIFY_LANDMARKS[name] for name in names]
    source = np.array([np.array(getattr(bones[bone], f"{end}_local")) for bone, end in ends])
    target = np.array([landmarks[name] for name in names])
    scale = np.sqrt(((target - target.mean(0)) ** 2).sum() / ((source - source.mean(0)) ** 2).sum())
    shift = target.mean(0) - scale * source.mean(0)
    width = float(np.linalg.norm(target[0] - target[1]))  # the mouth's width
    joints = np.array([np.array(bones[f"jaw.{side}"].head_local) for side in ("L", "R")])
    source = np.vstack([source, joints])
    target = np.vstack([target, [[scale * x + shift[0], hinge[1], hinge[2]] for x in joints[:, 0]]])
    fitted = scale * source + shift
    kernel = np.exp(-((np.linalg.norm(fitted[:, None] - fitted[None], axis=2) / width) ** 2))
    # Regularised: landmarks a fraction of the kernel's width apart would otherwise ask for huge opposite
    # weights, which throw the bones between them far off.
    weights = np.linalg.solve(kernel + 0.1 * np.eye(len(fitted)), target - fitted)
    bpy.context.view_layer.objects.active = metarig
    bpy.ops.object.mode_set(mode="EDIT")
    face = set(_descendants(metarig.data.edit_bones["face"]))
    # Every end read before any is written: a connected bone's head moves with its parent's tail.
    ends = {
        (bone.name, end): np.array(getattr(bone, end))
        for bone in metarig.data.edit_bones
        for end in ("head", "tail")
    }
    for (name, end), point in ends.items():
        point = scale * point + shift
        if name in face:
            distance = np.linalg.norm(fitted - point, axis=1) / width
            point = point + np.exp(-(distance**2)) @ weights
        setattr(metarig.data.edit_bones[name], end, tuple(point))
    bpy.ops.object.mode_set(mode="OBJECT")


def _descendants(bone) -> list[str]:
    found = [bone.name]
    for child in bone.children:
        found += _descendants(child)
    return found


def _reference_share(deltas: np.ndarray) -> np.ndarray:
    """Each vertex's motion in a unit over the unit's largest (a part's share of a rigid motion)."""
    size = np.linalg.norm(deltas, axis=1)
    return np.clip(size / max(np.percentile(size, 99.5), 1e-9), 0.0, 1.0)


def _weights_from_bones(rig, rest, jaw_share, lid_shares) -> dict[str, np.ndarray]:
    """Skin weights: the jaw's share to the lower face's deform bones, each lid's share to its upper lid's,
    the rest to every other deform bone of the head, each group by inverse squared distance to its bones."""
    low, high = rest.min(axis=0), rest.max(axis=0)
    matrix = np.array(rig.matrix_world)
    face = [
        bone.name
        for bone in rig.data.bones
        if bone.use_deform
        and bone.name.startswith("DEF-")
        and not bone.name.startswith("DEF-tongue")
        and np.all(
            np.abs(matrix[:3, :3] @ bone.head_local + matrix[:3, 3] - (low + high) / 2) <= (high - low) / 2
        )
    ]
    lower = [name for name in face if name.startswith(LOWER_FACE)]
    lids = {side: [name for name in face if name.startswith(prefix)] for side, prefix in UPPER_LIDS.items()}
    lidded = {name for names in lids.values() for name in names}
    others = [name for name in face if name not in lower and name not in lidded]
    rest_share = np.clip(1.0 - jaw_share - lid_shares["left"] - lid_shares["right"], 0.0, 1.0)
    groups: dict[str, np.ndarray] = {}
    for names, share in (
        (lower, jaw_share),
        (lids["left"], lid_shares["left"]),
        (lids["right"], lid_shares["right"]),
        (others, rest_share),
    ):
        for name, weights in _inverse_distance(rig, names, rest).items():
            groups[name] = groups.get(name, 0.0) + share * weights
    return groups


def _inverse_distance(rig, names: list[str], points: np.ndarray, nearest: int = 4) -> dict[str, np.ndarray]:
    """Weights of the points to the named bones (summing to 1): inverse squared distance to each bone's
    segment, over the nearest few bones."""
    matrix = np.array(rig.matrix_world)
    heads_ = np.array([matrix[:3, :3] @ rig.data.bones[n].head_local + matrix[:3, 3] for n in names])
    tails = np.array([matrix[:3, :3] @ rig.data.bones[n].tail_local + matrix[:3, 3] for n in names])
    along = tails - heads_
    share = np.einsum("pbc,bc->pb", points[:, None] - heads_[None], along) / np.maximum(
        (along**2).sum(1), 1e-12
    )
    closest = heads_[None] + np.clip(share, 0, 1)[..., None] * along[None]
    distance = np.linalg.norm(points[:, None] - closest, axis=2)
    weights = 1.0 / np.maximum(distance, 1e-4) ** 2
    if len(names) > nearest:
        cut = np.partition(weights, -nearest, axis=1)[:, -nearest][:, None]
        weights = np.where(weights >= cut, weights, 0.0)
    weights /= weights.sum(axis=1, keepdims=True)
    return {name: weights[:, column] for column, name in enumerate(names)}


def _follow_skin(part: bpy.types.Object, skin_rest: np.ndarray, groups: dict, rig: bpy.types.Object) -> None:
    """The part weighted as the skin vertex nearest each of its vertices (lashes follow their lids)."""
    nearest, _ = nearest_vertices(mesh.world_rest_coordinates(part), skin_rest)
    _weigh(part, rig, {name: weights[nearest] for name, weights in groups.items()})


# ---------------------------------------------------------------- shared


def _armature(context, name: str, bones: dict) -> bpy.types.Object:
    """An armature of the given bones: name -> (head, tail, parent name)."""
    data = bpy.data.armatures.new(name)
    armature = bpy.data.objects.new(name, data)
    context.scene.collection.objects.link(armature)
    context.view_layer.objects.active = armature
    bpy.ops.object.mode_set(mode="EDIT")
    for bone_name, (head, tail, parent) in bones.items():
        bone = data.edit_bones.new(bone_name)
        bone.head, bone.tail = tuple(head), tuple(tail)
        if parent is not None:
            bone.parent = data.edit_bones[parent]
    bpy.ops.object.mode_set(mode="OBJECT")
    return armature


def _weigh(obj: bpy.types.Object, armature: bpy.types.Object, groups: dict) -> None:
    """Vertex groups of the given weights (name -> per-vertex array), an armature modifier, the armature as
    the object's parent (the object stays where it is)."""
    for name, weights in groups.items():
        weights = np.broadcast_to(np.asarray(weights, np.float64), (len(obj.data.vertices),))
        group = obj.vertex_groups.get(name) or obj.vertex_groups.new(name=name)
        for value in np.unique(np.round(weights[weights > 1e-4], 3)):
            group.add(np.flatnonzero(np.round(weights, 3) == value).tolist(), float(value), "REPLACE")
    modifier = obj.modifiers.new("Armature", "ARMATURE")
    modifier.object = armature
    world = obj.matrix_world.copy()
    obj.parent = armature
    obj.matrix_world = world


def _bone_child(obj: bpy.types.Object, armature: bpy.types.Object, bone: str) -> None:
    world = obj.matrix_world.copy()
    obj.parent = armature
    obj.parent_type = "BONE"
    obj.parent_bone = bone
    bpy.context.view_layer.update()
    obj.matrix_world = world


if __name__ == "__main__":
    folder = Path(sys.argv[-1] if len(sys.argv) > 1 else "out")
    folder.mkdir(parents=True, exist_ok=True)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    jaw_bone_character(bpy.context)
    bpy.ops.wm.save_as_mainfile(filepath=str(folder.resolve() / "jaw_bone_character.blend"))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    rigify_face_character(bpy.context)
    bpy.ops.wm.save_as_mainfile(filepath=str(folder.resolve() / "rigify_face_character.blend"))
    print(f"Saved the characters in {folder}")


LANDMARKS = ("mouth_corner_left", "upper_lip", "lower_lip", "upper_lip_inner", "lower_lip_inner", "chin",
             "brow_left", "nose_tip")  # fmt: skip


def jaw_hinge(vertices: np.ndarray, deltas: np.ndarray) -> tuple[np.ndarray, float]:
    """The hinge (on the middle plane) and angle of the turn about the left-right axis that best gives the
    vertices the unit moves most their motion: d_y = -a z + b, d_z = a y - c, a the angle."""
    size = np.linalg.norm(deltas, axis=1)
    moving = size > 0.5 * size.max()
    y, z = vertices[moving, 1], vertices[moving, 2]
    ones, zeros = np.ones_like(y), np.zeros_like(y)
    system = np.vstack([np.column_stack([-z, ones, zeros]), np.column_stack([y, zeros, -ones])])
    observed = np.concatenate([deltas[moving, 1], deltas[moving, 2]])
    (angle, b, c), *_ = np.linalg.lstsq(system, observed, rcond=None)
    return np.array([0.0, c / angle, b / angle]), float(angle)


def evaluated_world(obj: bpy.types.Object) -> np.ndarray:
    """(N, 3) world coordinates of obj's evaluated mesh (shape keys, armature and all)."""
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    shape = evaluated.to_mesh()
    try:
        local = mesh.read_coordinates(shape.vertices, len(shape.vertices)).astype(np.float64)
    finally:
        evaluated.to_mesh_clear()
    matrix = np.array(obj.matrix_world, np.float64)
    return local @ matrix[:3, :3].T + matrix[:3, 3]


def lip_gaps(head: bpy.types.Object, frames) -> np.ndarray:
    """The lips' opening at the middle of the mouth on the evaluated mesh at each scene frame (metres)."""
    rest = mesh.world_rest_coordinates(head).astype(np.float64)
    polygons = [list(polygon.vertices) for polygon in head.data.polygons]
    measure = FaceMeasure(rest, polygons, shapekeys.head_landmarks(head))
    gaps = []
    for frame in frames:
        bpy.context.scene.frame_set(int(frame))
        gaps.append(measure.lip_aperture(evaluated_world(head) - rest))
    return np.array(gaps)


def phone_frames(timeline, letters: str, fps: float = 25) -> list[tuple[str, np.ndarray]]:
    """(letter, the scene frames it covers) of every phone of those letters (the scene starts at frame 1)."""
    return [
        (phone.letter, np.arange(int(np.floor(phone.start * fps)), int(np.ceil(phone.end * fps)) + 1) + 1)
        for phone in timeline.phones
        if phone.letter in letters
    ]
