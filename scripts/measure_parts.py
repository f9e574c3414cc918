"""Whether every part of a head follows its face: transfers onto heads whose parts are islands of one mesh.

    .venv/bin/python scripts/measure_parts.py [--heads NAME ...]

The heads (scripts/joined_heads.py) are made from the shared heads: Vitruvian with lash cards, single
lashes, eye-occlusion shells and tear lines added along its lids (with and without its eyeballs, as a
scanned head may come), MakeHuman's head with its teeth, tongue and eyes joined into its mesh (and its
teeth and tongue welded into one piece, or told apart by material only), and the default head joined and
bent into another face. The truth is each head's own motion: Vitruvian's and MakeHuman's artists' mouth
opening and blink (the added lashes and shells turning about the eyeball as their lid point does), the
reference's own units on the default head. Printed per head and key: the cosine of the transferred
motion against the truth over the whole mesh and over the skin alone, the edge stretch p99.9 over the
whole mesh (ours / the truth's: a tear or a curtain of webbing stretches edges tens of times), and per
part its share of the truth's motion, its share of ours, the cosine, and what the parts finder took it for.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from scripts import joined_heads  # noqa: E402
from scripts.measure_transfer import reshape_face  # noqa: E402
from tests.heads_on_disk import HEADS  # noqa: E402
from turkish_lipsync.core.faces.head_parts import find_parts  # noqa: E402
from turkish_lipsync.core.faces.landmarks import find_landmarks  # noqa: E402
from turkish_lipsync.core.faces.measure import displacement_cosine, edge_stretch, piece_motion  # noqa: E402
from turkish_lipsync.core.faces.reference import load_reference_head  # noqa: E402
from turkish_lipsync.core.faces.topology import edge_graph  # noqa: E402
from turkish_lipsync.core.faces.transfer import transfer_units  # noqa: E402

KEYS = ("jawOpen", "eyeBlinkLeft")
# The artists' keys that show our units, per shared head (the rest of shapekeys/artist_comparisons.toml).
ARTIST_KEYS = {
    "vitruvian": {"jawOpen": "Mouth_Large_Opened", "eyeBlinkLeft": "Eyes_Closed_Left"},
    "makehuman": {"jawOpen": "mouth-open", "eyeBlinkLeft": "eye-left-closure"},
}
# The default head bent into another face (measure_transfer.py's bends): a wider jaw, a longer chin,
# a bigger nose, eyes further apart, a sloping forehead.
BENDS = {"jaw": 0.15, "chin": 0.015, "nose": 0.006, "eyes": 0.004, "forehead": 0.01}


def glb_parts(path: Path, keys: dict[str, str]) -> dict:
    """part name -> (world vertices, triangles, our unit -> the artist key's world deltas) of a glb's
    meshes, the biggest first (Blender imports it)."""
    import bpy

    from scripts.face_report import world_key_deltas
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


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--heads", nargs="*", default=None, help="only the heads whose names contain these")
    arguments = parser.parse_args()
    means = []
    for head in kit_heads(arguments.heads):
        rows = measure_head(head)
        print(f"{head.name} ({len(head.vertices)} v)")
        for key, row in rows.items():
            means.append(row["whole"])
            print(
                f"  {key:13s} whole {row['whole']:.3f}  skin {row['skin']:.3f}  "
                f"stretch {row['stretch']:.1f} (truth {row['truth_stretch']:.1f})"
            )
            for part, figures in row["parts"].items():
                if figures["share"] > 0.005 or figures["ours"] > 0.005:
                    print(
                        f"      {part:22s} share {figures['share']:.2f}  ours {figures['ours']:.2f}  "
                        f"cosine {figures['cosine']:6.3f}  found as {figures['found']}"
                    )
    print(f"mean whole-mesh cosine {np.mean(means):.3f} over {len(means)} keys")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
