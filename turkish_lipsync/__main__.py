"""python -m turkish_lipsync: syllables, timeline and quality reports without Blender."""

import sys

from .core.cli import main

sys.exit(main())
