"""The kit of test heads whose motion is known: heads of the kinds users bring, made from the ones we have.

The default head with its parts joined into one mesh and bent into another face (its truth: the
reference's own units bent alike), and the shared heads (Vitruvian, MakeHuman) with their parts joined,
welded, or with lash cards, single lashes and eye shells added (scripts/joined_heads.py; their truth: the
artists' own keys). scripts/measure_parts.py measures transfers onto them, scripts/face_report.py --kit
renders one, and the tests build them too. The shared heads are read with Blender (bpy, imported where
needed); the default head's parts need no Blender.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from scripts import joined_heads  # noqa: E402
from scripts.measure_transfer import reshape_face  # noqa: E402
from tests.heads_on_disk import HEADS  # noqa: E402
from turkish_lipsync.core.faces.head_parts import find_parts  # noqa: E402
from turkish_lipsync.core.faces.landmarks import find_landmarks  # noqa: E402
from turkish_lipsync.core.faces.reference import load_reference_head  # noqa: E402

if TYPE_CHECKING:
    import bpy

KEYS = ("jawOpen", "eyeBlinkLeft")
# The artists' keys that show our units, per shared head (the rest of shapekeys/artist_comparisons.toml).
ARTIST_KEYS = {
    "vitruvian": {"jawOpen": "Mouth_Large_Opened", "eyeBlinkLeft": "Eyes_Closed_Left"},
    "makehuman": {"jawOpen": "mouth-open", "eyeBlinkLeft": "eye-left-closure"},
}
# The default head bent into another face (measure_transfer.py's bends): a wider jaw, a longer chin,
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
