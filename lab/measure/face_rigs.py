"""How closely heads moved by bones speak as the shape-key path does, on the evaluated mesh:

    nice -n 10 .venv/bin/python -m lab.measure.face_rigs [--text TEXT]

For the jaw-bone game character (MakeHuman's expression-units head, its own keys taken off, on a neck, head
and jaw armature) and for Rigify's face rig on the default head (lab/kit/rigged_heads.py), against the same
head speaking through shape keys built on it: the lips' opening at the middle of the mouth at every frame
(the lowest point of the upper lip minus the highest of the lower, negative where they press), its
correlation with the shape-key path's, the opening at the widest frame of each open vowel and at the
closing frame of each b, m, p. Prints the figures of docs/developer/measured/face-rigs.md.
"""

from __future__ import annotations

import argparse
import sys

import bpy
import numpy as np

from lab.kit.rigged_heads import (
    jaw_bone_character,
    lip_gaps,
    makehuman_with_our_keys,
    phone_frames,
    rigify_face_character,
)
from turkish_lipsync import blender
from turkish_lipsync.blender import face_rig, heads, shapekeys
from turkish_lipsync.blender.generate import generate
from turkish_lipsync.core.faces.rig_mappings import OwnRig

TEXT = "Merhaba, benim adım Erdem. Bu sabah vapura binip geçtim, ama bir de babamı gördüm."
FPS = 25


def _scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.render.fps = FPS
    return bpy.context


def speaking(head, text: str):
    result = generate(bpy.context, text, head=head)
    frames = np.arange(1, result.frame_end + 1)
    return result.timeline, frames, lip_gaps(head, frames)


def compare(name: str, keyed, rigged) -> None:
    timeline, frames, keyed_gaps = keyed
    _timeline, _frames, gaps = rigged
    by_frame = dict(zip(frames, gaps, strict=True))
    keyed_by_frame = dict(zip(frames, keyed_gaps, strict=True))
    closures = []
    for _letter, span in phone_frames(timeline, "bmp", FPS):
        closed = min(span, key=lambda frame: keyed_by_frame[frame])
        closures.append((keyed_by_frame[closed], by_frame[closed]))
    vowels = []
    for _letter, span in phone_frames(timeline, "aeo", FPS):
        widest = max(span, key=lambda frame: keyed_by_frame[frame])
        vowels.append((keyed_by_frame[widest], by_frame[widest]))
    closures, vowels = np.array(closures) * 1000, np.array(vowels) * 1000
    print(
        f"{name}: {len(frames)} frames, opening correlated with the shape keys' r = "
        f"{np.corrcoef(gaps, keyed_gaps)[0, 1]:.3f}; widest {gaps.max() * 1000:.1f} mm "
        f"(shape keys {keyed_gaps.max() * 1000:.1f} mm)"
    )
    print(
        f"  {len(closures)} b/m/p closing frames: bones {np.median(closures[:, 1]):+.1f} mm median, "
        f"{closures[:, 1].max():+.1f} mm most open; shape keys {np.median(closures[:, 0]):+.1f} mm, "
        f"{closures[:, 0].max():+.1f} mm"
    )
    print(
        f"  {len(vowels)} a/e/o widest frames: bones {np.median(vowels[:, 1]):.1f} mm median, "
        f"{(vowels[:, 1] / vowels[:, 0]).min():.2f}-{(vowels[:, 1] / vowels[:, 0]).max():.2f} of the shape "
        f"keys'"
    )


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--text", default=TEXT)
    args = parser.parse_args()
    blender.register()
    context = _scene()
    keyed = speaking(makehuman_with_our_keys(), args.text)
    context = _scene()
    character = jaw_bone_character(context)
    face_rig.store_setup(character["armature"], OwnRig("jaw_bone"))
    compare("jaw bone (MakeHuman expression-units head)", keyed, speaking(character["head"], args.text))
    context = _scene()
    reference = heads.create_reference_head(context)["head"]
    shapekeys.build_shape_keys(reference)
    keyed = speaking(reference, args.text)
    context = _scene()
    character = rigify_face_character(context)
    face_rig.store_setup(character["rig"], OwnRig("rigify_face"))
    compare("Rigify face rig (default head)", keyed, speaking(character["head"], args.text))
    return 0


if __name__ == "__main__":
    sys.exit(main())
