"""scripts/render.py end to end, as a pipeline runs it: MP4 with sound, a .blend, a second run on it."""

import json
import subprocess
import sys

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
av = pytest.importorskip("av")
soundfile = pytest.importorskip("soundfile")

from tests.render_runs import REPOSITORY, run_render  # noqa: E402
from turkish_lipsync.blender import compat, heads, keyframes, living, owned_keys, sequencer  # noqa: E402

SENTENCE = "Şu köşe yaz köşesi"


def _our_key_names(obj) -> set[str]:
    return {k.name for k in obj.data.shape_keys.key_blocks if k.name.startswith("TR_")}


def _points(fcurve) -> tuple:
    return tuple(tuple(round(c, 5) for c in key.co) for key in fcurve.keyframe_points)


def _snapshot() -> dict:
    """Everything in the open file that is not ours: it must survive a second run unchanged."""
    objects = {}
    for obj in bpy.data.objects:
        keys = getattr(obj.data, "shape_keys", None)
        user_keys = (
            tuple((k.name, round(k.value, 6)) for k in keys.key_blocks if not k.name.startswith("TR_"))
            if keys is not None
            else ()
        )
        objects[obj.name] = (obj.type, tuple(round(x, 6) for x in obj.location), user_keys)
    actions = {}
    ours = keyframes.our_curve_paths(bpy.data.objects)
    for action in bpy.data.actions:
        curves = tuple(
            (fc.data_path, fc.array_index, _points(fc))
            for fc in compat.all_action_fcurves(action)
            if fc.data_path not in ours
            and fc.data_path not in action.get(living.CURVES_PROPERTY, ())  # the living face's, marked ours
        )
        if curves:
            actions[action.name] = curves
    strips = compat.sequencer_strips(bpy.context.scene, create=False) or []
    other_strips = sorted((s.name, s.channel, s.frame_start) for s in strips if s.name != "TR_speech")
    texts = sorted(bpy.data.texts.keys())
    return {"objects": objects, "actions": actions, "strips": other_strips, "texts": texts}


@pytest.fixture(scope="module")
def first_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("render_script")
    out, blend = folder / "x.mp4", folder / "x.blend"
    result = run_render(
        "--text", SENTENCE, "--out", str(out), "--save-blend", str(blend),
        "--resolution", "64x36", "--samples", "1", "--engine", "cycles",
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    return folder, out, blend, result.stdout


def test_the_video_has_sound_and_lasts_as_long_as_the_speech(first_run):
    folder, out, _, _ = first_run
    wavs = list((folder / "lipsync_audio").glob("*.wav"))
    assert len(wavs) == 1
    speech_seconds = soundfile.info(str(wavs[0])).duration
    with av.open(str(out)) as container:
        video, audio = container.streams.video[0], container.streams.audio[0]
        video_seconds = float(video.duration * video.time_base)
        audio_seconds = float(audio.duration * audio.time_base)
        assert (video.codec_context.name, audio.codec_context.name) == ("h264", "aac")
    assert abs(video_seconds - speech_seconds) <= 1 / 25
    assert abs(audio_seconds - speech_seconds) <= 1 / 25


def test_the_saved_blend_holds_keys_curves_and_the_speech(first_run):
    _, _, blend, _ = first_run
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    head = bpy.data.objects["TR_Head"]
    names = _our_key_names(head)
    assert len({n for n in names if n.startswith(("TR_viseme_", "TR_emotion_")) and "release" not in n}) == 43
    action = head.data.shape_keys.animation_data.action
    assert action.name == "TR_şu köşe yaz köşesi"
    ours = keyframes.our_curve_paths([head])
    curves = [fc for fc in compat.all_action_fcurves(action) if fc.data_path in ours]
    assert len(curves) > 5 and all(len(fc.keyframe_points) >= 2 for fc in curves)
    scene = bpy.context.scene
    wav = sequencer.speech_wav_of(scene)
    assert wav is not None and wav.is_file()
    assert scene[sequencer.SPEECH_PATH_PROPERTY].startswith("//")  # relative: moves with the .blend
    if compat.HAS_AUDIO:
        assert sequencer.speech_strip(scene) is not None
    assert scene.camera is not None


def test_a_second_run_on_the_saved_blend_changes_only_ours(first_run, tmp_path):
    _, _, blend, _ = first_run
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    # The user's own work in the file: an animated object, a key and its curve on the head, a text.
    bpy.ops.mesh.primitive_cube_add(location=(2.0, 0.0, 0.0))
    cube = bpy.context.active_object
    cube.name = "UserCube"
    cube.keyframe_insert("location", frame=5)
    head = bpy.data.objects["TR_Head"]
    smile = head.shape_key_add(name="MySmile")
    smile.value = 0.3
    smile.keyframe_insert("value", frame=12)
    bpy.data.texts.new("notes").write("benim notlarım")
    edited = tmp_path / "edited.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(edited))
    before = _snapshot()

    second = tmp_path / "second.blend"
    result = run_render(
        "--head", str(edited), "--text", "merhaba", "--save-blend", str(second), "--no-render"
    )
    assert result.returncode == 0, result.stderr

    bpy.ops.wm.open_mainfile(filepath=str(second))
    assert _snapshot() == before
    head = bpy.data.objects["TR_Head"]
    paths = {fc.data_path for fc in compat.all_action_fcurves(head.data.shape_keys.animation_data.action)}
    assert 'key_blocks["MySmile"].value' in paths
    assert paths & keyframes.our_curve_paths([head])
    strips = compat.sequencer_strips(bpy.context.scene, create=False)
    if compat.HAS_AUDIO:
        assert [s.name for s in strips].count("TR_speech") == 1


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (("--text", "<SENT><HAPPY>merhaba</SENT>", "--no-render"), "JSML error at line 1"),
        (("--text", "merhaba"), "--out OUT.mp4 is required"),
        (("--text", "merhaba", "--no-render", "--head", "/nonexistent/head.obj"), "does not exist"),
        (("--text", "merhaba", "--no-render", "--resolution", "big"), "is not WIDTHxHEIGHT"),
        (("--jsml", "a.jsml", "--text", "merhaba"), "not allowed with"),
        (("--text", "merhaba", "--no-render", "--built-json", "b.json"), "--save-blend OUT.blend with it"),
        (("--frames", "1-2", "--out", "c.mp4", "--built-json", "b.json"), "drop --built-json"),
    ],
)
def test_errors_are_one_clear_line_and_a_nonzero_exit(arguments, message):
    result = run_render(*arguments)
    assert result.returncode != 0
    assert "Traceback" not in result.stderr
    error_lines = [line for line in result.stderr.splitlines() if line.startswith("render.py: error:")]
    assert len(error_lines) == 1 and message in error_lines[0], result.stderr


