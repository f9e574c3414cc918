"""Release tools and figure makers, never shipped in the extension.

    release/  the extension zips and the default head's data (python -m tools.release.build_extension)
    figures/  the manual's pictures and review sheets (python -m tools.figures.NAME)

Run every module from the repository root with `python -m tools.PACKAGE.NAME`.
"""

from pathlib import Path

REPOSITORY = Path(__file__).resolve().parent.parent
