"""Whether every part of a head follows its face: transfers onto heads whose parts are islands of one mesh.

    .venv/bin/python scripts/measure_parts.py [--heads NAME ...]

The heads (scripts/kit_heads.py, with scripts/joined_heads.py) are made from the shared heads: Vitruvian
with lash cards, single lashes, eye-occlusion shells and tear lines added along its lids (with and without
its eyeballs, as a scanned head may come), MakeHuman's head with its teeth, tongue and eyes joined into its
mesh (and its teeth and tongue welded into one piece, or told apart by material only), and the default head
joined and bent into another face. The truth is each head's own motion: Vitruvian's and MakeHuman's artists'
mouth opening and blink (the added lashes and shells turning about the eyeball as their lid point does), the
reference's own units on the default head. Printed per head and key: the cosine of the transferred motion
against the truth over the whole mesh and over the skin alone, the edge stretch p99.9 over the whole mesh
(ours / the truth's: a tear or a curtain of webbing stretches edges tens of times), and per part its share
of the truth's motion, its share of ours, the cosine, and what the parts finder took it for.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from scripts import joined_heads  # noqa: E402
from scripts.kit_heads import kit_heads  # noqa: E402
from turkish_lipsync.core.faces.head_parts import find_parts  # noqa: E402
from turkish_lipsync.core.faces.landmarks import find_landmarks  # noqa: E402
from turkish_lipsync.core.faces.measure import displacement_cosine, edge_stretch, piece_motion  # noqa: E402
from turkish_lipsync.core.faces.reference import load_reference_head  # noqa: E402
from turkish_lipsync.core.faces.topology import edge_graph  # noqa: E402
from turkish_lipsync.core.faces.transfer import transfer_units  # noqa: E402


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
