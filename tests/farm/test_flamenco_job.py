"""The Flamenco job type submitted from Blender: its compiler authors chunk renders and a join of the open
.blend, and those commands really run.

Flamenco's Manager is not available here; tests/farm/flamenco_compile.js gives compileJob() the globals the
Manager gives it. Each authored command is then run as a worker runs it, with the Manager's {blender}
variable empty: the tasks' Blender is then the bpy module of the Python that runs them. (An episode's scene,
with its build, is checked against the Open Job Description job in test_jobs.py.)
"""

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

av = pytest.importorskip("av")
pytest.importorskip("bpy")

REPOSITORY = Path(__file__).resolve().parents[2]
JOB_TYPE = REPOSITORY / "farm" / "flamenco" / "turkish_lipsync.js"
SCRIPT = REPOSITORY / "scripts" / "render.py"
NODE = shutil.which("node")


def _compile(tmp_path: Path, settings: dict) -> list[dict]:
    settings_file = tmp_path / "settings.json"
    settings_file.write_text(json.dumps(settings), encoding="utf-8")
    result = subprocess.run(
        [NODE, str(Path(__file__).with_name("flamenco_compile.js")), str(JOB_TYPE), str(settings_file)],
        capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


def _run(command: list[str]) -> None:
    result = subprocess.run(command, capture_output=True, text=True, timeout=600, check=False)
    assert result.returncode == 0, result.stderr[-2000:]


@pytest.mark.skipif(NODE is None, reason="needs node to run the job compiler")
def test_the_job_renders_chunks_on_workers_and_joins_them_with_the_speech(tmp_path):
    blend = tmp_path / "shot.blend"
    _run([sys.executable, str(SCRIPT), "--text", "Ama baba", "--no-render", "--save-blend", str(blend),
          "--resolution", "32x32", "--fps", "25"])  # fmt: skip
    wav = next((tmp_path / "lipsync_audio").glob("*.wav"))
    import bpy

    bpy.ops.wm.open_mainfile(filepath=str(blend))
    last = bpy.context.scene.frame_end
    tasks = _compile(
        tmp_path,
        {
            "frames": f"1-{last}",
            "chunk_size": 4,
            "engine": "CYCLES",
            "samples": 1,
            "checkout": str(REPOSITORY),
            "python": sys.executable,
            "speech_wav": str(wav),
            "render_output_path": str(tmp_path / "out" / "{timestamp}" / "shot.mp4"),
            "blendfile": str(blend),
        },
    )
    renders, join = tasks[:-1], tasks[-1]
    assert len(renders) == -(-last // 4) and {task["type"] for task in renders} == {"blender"}
    assert join["type"] == "misc" and join["dependencies"] == [task["name"] for task in renders]
    assert not any(task["name"] == "build" for task in tasks)  # the .blend is built already
    for task in renders:  # any order: each worker renders its own chunk
        (command,) = task["commands"]
        assert command["name"] == "exec" and f"--blend={blend}" in command["parameters"]["args"]
        _run_on_worker(command)
    (command,) = join["commands"]
    _run_on_worker(command)
    (video,) = (tmp_path / "out").glob("*/shot.mp4")
    with av.open(str(video)) as container:
        assert container.streams.audio and container.streams.video[0].frames == last
    assert sorted(path.name for path in video.parent.glob("chunks/*.mp4"))[0] == "frames-0001-0004.mp4"


def _run_on_worker(command: dict) -> None:
    """An exec command as a worker runs it, the Manager's variables replaced ({blender}: the bpy module)."""
    parameters = command["parameters"]
    _run([parameters["exe"], *(argument.replace("{blender}", "") for argument in parameters["args"])])


@pytest.mark.skipif(NODE is None, reason="needs node to run the job compiler")
def test_frames_with_gaps_are_refused(tmp_path):
    settings = {"frames": "1-4,8-9", "chunk_size": 10, "render_output_path": str(tmp_path / "x.mp4")}
    settings_file = tmp_path / "settings.json"
    settings_file.write_text(json.dumps(settings), encoding="utf-8")
    result = subprocess.run(
        [NODE, str(Path(__file__).with_name("flamenco_compile.js")), str(JOB_TYPE), str(settings_file)],
        capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip
    assert result.returncode != 0 and "must be one range START-END" in result.stderr


@pytest.mark.skipif(NODE is None, reason="needs node to read the job type")
def test_the_speech_setting_finds_the_wav_generate_wrote(tmp_path):
    """The Flamenco add-on evaluates each setting's `eval` in Blender (C = bpy.context, abspath = Blender's);
    in a scene saved after Generate the speech setting must name the WAV that Generate wrote."""
    blend = tmp_path / "shot.blend"
    _run([sys.executable, str(SCRIPT), "--text", "Ama baba", "--no-render", "--save-blend", str(blend)])
    (wav,) = (tmp_path / "lipsync_audio").glob("*.wav")
    import bpy

    bpy.ops.wm.open_mainfile(filepath=str(blend))
    result = subprocess.run(
        [NODE, str(Path(__file__).with_name("flamenco_compile.js")), str(JOB_TYPE), "--settings"],
        capture_output=True, text=True, timeout=60, check=True,
    )  # fmt: skip
    setting = next(s for s in json.loads(result.stdout) if s["key"] == "speech_wav")
    namespace = {"C": bpy.context, "D": bpy.data, "bpy": bpy, "abspath": bpy.path.abspath}
    assert Path(eval(setting["eval"], namespace)).resolve() == wav.resolve()
