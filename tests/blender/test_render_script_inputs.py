"""render.py never replaces what it reads, nor one of its outputs with another, and says so in one line
before anything is written; two scenes saved in one folder keep their own speech."""

import hashlib
import subprocess
import wave
from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
soundfile = pytest.importorskip("soundfile")

from tests.render_runs import run_render  # noqa: E402
from turkish_lipsync.blender import sequencer  # noqa: E402


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture()
def take(tmp_path) -> Path:
    """A user's own 48 kHz stereo recording."""
    path = tmp_path / "take.wav"
    t = np.arange(48000) / 48000
    tone = 0.1 * np.sin(2 * np.pi * 180 * t)
    soundfile.write(str(path), np.stack([tone, tone], axis=1), 48000)
    return path


def _refused(result: subprocess.CompletedProcess, message: str) -> None:
    assert result.returncode != 0
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0] and "Traceback" not in result.stderr, result.stderr


def test_outputs_that_are_inputs_are_refused_and_the_inputs_stay_as_they_were(tmp_path, take):
    before = _digest(take)
    (tmp_path / "link.wav").symlink_to(take)
    text = tmp_path / "speech.jsml"
    text.write_text("Merhaba.", encoding="utf-8")
    text_before = _digest(text)
    said = ["--text", "Merhaba.", "--no-render"]
    cases = [
        ([*said, "--audio", take, "--gltf", tmp_path / "take.glb"], "the speech WAV beside --gltf"),
        ([*said, "--audio", tmp_path / "link.wav", "--export", f"rhubarb-tsv={take}"], "file as --audio"),
        (["--jsml", text, "--no-render", "--export", f"rhubarb-tsv={text}"], "is the same file as --jsml"),
        ([*said, "--export", f"rhubarb-tsv={tmp_path / 'a'}", "--export", f"moho-dat={tmp_path / 'a'}"],
         "another output"),
    ]  # fmt: skip
    for arguments, message in cases:
        _refused(run_render(*arguments), message)
    assert _digest(take) == before and _digest(text) == text_before
    assert not (tmp_path / "take.glb").exists()


def test_outputs_that_cannot_be_written_are_refused_in_one_line(tmp_path):
    (tmp_path / "folder.glb").mkdir()
    _refused(run_render("--text", "Merhaba", "--no-render", "--gltf", tmp_path / "folder.glb"), "is a folder")
    _refused(
        run_render("--text", "Merhaba", "--no-render", "--gltf", "/sys/x.glb"), "cannot write the output"
    )


def test_a_still_frame_outside_the_animation_is_warned(tmp_path):
    result = run_render(
        "--text", "Ama", "--no-render", "--still", tmp_path / "still.png", "--still-frame", "900",
        "--engine", "cycles", "--samples", "1", "--resolution", "32x32",
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert "--still-frame 900 is outside the animation" in result.stderr


def test_two_scenes_saved_in_one_folder_keep_their_own_speech(tmp_path):
    """a.blend, then b.blend at half the rate: each plays its own WAV, and a.blend's is unchanged."""
    assert (
        run_render("--text", "Merhaba", "--no-render", "--save-blend", tmp_path / "a.blend").returncode == 0
    )
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "a.blend"))
    first = sequencer.speech_wav_of(bpy.context.scene)
    first_digest, first_frames = _digest(first), bpy.context.scene.frame_end
    result = run_render(
        "--text", "Merhaba", "--no-render", "--save-blend", tmp_path / "b.blend", "--rate", "0.5"
    )
    assert result.returncode == 0, result.stderr
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "b.blend"))
    second = sequencer.speech_wav_of(bpy.context.scene)
    assert second != first and _digest(first) == first_digest
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "a.blend"))
    with wave.open(str(sequencer.speech_wav_of(bpy.context.scene))) as handle:
        seconds = handle.getnframes() / handle.getframerate()
    assert abs(seconds * 25 - first_frames) <= 1  # a.blend still plays a speech as long as its animation


def _emotion_size(blend: Path) -> float:
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    keys = bpy.data.objects["TR_Head"].data.shape_keys.key_blocks
    basis, happy = np.empty(len(keys[0].points) * 3), np.empty(len(keys[0].points) * 3)
    keys[0].points.foreach_get("co", basis)
    keys["TR_emotion_happy"].points.foreach_get("co", happy)
    return float(np.abs(happy - basis).max())


def test_the_panels_build_settings_are_flags_too(tmp_path):
    """--key-source, --empowered and --rho build the keys as the panel's Head settings do."""
    plain, empowered = tmp_path / "plain.blend", tmp_path / "empowered.blend"
    assert run_render("--text", "Ama", "--no-render", "--save-blend", plain).returncode == 0
    result = run_render(
        "--text", "Ama", "--no-render", "--save-blend", empowered, "--empowered", "--rho", "2"
    )
    assert result.returncode == 0, result.stderr
    assert _emotion_size(empowered) == pytest.approx(2 * _emotion_size(plain), rel=1e-4)
    _refused(run_render("--text", "Ama", "--no-render", "--key-source", "obj_folder"), "go together")
    _refused(
        run_render("--text", "Ama", "--no-render", "--rho", "50"), "--rho 50.0 must lie between 1 and 10"
    )
