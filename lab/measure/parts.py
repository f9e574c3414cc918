"""Whether every part of a head follows its face: transfers onto heads whose parts are islands of one mesh.

    .venv/bin/python -m lab.measure.parts [--heads NAME ...]

The heads (lab/kit/heads.py, with lab/kit/joined_heads.py) are made from the shared heads: Vitruvian
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

import numpy as np

from lab.kit.heads import kit_heads, measure_head


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
