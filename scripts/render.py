"""Batch lip sync: Turkish text in, a head speaking it out (MP4 with sound and/or a .blend).

Runs inside Blender and with the bpy module:

    blender -b -P scripts/render.py -- --text "Merhaba" --out out/merhaba.mp4
    python scripts/render.py --jsml examples/demo.jsml --out out/demo.mp4 --save-blend out/demo.blend
    python scripts/render.py --audio take.wav --out out/take.mp4   # no text: what the take says is recognised

In a shot where a character is linked and library-overridden, --object names the head to animate (its
keys or face rig built in the character's own file): the file Blender opened, or --open with the bpy module:

    blender -b shot.blend -P scripts/render.py -- --object Head --jsml line.jsml --out line.mp4
    python scripts/render.py --open shot.blend --object Head --jsml line.jsml --out line.mp4

On any error it prints one line and exits non-zero. Given a .blend with --head, it changes only the TR_* keys,
their F-curves, the TR_speech strip and the frame range (plus camera and lights only where there are none).

On a render farm (farm/flamenco/turkish_lipsync.js), each worker renders a chunk of the saved .blend and one
task joins the chunks with the speech, copying the video (the join needs PyAV, not Blender):

    blender -b saved.blend -P scripts/render.py -- --frames 1-50 --engine cycles --out chunks/0001-0050.mp4
    python scripts/render.py --join chunks/0001-0050.mp4 chunks/0051-0100.mp4 --audio speech.wav --out out.mp4

The command is turkish_lipsync/core/batch (its flags, the join) and turkish_lipsync/blender/batch.py (the
Blender work); this file only finds the package beside it.
"""

import runpy
import sys
from pathlib import Path


def run_in_blender(arguments) -> None:
    """The Blender work, imported only when it is asked for: a join needs no Blender."""
    from turkish_lipsync.blender.batch import run_in_blender

    run_in_blender(arguments)


def main() -> int:
    runpy.run_path(str(Path(__file__).with_name("_package.py")))["import_package"]()
    from turkish_lipsync.core.batch.command import main, script_arguments

    return main(script_arguments(__file__), run_in_blender)


if __name__ == "__main__":
    sys.exit(main())
