"""An episode on a render farm, without Blender: its manifest read (manifest.py), its scenes' frames timed
(plan.py), its job written for Open Job Description and Flamenco from farm/steps.toml (jobs.py), the steps a
farm runs (tasks.py: each Blender step runs scripts/render.py in a process of its own), and the command
(command.py, run as scripts/episode.py)."""

from pathlib import Path

CHECKOUT = Path(__file__).resolve().parents[3]  # the repository: farm/steps.toml, scripts/render.py
