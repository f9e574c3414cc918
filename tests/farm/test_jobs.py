"""The two renderings of farm/steps.toml agree: the Flamenco job type's STEPS block is steps.toml's, and a
scene's Flamenco job (compiled as the Manager compiles it) gives every task the command that the task of the
same step and frames of the episode's Open Job Description job (created as openjd creates it) runs."""

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from openjd.model import (
    StepParameterSpaceIterator,
    SymbolTable,
    create_job,
    decode_job_template,
    preprocess_job_parameters,
)

from tools.release import flamenco
from turkish_lipsync.core.farm import jobs

REPOSITORY = Path(__file__).resolve().parents[2]

NODE = shutil.which("node")
COMPILER = Path(__file__).with_name("flamenco_compile.js")
EPISODE = {
    "01-kafe.txt": "AYŞE: Merhaba Ali!\nALİ: Merhaba.\n",
    "02-yol.jsml": "Ama baba.\n",
    "episode.toml": '[episode]\nfps = 8\nresolution = "32x32"\nsamples = 3\nchunk_size = 4\n',
}


@pytest.fixture(scope="module")
def job(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("episode")
    for name, text in EPISODE.items():
        (folder / name).write_text(text, encoding="utf-8")
    command = [sys.executable, str(REPOSITORY / "scripts" / "episode.py"), "job", str(folder), "--out"]
    made = subprocess.run([*command, str(folder / "job")], capture_output=True, text=True, timeout=300)
    assert made.returncode == 0, made.stderr
    return folder / "job"


class OpenJDJob:
    """The episode's job as openjd creates it from the template and parameters.json."""

    def __init__(self, job: Path):
        template = decode_job_template(
            template=json.loads((job / "template.json").read_text(encoding="utf-8")),
            supported_extensions=["TASK_CHUNKING"],
        )
        given = json.loads((job / "parameters.json").read_text(encoding="utf-8"))
        values = preprocess_job_parameters(
            job_template=template,
            job_parameter_values={name: str(value) for name, value in given.items()},
            job_template_dir=job,
            current_working_dir=job,
        )
        self.parameters = {f"Param.{name}": value.value for name, value in values.items()}
        self.steps = {
            step.name: step for step in create_job(job_template=template, job_parameter_values=values).steps
        }

    def chunks(self, name: str) -> list[str]:
        """The chunks openjd splits the step's frames into."""
        return [
            task["Frames"].value for task in StepParameterSpaceIterator(space=self.steps[name].parameterSpace)
        ]

    def command(self, name: str, chunk: str | None = None) -> list[str]:
        """The command line the step's task runs (for a chunked step: the task of that chunk)."""
        symbols = SymbolTable(source=self.parameters | ({"Task.Param.Frames": chunk} if chunk else {}))
        action = self.steps[name].script.actions.onRun
        return [action.command.resolve(symtab=symbols)] + [
            argument.resolve(symtab=symbols) for argument in action.args
        ]

    def after(self, name: str) -> set[str]:
        return {dependency.dependsOn for dependency in self.steps[name].dependencies or ()}


def flamenco_tasks(job: Path, scene: str) -> list[dict]:
    compiled = subprocess.run(
        [NODE, str(COMPILER), str(jobs.FLAMENCO_JOB_TYPE), str(job / "flamenco" / f"{scene}.json")],
        capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip
    assert compiled.returncode == 0, compiled.stderr
    return json.loads(compiled.stdout)


def test_the_job_types_steps_block_is_written_from_steps_toml():
    text = jobs.FLAMENCO_JOB_TYPE.read_text(encoding="utf-8")
    assert jobs.job_type_block(text) == jobs.flamenco_block()
    assert flamenco.main(["--check"]) == 0
    names = [step.name for step in jobs.load_steps().steps]
    assert names == ["build", "render", "join"]


def test_a_changed_step_is_caught_until_the_job_type_is_written_again(tmp_path, monkeypatch):
    changed = tmp_path / "steps.toml"
    changed.write_text(
        jobs.STEPS_FILE.read_text(encoding="utf-8").replace('"--samples={samples}",', "", 1),
        encoding="utf-8",
    )
    monkeypatch.setattr(jobs, "STEPS_FILE", changed)
    assert jobs.job_type_block(jobs.FLAMENCO_JOB_TYPE.read_text(encoding="utf-8")) != (
        jobs.flamenco_block(jobs.load_steps(changed))
    )
    assert flamenco.main(["--check"]) == 1


@pytest.mark.skipif(NODE is None, reason="needs node to run the job compiler")
@pytest.mark.parametrize("scene", ["01-kafe", "02-yol"])
def test_flamenco_and_openjd_run_the_same_command_for_every_task(job, scene):
    openjd = OpenJDJob(job)
    parameters = json.loads((job / "parameters.json").read_text(encoding="utf-8"))
    tasks = flamenco_tasks(job, scene)
    steps = [task["name"].split("-")[0] for task in tasks]
    assert steps == ["build"] + ["render"] * (len(tasks) - 2) + ["join"]
    assert [f"{scene} {step}" for step in dict.fromkeys(steps)] == [
        n for n in openjd.steps if n.startswith(scene)
    ]
    for task, step in zip(tasks, steps, strict=True):
        (command,) = task["commands"]
        assert command["name"] == "exec"
        # {blender} is the Manager's variable, a worker's Blender: here the job's Blender parameter
        flamenco = [command["parameters"]["exe"]] + [
            argument.replace("{blender}", parameters["Blender"]) for argument in command["parameters"]["args"]
        ]
        chunk = task["name"].partition("-")[2] or None
        assert flamenco == openjd.command(f"{scene} {step}", chunk), task["name"]
        waits_for = {f"{scene} {name.split('-')[0]}" for name in task["dependencies"]}
        assert waits_for == openjd.after(f"{scene} {step}"), task["name"]
    # both split the scene's frames into chunks of at most ChunkSize frames that cover them once
    (last,) = {int(chunk.split("-")[1]) for chunk in openjd.chunks(f"{scene} render")[-1:]}
    for chunks in (
        [task["name"].partition("-")[2] for task in tasks[1:-1]],
        openjd.chunks(f"{scene} render"),
    ):
        spans = [(int(a), int(b or a)) for a, _, b in (chunk.partition("-") for chunk in chunks)]
        assert [frame for a, b in spans for frame in range(a, b + 1)] == list(range(1, last + 1))
        assert max(b - a + 1 for a, b in spans) <= parameters["ChunkSize"]
