"""The Blender side of an episode scene's build: scripts/render.py builds and saves the scene, then the frames
and speech of the scene it saved are written as JSON for episode.py to check.

episode.py runs it in a Blender process of its own (`blender -b -P episode_blender.py -- RESULT.json
RENDER_ARGS...`, or `python episode_blender.py RESULT.json RENDER_ARGS...` with the bpy module).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

SCRIPTS = Path(__file__).resolve().parent
if str(SCRIPTS) not in sys.path:
    sys.path.insert(0, str(SCRIPTS))

import render  # noqa: E402  (puts the repository on the path)


def main(argv: list[str]) -> int:
    if not argv:
        print("episode_blender.py: error: give RESULT.json and render.py's arguments", file=sys.stderr)
        return 2
    result, *arguments = argv
    code = render.main(arguments)
    if code:
        return code
    import bpy

    from turkish_lipsync.blender import sequencer

    scene = bpy.context.scene
    wav = sequencer.speech_wav_of(scene)
    built = {"frames": [scene.frame_start, scene.frame_end], "speech": str(wav) if wav else None}
    Path(result).write_text(json.dumps(built), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]))
