"""An episode on a render farm: its scenes built, rendered in chunks and joined, here or on a farm.

    python scripts/episode.py job EPISODE --out JOB     # the job: JOB/template.json (Open Job Description)
    python scripts/episode.py run JOB                   # run it on this machine with openjd, scene by scene
    openjd run JOB/template.json --step "01-kafe render" --task-param Frames=26-50   # one chunk again

EPISODE is a folder of scene files (scripts with speakers, plain JSML) with an optional episode.toml beside
them, that file, or some of the scene files. The job is also a Deadline Cloud job bundle (`deadline bundle
submit JOB`) and holds one Flamenco job per scene (JOB/flamenco/). The steps a farm runs (build, render,
join; farm/steps.toml) are this command's others. Errors print one line each and exit non-zero.
scripts/episode.py finds the package beside it and runs main.
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import signal
import subprocess
import sys
from pathlib import Path

from ..base.errors import LipSyncError
from ..batch.arguments import OneLineArgumentParser, frame_range
from . import CHECKOUT
from .manifest import EpisodeError

TEMPLATE = "template.json"
PARAMETERS = "parameters.json"  # the job parameters' values on this machine
ERROR_LINE = re.compile(r"episode\.py: error: (.*)$")
STEP_LINE = re.compile(r"Running step '(.*)'")


# ---------------------------------------------------------------- job


def _write_json(path: Path, data) -> None:
    path.write_text(json.dumps(data, ensure_ascii=False, indent=1) + "\n", encoding="utf-8")


def _write_flamenco_jobs(folder: Path, jobs: dict[str, dict]) -> None:
    """One submission a scene; those of scenes the episode no longer has are taken away."""
    from .jobs import FLAMENCO_TYPE_NAME

    folder.mkdir(exist_ok=True)
    for old in folder.glob("*.json"):
        try:
            ours = json.loads(old.read_text(encoding="utf-8")).get("type") == FLAMENCO_TYPE_NAME
        except (OSError, ValueError, AttributeError):
            ours = False
        if ours and old.stem not in jobs:
            old.unlink()
    for scene, body in jobs.items():
        _write_json(folder / f"{scene}.json", body)


def make_job(arguments: argparse.Namespace) -> None:
    """The episode read and checked, each scene's frames timed, the job written."""
    from ..base.files import check_writable
    from .jobs import flamenco_jobs, openjd_template
    from .manifest import read_episode
    from .plan import plan_episode

    episode = read_episode(arguments.episode)
    frames = plan_episode(episode)
    job = arguments.out.resolve()
    output = (arguments.output or job / "output").resolve()
    check_writable(job / TEMPLATE, "job template")
    render = episode.render
    values = {
        "Python": sys.executable,
        "Blender": arguments.blender or "",
        "Checkout": str(CHECKOUT),
        "EpisodeFolder": str(episode.folder),
        "OutputFolder": str(output),
        "Engine": render.engine,
        "Samples": render.samples,
        "ChunkSize": render.chunk_size,
    }
    template = openjd_template(episode.title, frames, values)
    _write_json(job / TEMPLATE, template)
    _write_json(job / PARAMETERS, values)  # for openjd run -p file://
    _write_json(
        job / "parameter_values.json",
        {"parameterValues": [{"name": k, "value": v} for k, v in values.items()]},
    )
    _write_flamenco_jobs(job / "flamenco", flamenco_jobs(episode.title, frames, values))
    print(f"Episode {episode.title!r}: {len(frames)} scenes at {render.fps:g} fps, {render.engine}, "
          f"{render.samples} samples, {render.chunk_size} frames a chunk")  # fmt: skip
    for scene, (first, last) in frames.items():
        chunks = -(-(last - first + 1) // render.chunk_size)
        print(f"  {scene}: frames {first}-{last} ({chunks} chunks) -> {output / scene}.mp4")
    print(f"Wrote {job / TEMPLATE} and {job / 'flamenco'}/; run it here: {Path(sys.argv[0]).name} run {job}")


# ---------------------------------------------------------------- run


def _openjd() -> str:
    beside = Path(sys.executable).with_name("openjd")
    found = str(beside) if beside.is_file() else shutil.which("openjd")
    if found is None:
        raise LipSyncError("openjd is not installed: python -m pip install openjd-cli")
    return found


def _run_openjd(command: list[str], step: str) -> str:
    """One openjd session, its log passing through. Returns "" when it finished, else the step that
    failed and the error it printed."""
    error = None
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        for line in process.stdout:
            sys.stdout.write(line)
            if found := STEP_LINE.search(line):
                step = found.group(1)
            if found := ERROR_LINE.search(line):
                error = found.group(1).strip()
        process.wait()
    finally:
        if process.poll() is None:  # this run was stopped: openjd cancels its session's task
            process.terminate()
            try:
                process.wait(timeout=60)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
    if process.returncode == 0:
        return ""
    if process.returncode < 0:  # openjd itself was stopped: the whole run stops with it
        raise LipSyncError(f"openjd was stopped ({signal.Signals(-process.returncode).name}) in {step}")
    return f"{step}: {error or 'failed (the log is above)'}"


def run_job(arguments: argparse.Namespace) -> int:
    """Every scene (or the chosen ones) run one after another, each its join with every step before it;
    a failed scene does not stop the others. With --step, that step alone (--frames: one chunk)."""
    template, parameters = arguments.job / TEMPLATE, arguments.job / PARAMETERS
    if not template.is_file() or not parameters.is_file():
        raise LipSyncError(
            f"{arguments.job} holds no {TEMPLATE} and {PARAMETERS}: make the job (episode.py job)"
        )
    steps = [step["name"] for step in json.loads(template.read_text(encoding="utf-8"))["steps"]]
    scenes = [name.removesuffix(" join") for name in steps if name.endswith(" join")]
    unknown = sorted(set(arguments.scene or ()) - set(scenes))
    if unknown:
        raise LipSyncError(f"the job has no scene {', '.join(unknown)}; its scenes are {', '.join(scenes)}")
    if arguments.frames and arguments.step != "render":
        raise LipSyncError("--frames chooses a chunk of the render step: give --step render with it")
    chosen = [scene for scene in scenes if not arguments.scene or scene in arguments.scene]
    base = [_openjd(), "run", str(template), "-p", f"file://{parameters.resolve()}"]
    failures = {}
    for scene in chosen:
        if arguments.step is None:
            command = [*base, "--step", f"{scene} join", "--run-dependencies"]
        else:
            command = [*base, "--step", f"{scene} {arguments.step}", "--no-run-dependencies"]
        if arguments.frames:
            command += ["--task-param", f"Frames={arguments.frames[0]}-{arguments.frames[1]}"]
        if failure := _run_openjd(command, f"{scene} {arguments.step or 'build'}"):
            failures[scene] = failure
    output = Path(json.loads(parameters.read_text(encoding="utf-8"))["OutputFolder"])
    print(f"\nEpisode: {len(chosen) - len(failures)} of {len(chosen)} scenes done", flush=True)
    for scene in chosen:
        if scene not in failures and arguments.step in (None, "join"):
            print(f"  {scene}: {output / scene}.mp4", flush=True)
    for scene, failure in failures.items():
        print(f"episode.py: error: scene {scene} failed in {failure}", file=sys.stderr, flush=True)
    return 1 if failures else 0


# ---------------------------------------------------------------- the steps


def run_step(arguments: argparse.Namespace) -> None:
    from . import tasks

    if arguments.command == "build":
        if arguments.speech is None:
            raise LipSyncError("the build needs --speech=PATH: where the scene's speech WAV goes")
        tasks.build_scene(
            arguments.episode, arguments.scene, arguments.frames, arguments.blend, arguments.speech,
            arguments.blender,
        )  # fmt: skip
    elif arguments.command == "render":
        tasks.render_chunk(
            arguments.blend, arguments.frames, arguments.chunks, arguments.engine, arguments.samples,
            arguments.blender,
        )  # fmt: skip
    else:
        tasks.join_scene(
            arguments.blend, arguments.frames, arguments.chunks, arguments.engine, arguments.samples,
            arguments.speech, arguments.out,
        )  # fmt: skip


def _optional_path(text: str) -> Path | None:
    return Path(text) if text else None


def parse_arguments(argv: list[str]) -> argparse.Namespace:
    parser = OneLineArgumentParser(prog="episode.py", description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", required=True, parser_class=OneLineArgumentParser)
    job = commands.add_parser("job", help="make the episode's job (checks every scene, times its speech)")
    job.add_argument(
        "episode", type=Path, nargs="+", help="the episode's folder, episode.toml or scene files"
    )
    job.add_argument("--out", type=Path, required=True, help="the job's folder (a Deadline Cloud job bundle)")
    job.add_argument("--output", type=Path, help="where the scenes are written (default: OUT/output)")
    job.add_argument("--blender", help="a Blender for the tasks (default: the bpy module of this Python)")
    run = commands.add_parser("run", help="run the job on this machine with openjd, scene after scene")
    run.add_argument("job", type=Path, help="the job's folder")
    run.add_argument("--scene", action="append", help="run only this scene (repeatable)")
    run.add_argument("--step", choices=("build", "render", "join"), help="run only this step of the scenes")
    run.add_argument("--frames", type=frame_range, help="with --step render: only the chunk of these frames")

    _add_steps(commands)
    return parser.parse_args(argv)


# A step's flag -> what it reads; the rest are paths. A speech or a Blender may be empty.
FLAG_TYPES = {"frames": frame_range, "samples": int, "speech": _optional_path, "scene": str, "engine": str}
MAY_BE_EMPTY = {"speech", "blender"}
STEP_FLAG = re.compile(r"^--([a-z_]+)=\{([a-z_]+)\}$")


def _add_steps(commands) -> None:
    """The farm's steps as commands: their flags are farm/steps.toml's arguments, their help its values'."""
    from .jobs import load_steps

    farm = load_steps()
    for step in farm.steps:
        command = commands.add_parser(step.name, help=f"a farm task: {step.title[0].lower()}{step.title[1:]}")
        command.description = f"{step.title}; writes {step.writes}."
        for argument in step.arguments:
            flag, value = STEP_FLAG.match(argument).groups()
            kind = str if flag == "blender" else FLAG_TYPES.get(flag, Path)
            command.add_argument(
                f"--{flag}", type=kind, required=flag not in MAY_BE_EMPTY, help=farm.values[value]
            )
        command.set_defaults(blender="", speech=None)


def _stop(signal_number, _frame) -> None:
    """Stopped by the farm or the user: what was half made is taken away as the stack unwinds."""
    print(f"episode.py: stopped ({signal.Signals(signal_number).name})", file=sys.stderr, flush=True)
    raise SystemExit(128 + signal_number)


def main(argv: list[str] | None = None) -> int:
    arguments = parse_arguments(sys.argv[1:] if argv is None else argv)
    signal.signal(signal.SIGTERM, _stop)
    try:
        if arguments.command == "job":
            make_job(arguments)
        elif arguments.command == "run":
            return run_job(arguments)
        else:
            run_step(arguments)
    except KeyboardInterrupt:
        print("episode.py: stopped", file=sys.stderr)
        return 130
    except EpisodeError as error:
        for problem in error.problems:
            print(f"episode.py: error: {problem}", file=sys.stderr)
        return 1
    except LipSyncError as error:
        print(f"episode.py: error: {error}", file=sys.stderr)
        return 1
    except OSError as error:
        print(f"episode.py: error: {error.filename or ''}: {error.strerror or error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