def test_a_users_recording_replaces_the_synthetic_voice(tmp_path):
    # The "recording" is the same sentence spoken slower by the engine: a voice of another length.
    recording = tmp_path / "recording.wav"
    slower = f'<PROS RATE="-30%">{SENTENCE}</PROS>'
    made = subprocess.run(
        [sys.executable, "-m", "turkish_lipsync", "timeline", "--text", slower, "--wav", str(recording)],
        capture_output=True, text=True, timeout=300, cwd=REPOSITORY, check=False,
    )  # fmt: skip
    assert made.returncode == 0, made.stderr
    recorded_seconds = soundfile.info(str(recording)).duration
    result = run_render(
        "--text",
        SENTENCE,
        "--audio",
        str(recording),
        "--no-render",
        "--save-blend",
        str(tmp_path / "r.blend"),
    )
    assert result.returncode == 0, result.stderr
    generated = next(line for line in result.stdout.splitlines() if line.startswith("Generated"))
    seconds = float(generated.split(",")[1].split()[0])
    assert seconds == pytest.approx(recorded_seconds, abs=0.15)
    missing = run_render("--text", SENTENCE, "--audio", str(tmp_path / "none.wav"), "--no-render")
    assert missing.returncode != 0 and "--audio" in missing.stderr and "Traceback" not in missing.stderr


def test_a_users_own_tr_keys_survive_a_rebuild_and_are_never_keyed(tmp_path):
    """Keys of the user's own that carry our prefix, one of them our very name: --rebuild-keys leaves
    them as they are, builds ours beside them under free names, says so, and keys only ours."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    head = heads.create_reference_head(bpy.context)["head"]
    head.shape_key_add(name="Basis", from_mix=False)
    sculpts = {}
    for name in ("TR_viseme_a", "TR_mine"):
        block = head.shape_key_add(name=name, from_mix=False)
        block.data[0].co.z += 0.01
        sculpts[name] = np.array([point.co[:] for point in block.data])
    mine = tmp_path / "mine.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(mine))
    out = tmp_path / "out.blend"
    result = run_render(
        "--head", str(mine), "--text", "merhaba", "--rebuild-keys", "--no-render", "--save-blend", str(out)
    )
    assert result.returncode == 0, result.stderr
    assert "has a key of its own named 'TR_viseme_a'" in result.stdout + result.stderr
    bpy.ops.wm.open_mainfile(filepath=str(out))
    head = bpy.data.objects["TR_Head"]
    blocks = head.data.shape_keys.key_blocks
    for name, points in sculpts.items():
        np.testing.assert_array_equal(np.array([point.co[:] for point in blocks[name].data]), points)
    assert owned_keys.owned_keys(head)["TR_viseme_a"] == "TR_viseme_a.001"
    paths = {fc.data_path for fc in compat.all_action_fcurves(head.data.shape_keys.animation_data.action)}
    assert 'key_blocks["TR_viseme_a.001"].value' in paths
    assert not paths & {'key_blocks["TR_viseme_a"].value', 'key_blocks["TR_mine"].value'}


def test_a_recording_alone_is_recognised(tmp_path):
    from lab.kit.voices import TEST_VOICES, make_take

    take, truth, lead, _ = make_take(
        "Bu sabah babam bana mavi bir kalem aldı.", TEST_VOICES["Andrea"], "clean 60 dB", tmp_path,
        np.random.default_rng(1),
    )  # fmt: skip
    result = run_render("--audio", str(take), "--no-render", "--save-blend", str(tmp_path / "r.blend"))
    assert result.returncode == 0, result.stderr
    generated = next(line for line in result.stdout.splitlines() if line.startswith("Generated"))
    assert int(generated.split()[1]) >= 0.7 * len(truth.phones)
    assert "Traceback" not in result.stderr


def test_the_built_json_names_the_saved_scenes_frames_and_speech(tmp_path):
    """What an episode's build step reads (core/farm/tasks.py): the saved scene's frame range and its WAV."""
    blend, built = tmp_path / "scene.blend", tmp_path / "built.json"
    result = run_render(
        "--text", "Ama baba.", "--fps", "8", "--no-render", "--save-blend", blend, "--built-json", built
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    described = json.loads(built.read_text(encoding="utf-8"))
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    scene = bpy.context.scene
    assert described["frames"] == [scene.frame_start, scene.frame_end] and scene.frame_end > scene.frame_start
    wav = sequencer.speech_wav_of(scene)
    assert wav is not None and described["speech"] == str(wav) and wav.is_file()
    assert wav.parent == tmp_path / "lipsync_audio"
