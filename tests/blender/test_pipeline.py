"""One pipeline: the CLI gives what the panel keys; Blender shows phones on time; warnings reach the user."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from turkish_lipsync.blender import compat, heads, keyframes, owned_keys, shapekeys  # noqa: E402
from turkish_lipsync.blender.generate import generate  # noqa: E402
from turkish_lipsync.core.faces.arkit_names import ARKIT_UNITS  # noqa: E402
from turkish_lipsync.core.pipeline import LipSyncOptions, lip_sync  # noqa: E402

pytestmark = pytest.mark.usefixtures("registered_extension")

ROOT = Path(__file__).resolve().parents[2]
TEXT = "<HAPPY>Merhaba</HAPPY>, benim adım Erdem. Bu sabah vapura binip geçtim."


@pytest.fixture
def reference_head():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.render.fps = 25
    objects = heads.create_reference_head(bpy.context)
    shapekeys.build_shape_keys(objects["head"])
    return objects["head"]


def _cli_tracks(*arguments: str) -> dict:
    result = subprocess.run(
        [sys.executable, "-m", "turkish_lipsync", "timeline", "--text", TEXT, "--format", "json", *arguments],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
    )
    return json.loads(result.stdout)["tracks"]


def _keyed(head) -> dict[str, np.ndarray]:
    """(frame, value) of every keyframe Blender holds on the head's TR_* keys."""
    action = head.data.shape_keys.animation_data.action
    curves = {}
    for fcurve in compat.all_action_fcurves(action):
        name = fcurve.data_path.split('"')[1]
        points = np.empty(len(fcurve.keyframe_points) * 2)
        fcurve.keyframe_points.foreach_get("co", points)
        curves[name] = points.reshape(-1, 2)
    return curves


@pytest.mark.parametrize("timing, frame_tolerance", [("table", 1e-4), ("phone", 0.5)])
def test_the_command_line_gives_the_tracks_the_panel_writes(reference_head, timing, frame_tolerance):
    settings = bpy.context.scene.turkish_lipsync
    settings.head = reference_head
    block = bpy.data.texts.new("speech")
    block.write(TEXT)
    settings.source_kind, settings.text = "TEXT", block
    settings.timing, settings.motion, settings.rate, settings.emotion_strength = timing, "thesis", 1.4, 0.5
    assert bpy.ops.turkish_lipsync.generate() == {"FINISHED"}
    keyed = _keyed(reference_head)
    printed = _cli_tracks(
        "--timing", timing, "--rate", "1.4", "--emotion-strength", "0.5", "--motion", "thesis", "--fps", "25"
    )
    assert printed["interpolation"] == "LINEAR"
    assert set(printed["keys"]) == set(keyed)
    start = bpy.context.scene.frame_start
    for name, track in printed["keys"].items():
        frames = np.asarray(track["frames"]) + start
        assert len(frames) == len(keyed[name]), name
        # eSpeak NG's output depends a little on what it spoke before in the process (a sentence's phones
        # move by up to ~10 ms, measured), so a fresh CLI process and the panel agree to half a frame;
        # table timing is exact.
        np.testing.assert_allclose(keyed[name][:, 0], frames, atol=frame_tolerance, err_msg=name)
        np.testing.assert_allclose(keyed[name][:, 1], track["values"], atol=1e-5, err_msg=name)


@pytest.mark.parametrize("fps", [24, 25, 30, 60])
def test_blender_shows_each_spoken_phone_on_the_whole_frame_nearest_its_onset(reference_head, fps):
    """On the frame nearest each phone the engine spoke, the evaluated face shows that phone's viseme.

    The truth is the engine's own phone events; what is checked is the weight Blender evaluates on whole
    frames of the written action (thesis motion: linear morphs between letter models).
    """
    scene = bpy.context.scene
    scene.render.fps = fps
    result = lip_sync(
        "Babam bana mavi bir kalem aldı, şimdi okula gidiyoruz.", LipSyncOptions(motion="thesis", fps=fps)
    )
    keyframes.write_weight_tracks([reference_head], result.tracks, scene.frame_start, "TR_check")
    letters = result.utterance.letters
    events = result.synthesis.phone_events
    onsets = np.array([event.start for event in events])
    checked = 0
    for number, event in enumerate(events):
        if not event.letters:
            continue
        # Linear morphing puts the viseme above half weight within half a frame of its onset when the
        # phone and the one before it last a frame or more.
        before = onsets[number] - onsets[number - 1] if number else event.end - event.start
        if min(before, event.end - event.start) < 1.0 / fps:
            continue
        frame = round(event.start * fps)
        scene.frame_set(scene.frame_start + frame)
        viseme = letters[event.letters[0]].viseme
        weight = reference_head.data.shape_keys.key_blocks[f"TR_viseme_{viseme}"].value
        assert weight >= 0.5 - 1e-4, (letters[event.letters[0]].char, event.start, frame, weight)
        checked += 1
    assert checked >= 0.6 * len(events)


