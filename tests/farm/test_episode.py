"""An episode on a farm, run here: `episode.py job` makes its Open Job Description template, `openjd run`
runs it (each chunk a Blender process of its own), and each scene's MP4 is, frame for frame and sample for
sample, the single-process render of the same scene joined with its speech.

The episode: a conversation of two default heads, one head's JSML, and a scene whose head is not a head
(a cube: no face is found), at 32x32 pixels, 8 frames a second, one Cycles sample, 4 frames a chunk.
"""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

av = pytest.importorskip("av")
pytest.importorskip("bpy")
from tests.render_runs import decoded_media, run_render  # noqa: E402

REPOSITORY = Path(__file__).resolve().parents[2]
EPISODE_SCRIPT = REPOSITORY / "scripts" / "episode.py"
OPENJD = str(Path(sys.executable).with_name("openjd"))
CUBE = "\n".join(
    ["v -1 -1 -1", "v 1 -1 -1", "v 1 1 -1", "v -1 1 -1", "v -1 -1 1", "v 1 -1 1", "v 1 1 1", "v -1 1 1"]
    + ["f 1 2 3 4", "f 5 8 7 6", "f 1 5 6 2", "f 2 6 7 3", "f 3 7 8 4", "f 5 1 4 8"]
)
FILES = {
    "01-kafe.txt": "AYŞE: Merhaba Ali!\nALİ: Merhaba.\n",
    "02-yol.jsml": "<SENT><HAPPY>Ama baba.</HAPPY></SENT>\n",
    "03-kutu.jsml": "Baba.\n",
    "heads/kutu.obj": CUBE,
    "episode.toml": '[episode]\ntitle = "Deneme"\nfps = 8\nresolution = "32x32"\nsamples = 1\n'
    'chunk_size = 4\n\n[scene."03-kutu"]\nhead = "heads/kutu.obj"\n',
}
GOOD = ("01-kafe", "02-yol")


def _episode(*arguments) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, str(EPISODE_SCRIPT), *map(str, arguments)],
        capture_output=True, text=True, timeout=900, check=False,
    )  # fmt: skip


def _openjd(job: Path, *arguments) -> subprocess.CompletedProcess:
    return subprocess.run(
        [OPENJD, "run", str(job / "template.json"), "-p", f"file://{job / 'parameters.json'}", *arguments],
        capture_output=True, text=True, timeout=600, check=False,
    )  # fmt: skip


@pytest.fixture(scope="module")
def episode(tmp_path_factory):
    """The episode's job made and run: (job folder, output folder, the run, the frames of each scene)."""
    folder = tmp_path_factory.mktemp("episode")
    for name, text in FILES.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(text, encoding="utf-8")
    job = folder / "job"
    made = _episode("job", folder, "--out", job)
    assert made.returncode == 0, made.stderr
    template = json.loads((job / "template.json").read_text(encoding="utf-8"))
    frames = {
        step["name"].removesuffix(" render"): step["parameterSpace"]["taskParameterDefinitions"][0]["range"]
        for step in template["steps"]
        if step["name"].endswith(" render")
    }
    run = _episode("run", job)
    return (
        job,
        job / "output",
        run,
        {scene: tuple(map(int, span.split("-"))) for scene, span in frames.items()},
    )


def _single_render(output: Path, scene: str, last: int) -> Path:
    """The scene's .blend rendered whole by one process, joined with its speech as the farm joins it."""
    whole, single = output / f"{scene}-whole.mp4", output / f"{scene}-single.mp4"
    if not single.is_file():
        blend = output / scene / f"{scene}.blend"
        for arguments in (
            (
                "--head",
                blend,
                "--frames",
                f"1-{last}",
                "--engine",
                "cycles",
                "--samples",
                "1",
                "--out",
                whole,
            ),
            ("--join", whole, "--audio", output / scene / f"{scene}.wav", "--out", single),
        ):
            result = run_render(*arguments)
            assert result.returncode == 0, result.stderr[-2000:]
    return single


def _assert_same_media(joined: Path, single: Path, frames: int) -> None:
    frames_joined, audio_joined = decoded_media(joined)
    frames_single, audio_single = decoded_media(single)
    assert len(frames_joined) == len(frames_single) == frames
    for number, (ours, theirs) in enumerate(zip(frames_joined, frames_single, strict=True), start=1):
        np.testing.assert_array_equal(ours, theirs, err_msg=f"{joined.name}: frame {number}")
    assert any(not np.array_equal(frames_joined[0], frame) for frame in frames_joined[1:])  # the mouth moves
    np.testing.assert_array_equal(audio_joined, audio_single)
    assert np.abs(audio_joined).max() > 0.05  # the speech, not silence


def test_the_template_passes_openjd_check_and_has_three_steps_a_scene(episode):
    job, _, _, frames = episode
    checked = subprocess.run([OPENJD, "check", str(job / "template.json")], capture_output=True, text=True)
    assert checked.returncode == 0 and "passes validation checks" in checked.stdout, checked.stdout
    steps = [
        step["name"] for step in json.loads((job / "template.json").read_text(encoding="utf-8"))["steps"]
    ]
    assert steps == [
        f"{scene} {step}" for scene in (*GOOD, "03-kutu") for step in ("build", "render", "join")
    ]
    assert all(first == 1 and last > 4 for first, last in frames.values())


