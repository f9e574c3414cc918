"""The kit of test heads whose motion is known: heads of the kinds users bring, made from the ones we have.

The default head with its parts joined into one mesh and bent into another face (its truth: the
reference's own units bent alike), and the shared heads (Vitruvian, MakeHuman) with their parts joined,
welded, or with lash cards, single lashes and eye shells added (lab/kit/joined_heads.py; their truth: the
artists' own keys). lab/measure/parts.py measures transfers onto them, tools/figures/face_report.py --kit
renders one, and the tests build them too. The shared heads are read with Blender (bpy, imported where
needed); the default head's parts need no Blender.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from lab.kit import joined_heads
from lab.kit.bent_faces import reshape_face
from lab.kit.heads_on_disk import HEADS
from turkish_lipsync.core.faces.head_parts import find_parts
from turkish_lipsync.core.faces.landmarks import find_landmarks
from turkish_lipsync.core.faces.measure import displacement_cosine, edge_stretch, piece_motion
from turkish_lipsync.core.faces.reference import load_reference_head
from turkish_lipsync.core.faces.registration import similarity_fit
from turkish_lipsync.core.faces.topology import edge_graph
from turkish_lipsync.core.faces.transfer import reference_landmarks_of, transfer_units

if TYPE_CHECKING:
    import bpy

KEYS = ("jawOpen", "eyeBlinkLeft")
# The artists' keys that show our units, per shared head (the rest of shapekeys/artist_comparisons.toml).
ARTIST_KEYS = {
    "vitruvian": {"jawOpen": "Mouth_Large_Opened", "eyeBlinkLeft": "Eyes_Closed_Left"},
    "makehuman": {"jawOpen": "mouth-open", "eyeBlinkLeft": "eye-left-closure"},
}
# The default head bent into another face (lab/measure/transfer.py's bends): a wider jaw, a longer chin,
# a bigger nose, eyes further apart, a sloping forehead.
BENDS = {"jaw": 0.15, "chin": 0.015, "nose": 0.006, "eyes": 0.004, "forehead": 0.01}


def world_key_deltas(obj: bpy.types.Object) -> dict[str, np.ndarray]:
    """Every shape key of obj as world-space displacements from its reference key."""
    from turkish_lipsync.blender import mesh

    keys = obj.data.shape_keys
    if keys is None:
        return {}
    linear = mesh.world_matrix(obj)[:3, :3]
    count = len(obj.data.vertices)
    rest = mesh.read_coordinates(keys.reference_key.points, count).astype(np.float64)
    return {
        block.name: (mesh.read_coordinates(block.points, count) - rest) @ linear.T
        for block in keys.key_blocks
        if block != keys.reference_key
    }


def glb_parts(path: Path, keys: dict[str, str]) -> dict:
    """part name -> (world vertices, triangles, our unit -> the artist key's world deltas) of a glb's
    meshes, the biggest first (Blender imports it)."""
    import bpy

    from turkish_lipsync.blender import heads, mesh

    bpy.ops.wm.read_factory_settings(use_empty=True)
    objects = sorted(
        (obj for obj in heads.import_head(path) if obj.type == "MESH"),
        key=lambda obj: -len(obj.data.vertices),
    )
    parts = {}
    for obj in objects:
        deltas = world_key_deltas(obj)
        truth = {unit: deltas[name].astype(np.float64) for unit, name in keys.items() if name in deltas}
        parts[obj.name] = (mesh.world_rest_coordinates(obj).astype(np.float64), mesh.triangles(obj), truth)
    return parts


def default_head_parts() -> dict:
    """The default head's parts (the reference's, as create_reference_head makes them), bent by BENDS."""
    reference = load_reference_head()
    parts = {}
    for part in ("skin", *(name for name in reference.parts if name != "skin")):
        indices, vertices, quads = reference.part_mesh(part)
        bent = reshape_face(vertices, reference.landmarks, BENDS)
        truth = {
            key: reshape_face(vertices + reference.units[key][indices], reference.landmarks, BENDS) - bent
            for key in KEYS
        }
        parts[part] = (bent, np.concatenate((quads[:, [0, 1, 2]], quads[:, [0, 2, 3]])), truth)
    return parts


def kit_heads(names: list[str] | None = None) -> list[joined_heads.KitHead]:
    made = []
    default = joined_heads.joined_head("default head, parts joined, bent", default_head_parts())
    made.append(default)
    made.append(
        default.welded(
            [("lower_teeth", "tongue", False), ("upper_teeth", "lower_teeth", True)],
            "default head, teeth and tongue welded",
        )
    )
    made.append(
        default.welded(
            [("lower_teeth", "skin", False), ("upper_teeth", "skin", False), ("tongue", "skin", False)],
            "default head, parts welded, by material",
            True,
        )
    )
    vitruvian = HEADS / "vitruvian" / "vitruvian_head_facs.glb"
    if vitruvian.exists():
        head = joined_heads.joined_head("vitruvian", glb_parts(vitruvian, ARTIST_KEYS["vitruvian"]))
        head.labels.update(_eye_pieces(head))
        eyes = joined_heads.find_eyes(
            head.vertices, head.triangles, find_landmarks(head.vertices, head.triangles)
        )
        cards = head.with_added(joined_heads.lash_cards(eyes), "vitruvian + lash cards")
        made.append(cards.with_added(joined_heads.eye_shells(eyes), "vitruvian + lash cards + eye shells"))
        made.append(head.with_added(joined_heads.lash_strands(eyes), "vitruvian + single lashes"))
        bare = head.without("eyeball", "cornea", name="vitruvian without eyeballs")
        bare = bare.with_added(joined_heads.lash_cards(eyes), bare.name)  # the eyes as found with eyeballs
        made.append(bare.with_added(joined_heads.eye_shells(eyes), f"{bare.name} + lash cards + eye shells"))
    makehuman = HEADS / "makehuman" / "mh_head_expression_units.glb"
    if makehuman.exists():
        joined = joined_heads.joined_head(
            "makehuman, parts joined", glb_parts(makehuman, ARTIST_KEYS["makehuman"])
        )
        made.append(joined)
        made.append(
            joined.welded(
                [("teeth_lower", "tongue", False), ("teeth_upper", "teeth_lower", True)],
                "makehuman, teeth and tongue welded",
            )
        )
    return [head for head in made if names is None or any(name in head.name for name in names)]


def _eye_pieces(head: joined_heads.KitHead) -> dict[str, np.ndarray]:
    """Vitruvian's eyeballs and corneas, islands of its skin's object, as labelled parts."""
    landmarks = find_landmarks(head.vertices, head.triangles)
    parts = find_parts(head.vertices, head.triangles, landmarks)
    head.labels["skin"] = parts.skin
    return {kind: parts.indices(kind) for kind in ("eyeball", "cornea")}


def measure_head(head: joined_heads.KitHead) -> dict:
    landmarks = find_landmarks(head.vertices, head.triangles)
    parts = find_parts(head.vertices, head.triangles, landmarks, head.materials)
    units = transfer_units(
        load_reference_head(), head.vertices, head.triangles, landmarks, target_parts=parts
    )
    kinds = np.full(len(head.vertices), "skin", dtype=object)
    for piece in parts.pieces:
        kinds[piece.indices] = piece.kind
    edges, _ = edge_graph(len(head.vertices), head.triangles, head.vertices)
    rows = {}
    for key, truth in head.truth.items():
        ours = units[key]
        skin = head.labels["skin"]
        row = {
            "whole": displacement_cosine(ours, truth),
            "skin": displacement_cosine(ours[skin], truth[skin]),
            "stretch": edge_stretch(head.vertices, edges, ours),
            "truth_stretch": edge_stretch(head.vertices, edges, truth),
        }
        labelled = {part: indices for part, indices in head.labels.items() if part != "skin" and len(indices)}
        row["parts"] = piece_motion(labelled, ours, truth)
        for part, indices in labelled.items():
            found, counts = np.unique(kinds[indices], return_counts=True)
            row["parts"][part]["found"] = str(found[np.argmax(counts)])
        rows[key] = row
    return rows


def strip_keys(objects) -> None:
    for obj in objects:
        if obj.data.shape_keys is not None:
            obj.shape_key_clear()


def millimetres_per_unit(landmarks) -> float:
    """Millimetres in one of the head's units, read from its size against the reference head's (a human
    head in metres): the nearest power of ten, so a head in metres reads true and one modelled in
    centimetres or decimetres (MediaPipe's mask, MakeHuman's body) reads in millimetres all the same."""
    reference = reference_landmarks_of(load_reference_head())
    names = [name for name in reference if name in landmarks]
    scale, _, _ = similarity_fit(
        np.array([reference[name] for name in names]), np.array([landmarks[name] for name in names])
    )
    return 1000.0 / 10.0 ** round(math.log10(scale))
