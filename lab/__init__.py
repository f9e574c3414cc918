"""The lab beside the product: what measures, tunes and trains it, never shipped in the extension.

    kit/      what the lab and the tests share: people's recordings, synthetic takes and their degradations,
              the corpus, test heads, measures of a timeline and of an evaluated scene
    measure/  scripts that print the figures of docs/developer/measured/ (python -m lab.measure.NAME)
    tune/     scripts that try the product's settings on the tune part of people's recordings
    train/    the acoustic model's training (PyTorch, in a venv of its own)

Run every module from the repository root with `python -m lab.PACKAGE.NAME`: the root is then on the import
path and nothing edits sys.path. The tests import the kit only, never a measuring, tuning or training script.
"""

from pathlib import Path

REPOSITORY = Path(__file__).resolve().parent.parent
