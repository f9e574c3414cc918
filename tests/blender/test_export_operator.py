"""The panel's Export Animation and Cue File: exports that match the head's keys, cue files that time it."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

bpy = pytest.importorskip("bpy")

from turkish_lipsync.blender import compat, exports, keyframes  # noqa: E402
from turkish_lipsync.core.interchange import export_formats  # noqa: E402
from turkish_lipsync.core.interchange.arkit_csv import LIVE_LINK_UNITS, read_arkit_csv  # noqa: E402
from turkish_lipsync.core.speech.cues import read_cue_file  # noqa: E402

pytestmark = pytest.mark.usefixtures("registered_extension")

REPOSITORY = Path(__file__).resolve().parents[2]
TEXT = "Merhaba, benim adım Erdem."
FPS = 24


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
    assert _closure_of_benim_is_keyed(read_cue_file(tmp_path / "speech.json").cues)


def _closure_of_benim_is_keyed(cues) -> bool:
    """ "benim" opens with closed lips: the A cue there must be where the head's b key is at its closure."""
    pause = next(cue for cue in cues if cue.shape == "X" and cue.start > 0)  # the comma after "Merhaba"
    closure = next(cue for cue in cues if cue.shape == "A" and cue.start >= pause.end)
    start = bpy.context.scene.frame_start
    frames = [start + closure.start * FPS + offset for offset in (-1, 0, 1, 2)]
    return max(_curve_value("TR_viseme_bpe", frame) for frame in frames) > 0.9


def test_an_export_after_the_settings_changed_describes_the_keys_the_head_has(saved, tmp_path):
    """Generate at the normal rate, then the panel is changed (half the rate, another text, table timing):
    the export still describes the animation on the head, not one the new settings would make."""
    settings = _open(saved, text="Bu sabah vapura bindi.")
    settings.rate, settings.timing = 0.5, "table"
    settings.export_format, settings.export_path = "rhubarb-json", str(tmp_path / "later.json")
    assert bpy.ops.turkish_lipsync.export_animation() == {"FINISHED"}
    assert _closure_of_benim_is_keyed(read_cue_file(tmp_path / "later.json").cues)
    settings.export_format, settings.export_path = "arkit-csv", str(tmp_path / "later.csv")
    assert bpy.ops.turkish_lipsync.export_animation() == {"FINISHED"}
    frames, weights = read_arkit_csv(tmp_path / "later.csv", FPS)
    jaw = LIVE_LINK_UNITS.index("jawOpen")
    start = bpy.context.scene.frame_start
    # the a of "Merhaba" opens the jaw in the CSV on the frames where the head's a key opens the mouth
    opened = [frame for frame in frames if _curve_value("TR_viseme_a", start + frame) > 0.8]
    assert opened and all(weights[int(frame), jaw] > 0.2 for frame in opened)


def test_the_live_link_csv_has_one_row_per_frame_of_the_scene(saved, tmp_path):
    """Generate sets the scene's frames to the speech; the CSV describes exactly those frames (it had two
    rows more: the motion's tracks reach a frame past the speech's end, which the scene does not show)."""
    settings = _open(saved)
    settings.export_format, settings.export_path = "arkit-csv", str(tmp_path / "speech.csv")
    assert bpy.ops.turkish_lipsync.export_animation() == {"FINISHED"}
    frames, _ = read_arkit_csv(tmp_path / "speech.csv", FPS)
    scene = bpy.context.scene
    assert len(frames) == scene.frame_end - scene.frame_start + 1
    assert frames[0] == 0 and frames[-1] == scene.frame_end - scene.frame_start


def test_keys_edited_by_hand_are_exported_as_they_are_with_a_warning(saved, tmp_path):
    _open(saved)
    head = bpy.data.objects["TR_Head"]
    action = head.data.shape_keys.animation_data.action
    wanted = keyframes.curve_data_path("TR_viseme_a")
    curve = next(fc for fc in compat.all_action_fcurves(action) if fc.data_path == wanted)
    peak = max(curve.keyframe_points, key=lambda point: point.co[1])
    peak.co[1] = 0.25  # the animator softens the widest a
    result = exports.export_animation(bpy.context, head, "arkit-csv", tmp_path / "edited.csv")
    assert any("changed after Generate Animation" in warning for warning in result.warnings)
    _, weights = read_arkit_csv(tmp_path / "edited.csv", FPS)
    frame = round(peak.co[0]) - bpy.context.scene.frame_start
    before = arkit_weights_of_keys(head, frame)
    assert weights[frame, LIVE_LINK_UNITS.index("jawOpen")] == pytest.approx(before, abs=1e-5)


def arkit_weights_of_keys(head, frame: int) -> float:
    """jawOpen at a frame as the head's keys hold it now: each key's weight times its recipe's jawOpen."""
    from turkish_lipsync.core.faces.recipes import load_recipes

    start = bpy.context.scene.frame_start
    total = 0.0
    for name, recipe in load_recipes().key_recipes().items():
        if recipe.get("jawOpen") and name in head.data.shape_keys.key_blocks:
            try:
                total += _curve_value(name, start + frame) * recipe["jawOpen"]
            except StopIteration:  # a key with no curve rests at zero
                pass
    return min(max(total, 0.0), 1.0)


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
