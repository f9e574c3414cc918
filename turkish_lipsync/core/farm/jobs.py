"""The farm's steps (farm/steps.toml) rendered for the two job formats.

- `openjd_template(...)`: an episode's Open Job Description template (the job AWS Deadline Cloud runs, and
  `openjd run` here): the steps for every scene, named "<scene> build", "<scene> render", "<scene> join".
- `flamenco_block(...)`: the STEPS block of the Flamenco job type (farm/flamenco/turkish_lipsync.js), whose
  compileJob() authors a Flamenco job's tasks from it (written there by `python -m tools.release.flamenco`);
  `flamenco_jobs(...)` one job submission per scene.
"""

from __future__ import annotations

import json
import re
import sys
from dataclasses import dataclass
from pathlib import Path

from ..base.errors import DataError
from . import CHECKOUT

STEPS_FILE = CHECKOUT / "farm" / "steps.toml"
FLAMENCO_JOB_TYPE = CHECKOUT / "farm" / "flamenco" / "turkish_lipsync.js"
FLAMENCO_TYPE_NAME = "turkish-lipsync"  # the Manager names a job type after its file, _ as -
BEGIN_MARK, END = "// BEGIN STEPS", "// END STEPS"  # the block from its first line's start to its end
BEGIN = f"{BEGIN_MARK}: farm/steps.toml, written by `python -m tools.release.flamenco`; do not edit"
PLACEHOLDER = re.compile(r"\{([a-z_]+)\}")
CHUNK_PARAMETER = "Frames"
# A cancelled task is told first (SIGTERM), so that it stops its Blender and takes away what it half made.
CANCEL = {"mode": "NOTIFY_THEN_TERMINATE", "notifyPeriodInSeconds": 30}


@dataclass(frozen=True)
class Step:
    name: str
    title: str
    writes: str
    arguments: tuple[str, ...]
    after: str | None = None
    chunked: bool = False
    blender: bool = False
    episode_only: bool = False


@dataclass(frozen=True)
class FarmSteps:
    program: tuple[str, ...]
    steps: tuple[Step, ...]
    paths: dict[str, str]
    values: dict[str, str]  # every placeholder and what it is

    def step(self, name: str) -> Step:
        return next(step for step in self.steps if step.name == name)


def fill(template: str, values: dict[str, str]) -> str:
    """The template with each {name} replaced by its value (every name must have one)."""

    def value(match: re.Match) -> str:
        if match.group(1) not in values:
            raise DataError(f"{STEPS_FILE}: {{{match.group(1)}}} has no value here")
        return values[match.group(1)]

    return PLACEHOLDER.sub(value, template)


def load_steps(path: Path | None = None) -> FarmSteps:
    """farm/steps.toml, checked: known fields, steps after earlier steps, every placeholder described."""
    from ..base.data import read_toml_file

    path = path or STEPS_FILE
    data = read_toml_file(path, "restore farm/steps.toml from the repository")
    fields = set(Step.__dataclass_fields__)
    steps: list[Step] = []
    for number, entry in enumerate(data.get("steps", ()), start=1):
        unknown = set(entry) - fields
        if unknown or not {"name", "title", "writes", "arguments"} <= set(entry):
            raise DataError(f"{path}: step {number} has unknown fields {sorted(unknown)} or lacks one")
        step = Step(**{**entry, "arguments": tuple(entry["arguments"])})
        if step.after is not None and step.after not in {earlier.name for earlier in steps}:
            raise DataError(f"{path}: step {step.name} comes after {step.after!r}, no step before it")
        steps.append(step)
    farm = FarmSteps(
        tuple(data.get("program", ())), tuple(steps), data.get("paths", {}), data.get("values", {})
    )
    used = {
        name
        for text in (*farm.program, *farm.paths.values(), *(a for s in farm.steps for a in s.arguments))
        for name in PLACEHOLDER.findall(text)
    }
    undescribed = used - set(farm.values)
    if not farm.steps or not farm.program or undescribed:
        raise DataError(
            f"{path}: no steps or program, or values without a description: {sorted(undescribed)}"
        )
    return farm


def command_of(farm: FarmSteps, step: Step, values: dict[str, str]) -> list[str]:
    """A task's command line: the program, the step's name, its arguments."""
    program = [fill(part, values) for part in farm.program]
    return [*program, step.name, *(fill(argument, values) for argument in step.arguments)]


# ---------------------------------------------------------------- Open Job Description


# The job's parameters: (name, the value of steps.toml it gives, its type, its label, more of its definition)
# (ChunkSize gives no value: it sizes the render step's chunks)
OPENJD_PARAMETERS = (
    ("Python", "python", "STRING", "Python", {}),
    ("Blender", "blender", "STRING", "Blender", {}),
    ("Checkout", "checkout", "PATH", "Turkish Lip Sync", {"objectType": "DIRECTORY", "dataFlow": "NONE"}),
    ("EpisodeFolder", "episode", "PATH", "Episode", {"objectType": "DIRECTORY", "dataFlow": "IN"}),
    ("OutputFolder", "output", "PATH", "Output", {"objectType": "DIRECTORY", "dataFlow": "OUT"}),
    ("Engine", "engine", "STRING", "Engine", {"allowedValues": ["CYCLES", "EEVEE", "WORKBENCH"]}),
    ("Samples", "samples", "INT", "Samples", {"minValue": 1, "maxValue": 4096}),
    ("ChunkSize", None, "INT", "Frames per chunk", {"minValue": 1, "maxValue": 150}),  # the chunks' size
)