def test_a_head_lacking_units_is_warned_by_the_build_and_the_operator(capfd):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    head = heads.create_reference_head(bpy.context)["head"]
    shapekeys.build_shape_keys(head, parts=[], arkit_keys=True)
    head["tr_reference_part"] = "not the reference"
    head.location.x += 1.0  # away from the reference's place: only its own ARKit keys count
    owned_keys.disown(head, ARKIT_UNITS)  # our ARKit keys, handed over as if an artist had made them
    for name in ("mouthRollUpper", "mouthRollLower", "cheekPuff", "browInnerUp"):
        head.shape_key_remove(head.data.shape_keys.key_blocks[name])
    report = shapekeys.build_shape_keys(head, parts=[])
    assert report.source == "arkit"
    assert set(report.missing_units) == {"mouthRollUpper", "mouthRollLower", "cheekPuff", "browInnerUp"}
    assert len(report.warnings) == 1 and "mouthRollUpper" in report.warnings[0]

    bpy.context.scene.turkish_lipsync.head = head
    bpy.context.scene.turkish_lipsync.key_source = "arkit"
    capfd.readouterr()
    assert bpy.ops.turkish_lipsync.build_shape_keys() == {"FINISHED"}
    printed = capfd.readouterr()
    assert "Warning:" in printed.out + printed.err and "cheekPuff" in printed.out + printed.err


def test_a_cancelled_render_leaves_the_scene_as_it_was_and_no_partial_video(reference_head, tmp_path):
    from turkish_lipsync.blender import pipeline

    scene = bpy.context.scene
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x, scene.render.resolution_y = 321, 123
    scene.render.filepath = "//my_frames/"
    before_objects = set(bpy.data.objects.keys())
    before = (
        scene.render.engine,
        scene.render.resolution_x,
        scene.render.filepath,
        scene.camera,
        scene.world,
    )
    before_format = scene.render.image_settings.file_format
    out = tmp_path / "clip.mp4"
    prepared = pipeline.prepare_render(bpy.context, reference_head, str(out), engine="CYCLES", samples=2)
    assert scene.render.engine == "CYCLES" and scene.camera is not None
    assert set(bpy.data.objects.keys()) > before_objects  # camera and lights were added
    out.write_bytes(b"half a video")  # what an interrupted render leaves
    pipeline.cancel_render(bpy.context, prepared)
    after = (scene.render.engine, scene.render.resolution_x, scene.render.filepath, scene.camera, scene.world)
    assert after == before
    assert scene.render.image_settings.file_format == before_format
    assert set(bpy.data.objects.keys()) == before_objects
    assert not out.exists()


def test_own_keys_held_at_a_value_are_warned_and_put_at_rest_only_when_asked(reference_head):
    """A head that arrives with its own keys on (Vitruvian's file holds all 148 at 1): the speech would play
    on a deformed face. Generate says so; the keys change only when asked, animated ones never."""
    from turkish_lipsync.blender import pipeline

    block = reference_head.shape_key_add(name="Grin", from_mix=False)
    block.data[0].co.z += 0.01
    block.value = 0.8
    animated = reference_head.shape_key_add(name="Wink", from_mix=False)
    animated.value = 0.5
    animated.keyframe_insert("value", frame=1)
    result = generate(bpy.context, "Ama", LipSyncOptions(timing="table"), head=reference_head)
    (warning,) = [w for w in result.warnings if "own shape keys hold a value" in w]
    assert warning.startswith("1 of") and "Grin 0.80" in warning and "Wink" not in warning
    assert block.value == pytest.approx(0.8)
    assert pipeline.put_own_keys_at_rest(reference_head) == 1 and block.value == 0.0
    assert animated.value == pytest.approx(0.5)
    result = generate(bpy.context, "Ama", LipSyncOptions(timing="table"), head=reference_head)
    assert not [w for w in result.warnings if "own shape keys hold a value" in w]