@pytest.mark.parametrize("scene", GOOD)
def test_each_scene_is_one_mp4_with_its_speech_frame_identical_to_one_render(episode, scene):
    _, output, run, frames = episode
    last = frames[scene][1]
    chunks = sorted((output / scene / "chunks").glob("frames-*.mp4"))
    assert len(chunks) == -(-last // 4)  # each chunk its own task, rendered by a Blender process of its own
    assert run.stdout.count(f"{scene} frames ") == len(chunks)
    with av.open(str(output / f"{scene}.mp4")) as container:
        assert container.streams.video and container.streams.audio
    _assert_same_media(output / f"{scene}.mp4", _single_render(output, scene, last), last)


def test_a_bad_scene_fails_its_own_build_with_one_line_and_the_others_finish(episode):
    _, output, run, _ = episode
    assert run.returncode == 1
    errors = [line for line in run.stdout.splitlines() if "episode.py: error:" in line]
    assert len(errors) == 1 and "03-kutu: No mouth found under the nose" in errors[0], errors
    assert "03-kutu render" not in run.stdout  # nothing of the scene after its build
    assert (
        run.stderr.strip()
        .splitlines()[-1]
        .startswith("episode.py: error: scene 03-kutu failed in 03-kutu build")
    )
    assert "Episode: 2 of 3 scenes done" in run.stdout
    assert not (output / "03-kutu.mp4").exists() and not (output / "03-kutu" / "03-kutu.blend").exists()
    assert all((output / f"{scene}.mp4").is_file() for scene in GOOD)


def test_running_the_job_again_skips_what_is_done(episode):
    job, output, _, frames = episode
    chunks = output / "02-yol" / "chunks"
    before = {path.name: path.stat().st_mtime_ns for path in chunks.iterdir()}
    again = _episode("run", job, "--scene", "02-yol")
    assert again.returncode == 0, again.stdout[-3000:]
    assert "02-yol: built already from these files" in again.stdout
    assert again.stdout.count("rendered already from this .blend") == len(before) // 2
    assert {path.name: path.stat().st_mtime_ns for path in chunks.iterdir()} == before


def _process_writing(path: Path) -> int | None:
    """The process whose command line names the file (the chunk's Blender, rendering into it)."""
    for entry in Path("/proc").iterdir():
        try:
            if entry.name.isdigit() and str(path).encode() in (entry / "cmdline").read_bytes():
                return int(entry.name)
        except OSError:
            continue
    return None


def test_a_chunk_killed_midway_is_rendered_again_alone_and_the_join_is_still_one_render(episode):
    job, output, _, frames = episode
    chunks, last = output / "01-kafe" / "chunks", frames["01-kafe"][1]
    for path in chunks.glob("frames-0005-0008.*"):  # the chunk as it is before it was ever rendered
        path.unlink()
    others = {path.name: path.stat().st_mtime_ns for path in chunks.iterdir()}
    partial = chunks / ".frames-0005-0008.partial.mp4"
    command = [OPENJD, "run", str(job / "template.json"), "-p", f"file://{job / 'parameters.json'}"]
    command += ["--step", "01-kafe render", "--task-param", "Frames=5-8"]
    task = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    started, killed = time.monotonic(), None
    while killed is None and time.monotonic() - started < 120 and task.poll() is None:
        if partial.exists() and (pid := _process_writing(partial)) is not None:
            os.kill(pid, signal.SIGKILL)  # while Blender writes the chunk's frames
            killed = pid
        time.sleep(0.002)
    log = task.communicate(timeout=120)[0]
    assert killed is not None, log[-3000:]
    assert task.returncode != 0
    assert "01-kafe frames 5-8: its Blender process was killed (SIGKILL) before it finished" in log
    assert not (chunks / "frames-0005-0008.mp4").exists() and not partial.exists()

    join = _openjd(job, "--step", "01-kafe join")
    assert join.returncode != 0 and "frames 5-8 of 1-" in join.stdout  # the join refuses the gap

    rerun = _openjd(job, "--step", "01-kafe render", "--task-param", "Frames=5-8")
    assert rerun.returncode == 0, rerun.stdout[-3000:]
    assert rerun.stdout.count("01-kafe frames ") == 1  # that chunk alone
    assert {name: (chunks / name).stat().st_mtime_ns for name in others} == others
    join = _openjd(job, "--step", "01-kafe join")
    assert join.returncode == 0, join.stdout[-3000:]
    _assert_same_media(output / "01-kafe.mp4", _single_render(output, "01-kafe", last), last)


def test_a_scene_changed_after_the_job_was_made_fails_its_build_and_asks_for_the_job_again(tmp_path):
    (tmp_path / "a.jsml").write_text("Ama.\n", encoding="utf-8")
    (tmp_path / "episode.toml").write_text('[episode]\nfps = 8\nresolution = "32x32"\n', encoding="utf-8")
    assert _episode("job", tmp_path, "--out", tmp_path / "job").returncode == 0
    (tmp_path / "a.jsml").write_text("Ama baba geldi mi?\n", encoding="utf-8")  # a longer line since
    run = _episode("run", tmp_path / "job", "--step", "build")
    assert run.returncode == 1
    (error,) = [line for line in run.stdout.splitlines() if "episode.py: error:" in line]
    assert "a: the scene was built with frames 1-" in error and "make the job again" in error
    assert not (tmp_path / "job" / "output" / "a" / "a.blend").exists()
