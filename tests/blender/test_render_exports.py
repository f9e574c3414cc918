"""render.py --export and --cues: the batch script writes the exports and reads cue files as the timing."""

import json

import pytest

bpy = pytest.importorskip("bpy")

from tests.render_runs import run_render  # noqa: E402
from turkish_lipsync.blender import compat, keyframes  # noqa: E402
from turkish_lipsync.core.interchange.arkit_csv import read_arkit_csv  # noqa: E402
from turkish_lipsync.core.speech.cues import read_cue_file  # noqa: E402

TEXT = "Merhaba, benim adım Erdem."


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    folder = tmp_path_factory.mktemp("exports")
    result = run_render(
        "--text", TEXT, "--no-render", "--save-blend", str(folder / "scene.blend"), "--fps", "24",
        "--export", f"rhubarb-json={folder / 'cues' / 'speech.json'}",
        "--export", f"papagayo-pgo={folder / 'speech.pgo'}",
        "--export", f"arkit-csv={folder / 'speech.csv'}",
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    return folder


def test_exports_are_written_and_name_the_speech(exported):
    document = json.loads((exported / "cues" / "speech.json").read_text(encoding="utf-8"))
    wav = (exported / "cues" / document["metadata"]["soundFile"]).resolve()
    assert wav.is_file() and wav.parent.name == "lipsync_audio"
    cues = read_cue_file(exported / "cues" / "speech.json").cues
    assert cues[0].start == 0 and abs(cues[-1].end - document["metadata"]["duration"]) < 1e-6
    bpy.ops.wm.open_mainfile(filepath=str(exported / "scene.blend"))
    scene = bpy.context.scene
    frames, weights = read_arkit_csv(exported / "speech.csv", 24)
    assert len(frames) == scene.frame_end - scene.frame_start + 1 and weights.shape[1] == 52  # a row a frame


def test_a_papagayo_project_times_the_animation_with_its_own_text(exported, tmp_path):
    blend = tmp_path / "from_cues.blend"
    result = run_render(
        "--cues", str(exported / "speech.pgo"), "--no-render", "--save-blend", str(blend), "--fps", "24"
    )
    assert result.returncode == 0, result.stderr
    assert "Generated 21 phones" in result.stdout
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    head = next(o for o in bpy.data.objects if o.type == "MESH" and o.data.shape_keys is not None)
    action = head.data.shape_keys.animation_data.action
    assert action.name.startswith("TR_merhaba")
    closing = [
        fc
        for fc in compat.all_action_fcurves(action)
        if fc.data_path == keyframes.curve_data_path("TR_viseme_bpe")
    ]
    assert (
        closing and max(point.co[1] for point in closing[0].keyframe_points) > 0.9
    )  # "benim" closes the lips


def test_an_unknown_export_format_is_refused():
    result = run_render("--text", TEXT, "--no-render", "--export", "rhubarb-srt=x.srt")
    assert result.returncode == 2 and "rhubarb-srt" in result.stderr
