"""An episode on a render farm: its scenes built, rendered in chunks and joined, here or on a farm.

    python scripts/episode.py job EPISODE --out JOB     # the job: JOB/template.json (Open Job Description)
    python scripts/episode.py run JOB                   # run it on this machine with openjd, scene by scene
    openjd run JOB/template.json --step "01-kafe render" --task-param Frames=26-50   # one chunk again

The command is turkish_lipsync/core/farm/command.py (its --help says more); this file only finds the
package beside it. The farm's tasks run this file (farm/steps.toml), each Blender step scripts/render.py.
"""

import runpy
import sys
from pathlib import Path


def main() -> int:
    runpy.run_path(str(Path(__file__).with_name("_package.py")))["import_package"]()
    from turkish_lipsync.core.farm.command import main

    return main()


if __name__ == "__main__":
    sys.exit(main())
