"""The panel's Export Animation and Cue File: exports that match the head's keys, cue files that time it."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

bpy = pytest.importorskip("bpy")

from turkish_lipsync import blender  # noqa: E402
from turkish_lipsync.blender import compat, keyframes  # noqa: E402
from turkish_lipsync.core.interchange import export_formats  # noqa: E402
from turkish_lipsync.core.speech.cues import read_cue_file  # noqa: E402

REPOSITORY = Path(__file__).resolve().parents[2]
TEXT = "Merhaba, benim adım Erdem."
FPS = 24


@pytest.fixture(scope="module", autouse=True)
def registered():
    blender.register()
    yield
    blender.unregister()


@pytest.fixture(scope="module")
def saved(tmp_path_factory) -> Path:
    blend = tmp_path_factory.mktemp("export_operator") / "scene.blend"
    result = subprocess.run(
        [sys.executable, str(REPOSITORY / "scripts" / "render.py"), "--text", TEXT, "--no-render",
         "--save-blend", str(blend), "--fps", str(FPS)],
        capture_output=True, text=True, timeout=600, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    return blend


def _open(blend: Path, text: str = TEXT):
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    settings = bpy.context.scene.turkish_lipsync
    settings.head = bpy.data.objects["TR_Head"]
    block = bpy.data.texts.new("speech")
    block.write(text)
    settings.source_kind, settings.text = "TEXT", block
    return settings


def _curve_value(name: str, frame: float) -> float:
    action = bpy.data.objects["TR_Head"].data.shape_keys.animation_data.action
    wanted = keyframes.curve_data_path(name)
    curve = next(fc for fc in compat.all_action_fcurves(action) if fc.data_path == wanted)
    return curve.evaluate(frame)


def test_every_format_is_exported_and_the_cues_match_the_keys(saved, tmp_path):
    settings = _open(saved)
    for export_format, chosen in export_formats().items():
        suffix = chosen.suffix
        settings.export_format = export_format
        settings.export_path = str(tmp_path / "speech.txt")
        assert bpy.ops.turkish_lipsync.export_animation() == {"FINISHED"}
        assert (tmp_path / f"speech{suffix}").is_file()
    document = json.loads((tmp_path / "speech.json").read_text(encoding="utf-8"))
    assert (tmp_path / document["metadata"]["soundFile"]).resolve().is_file()
    # "benim" opens with closed lips: the A cue there is where the head's b key is at its closure
    cues = read_cue_file(tmp_path / "speech.json").cues
    pause = next(cue for cue in cues if cue.shape == "X" and cue.start > 0)  # the comma after "Merhaba"
    closure = next(cue for cue in cues if cue.shape == "A" and cue.start >= pause.end)
    start = bpy.context.scene.frame_start
    frames = [start + closure.start * FPS + offset for offset in (-1, 0, 1, 2)]
    assert max(_curve_value("TR_viseme_bpe", frame) for frame in frames) > 0.9


def test_another_text_is_not_exported_as_this_animation(saved, tmp_path):
    settings = _open(saved, text="Bu sabah vapura bindi.")
    settings.export_format, settings.export_path = "rhubarb-tsv", str(tmp_path / "other.tsv")
    with pytest.raises(RuntimeError, match="was not generated from this text"):
        bpy.ops.turkish_lipsync.export_animation()
    assert not (tmp_path / "other.tsv").exists()


def test_a_papagayo_project_times_generate_with_its_own_text(saved, tmp_path):
    settings = _open(saved)
    settings.export_format, settings.export_path = "papagayo-pgo", str(tmp_path / "speech.pgo")
    assert bpy.ops.turkish_lipsync.export_animation() == {"FINISHED"}
    settings.text = None
    settings.cue_file = str(tmp_path / "speech.pgo")
    assert bpy.ops.turkish_lipsync.generate.poll()
    assert bpy.ops.turkish_lipsync.generate() == {"FINISHED"}
    action = bpy.data.objects["TR_Head"].data.shape_keys.animation_data.action
    assert action.name.startswith("TR_merhaba benim")