def openjd_values(farm: FarmSteps, scene: str, frames: tuple[int, int]) -> dict[str, str]:
    """Every placeholder as the template writes it: job parameters, the scene's own values, the chunk."""
    values = {value: f"{{{{Param.{name}}}}}" for name, value, *_ in OPENJD_PARAMETERS if value}
    values |= {
        "chunk": f"{{{{Task.Param.{CHUNK_PARAMETER}}}}}",
        "scene": scene,
        "frames": f"{frames[0]}-{frames[1]}",
    }
    return values | {name: fill(path, values) for name, path in farm.paths.items()}


def _openjd_parameters(farm: FarmSteps, values: dict) -> list[dict]:
    """The job's parameters, described as steps.toml describes their values; a folder has no default (Open
    Job Description takes a default folder inside the template's own folder only): parameters.json beside
    the template gives this machine's."""
    controls = {"PATH": "CHOOSE_DIRECTORY", "INT": "SPIN_BOX", "STRING": "LINE_EDIT"}
    found = []
    for name, value, kind, label, more in OPENJD_PARAMETERS:
        control = "DROPDOWN_LIST" if "allowedValues" in more else controls[kind]
        description = farm.values[value] if value else "frames one task of the render step renders"
        found.append(
            {"name": name, "type": kind, "description": description}
            | ({} if kind == "PATH" else {"default": values[name]})
            | {"userInterface": {"control": control, "label": label}}
            | more
        )
    return found


def _openjd_step(farm: FarmSteps, step: Step, scene: str, frames: tuple[int, int]) -> dict:
    command = command_of(farm, step, openjd_values(farm, scene, frames))
    entry: dict = {
        "name": f"{scene} {step.name}",
        "description": f"{step.title}: {step.writes}",
        "script": {"actions": {"onRun": {"command": command[0], "args": command[1:], "cancelation": CANCEL}}},
    }
    if step.chunked:
        entry["parameterSpace"] = {
            "taskParameterDefinitions": [
                {
                    "name": CHUNK_PARAMETER,
                    "type": "CHUNK[INT]",
                    "range": f"{frames[0]}-{frames[1]}",
                    "chunks": {"defaultTaskCount": "{{Param.ChunkSize}}", "rangeConstraint": "CONTIGUOUS"},
                }
            ]
        }
    if step.after is not None:
        entry["dependencies"] = [{"dependsOn": f"{scene} {step.after}"}]
    return entry


def openjd_template(title: str, frames: dict[str, tuple[int, int]], values: dict) -> dict:
    """The episode's job: every scene's steps (a failed scene stops only its own), the job's parameters
    with this machine's values as defaults where a default may be given."""
    farm = load_steps()
    return {
        "specificationVersion": "jobtemplate-2023-09",
        "extensions": ["TASK_CHUNKING"],
        "name": title,
        "description": "Turkish Lip Sync: each scene built, rendered in chunks and joined with its speech",
        "parameterDefinitions": _openjd_parameters(farm, values),
        "steps": [
            _openjd_step(farm, step, scene, span) for scene, span in frames.items() for step in farm.steps
        ],
    }


# ---------------------------------------------------------------- Flamenco


def flamenco_block(farm: FarmSteps | None = None) -> str:
    """The job type's STEPS block: the program, the steps and the scene's paths as JavaScript constants."""
    farm = farm or load_steps()
    steps = [
        {key: value for key, value in vars(step).items() if key not in ("title", "writes")}
        for step in farm.steps
    ]

    def constant(name: str, value) -> str:
        return f"const {name} = {json.dumps(value, ensure_ascii=False, indent=2)};"

    body = "\n".join(
        [constant("PROGRAM", list(farm.program)), constant("STEPS", steps), constant("PATHS", farm.paths)]
    )
    return f"{BEGIN}\n{body}\n{END}"


def job_type_block(text: str) -> str:
    start, end = text.find(BEGIN_MARK), text.find(END)
    if start < 0 or end < start:
        raise DataError(f"{FLAMENCO_JOB_TYPE} has no STEPS block ({BEGIN_MARK!r} ... {END!r})")
    return text[start : end + len(END)]


def flamenco_jobs(title: str, frames: dict[str, tuple[int, int]], values: dict) -> dict[str, dict]:
    """Each scene as a Flamenco job submission (the body of POST /api/v3/jobs): one job per scene, as
    Flamenco fails a whole job when one of its tasks fails."""
    return {
        scene: {
            "name": f"{title} {scene}",
            "type": FLAMENCO_TYPE_NAME,
            "priority": 50,
            "submitter_platform": {"win32": "windows"}.get(sys.platform, sys.platform),
            "settings": {
                "scene": scene,
                "frames": f"{first}-{last}",
                "episode_folder": values["EpisodeFolder"],
                "output_folder": values["OutputFolder"],
                "checkout": values["Checkout"],
                "python": values["Python"],
                "engine": values["Engine"],
                "samples": values["Samples"],
                "chunk_size": values["ChunkSize"],
            },
        }
        for scene, (first, last) in frames.items()
    }
