"""The three operators on the default head and on the shared heads: results, errors, undo, regenerate."""

from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from turkish_lipsync import blender  # noqa: E402
from turkish_lipsync.blender import compat, heads, pipeline, sequencer  # noqa: E402
from turkish_lipsync.core.model import EMOTIONS, emotion_key_name, viseme_key_name  # noqa: E402

# The thesis's 37 models (Table 5.1, Appendix B).
VISEMES = (
    "a bpa cjae dta fvae gkya la ma na ra sza ta e bpe dte gkye le me ne re sze I Ii o bpo cjo do fvo gkyo "
    "lo mo no ro szto oi u neutral"
).split()

HEADS = Path(__file__).resolve().parents[2].parent / "shared" / "heads"
SENTENCE = "Şu köşe yaz köşesi"


@pytest.fixture(scope="module", autouse=True)
def registered():
    blender.register()
    yield
    blender.unregister()


@pytest.fixture(autouse=True)
def empty_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.render.fps = 25
    yield


def _settings():
    return bpy.context.scene.turkish_lipsync


def _speak(text: str) -> None:
    block = bpy.data.texts.new("speech")
    block.write(text)
    _settings().source_kind = "TEXT"
    _settings().text = block


def _our_curves(obj) -> list:
    key = obj.data.shape_keys
    if key.animation_data is None or key.animation_data.action is None:
        return []
    return [
        fc
        for fc in compat.all_action_fcurves(key.animation_data.action)
        if fc.data_path.startswith('key_blocks["TR_')
    ]


def _default_head_with_keys():
    assert bpy.ops.turkish_lipsync.build_shape_keys() == {"FINISHED"}
    return _settings().head


def test_build_shape_keys_creates_the_reference_head_with_the_43_keys():
    head = _default_head_with_keys()
    names = set(head.data.shape_keys.key_blocks.keys())
    expected = {viseme_key_name(v) for v in VISEMES} | {emotion_key_name(e) for e in EMOTIONS}
    assert len(expected) == 43
    assert expected <= names
    # Building again replaces ours and leaves the user's own key alone.
    head.shape_key_add(name="MyOwnKey").value = 0.25
    assert bpy.ops.turkish_lipsync.build_shape_keys() == {"FINISHED"}
    key_blocks = head.data.shape_keys.key_blocks
    assert key_blocks["MyOwnKey"].value == pytest.approx(0.25)
    assert len([k for k in key_blocks.keys() if k == viseme_key_name("a")]) == 1


def test_generate_operator_keys_the_speech_and_places_the_audio():
    head = _default_head_with_keys()
    _speak(SENTENCE)
    assert bpy.ops.turkish_lipsync.generate() == {"FINISHED"}
    assert head.data.shape_keys.animation_data.action.name == "TR_şu köşe yaz köşesi"
    assert len(_our_curves(head)) > 5
    scene = bpy.context.scene
    wav = sequencer.speech_wav_of(scene)
    assert wav is not None and wav.is_file()
    if compat.HAS_AUDIO:
        strip = sequencer.speech_strip(scene)
        assert strip is not None and strip.frame_start == 1


def test_generate_keys_the_tracks_of_the_speech_on_head_and_teeth():
    head = _default_head_with_keys()
    scene = bpy.context.scene
    result = pipeline.generate(bpy.context, head, SENTENCE)
    timeline, tracks = result.timeline, result.tracks
    assert scene.frame_start == 1
    assert scene.frame_end == round(timeline.duration * 25)
    curves = _our_curves(head)
    assert {fc.data_path for fc in curves} == {f'key_blocks["{t.name}"].value' for t in tracks.tracks}

    # Every key lies on its track: F-curves pass through the tracks' (frame, weight) points.
    by_path = {fc.data_path: fc for fc in curves}
    for track in tracks.tracks:
        fcurve = by_path[f'key_blocks["{track.name}"].value']
        got = [fcurve.evaluate(1 + frame) for frame in track.frames]
        np.testing.assert_allclose(got, track.values, atol=1e-5, err_msg=track.name)

    # The mouth follows the phones: the evaluated face at each phone centre matches the tracks there
    # (Bézier keys bend a little between keys where linear sampling does not).
    centres = np.array([(p.start + p.end) / 2 * 25 for p in timeline.phones])
    names, expected = tracks.sample(centres)
    for row, frame in enumerate(1 + centres):
        scene.frame_set(int(frame), subframe=frame - int(frame))
        key_blocks = head.data.shape_keys.key_blocks
        got = [key_blocks[name].value for name in names]
        np.testing.assert_allclose(got, expected[row], atol=0.1, err_msg=timeline.phones[row].letter)

    teeth = [obj for obj in pipeline.head_objects(head)[1:] if obj.data.shape_keys is not None]
    assert teeth and all(_our_curves(obj) for obj in teeth)


def test_regenerate_replaces_ours_and_keeps_the_users_animation():
    head = _default_head_with_keys()
    head.location.x = 0.0
    head.keyframe_insert("location", index=0, frame=1)
    head.data.shape_keys.key_blocks[viseme_key_name("neutral")].value = 0.0
    _speak(SENTENCE)
    assert bpy.ops.turkish_lipsync.generate() == {"FINISHED"}
    first = len(_our_curves(head))
    _settings().text.clear()
    _settings().text.write("merhaba")
    assert bpy.ops.turkish_lipsync.generate() == {"FINISHED"}
    assert 0 < len(_our_curves(head)) <= max(first, 60)
    assert head.data.shape_keys.animation_data.action.name == "TR_merhaba"
    assert head.animation_data.action is not None
    assert [fc.data_path for fc in compat.all_action_fcurves(head.animation_data.action)] == ["location"]
    if compat.HAS_AUDIO:
        strips = compat.sequencer_strips(bpy.context.scene)
        assert [s.name for s in strips] == [sequencer.SPEECH_STRIP_NAME]


def test_undo_takes_the_generation_back():
    _default_head_with_keys()
    _speak(SENTENCE)
    bpy.context.scene.frame_end = 250
    bpy.ops.ed.undo_push(message="before generate")
    # Called with undo=True, as the UI calls it: the operator's UNDO flag pushes the undo step.
    assert bpy.ops.turkish_lipsync.generate("EXEC_DEFAULT", True) == {"FINISHED"}
    assert bpy.context.scene.frame_end != 250
    bpy.ops.ed.undo()
    assert bpy.context.scene.frame_end == 250
    assert _our_curves(bpy.data.objects["TR_Head"]) == []


def test_bad_markup_is_reported_and_changes_nothing():
    head = _default_head_with_keys()
    _speak("<SENT><HAPPY>merhaba</SENT>")
    scene = bpy.context.scene
    scene.frame_end = 99
    actions_before = len(bpy.data.actions)
    with pytest.raises(RuntimeError, match="JSML error at line 1"):
        bpy.ops.turkish_lipsync.generate()
    assert scene.frame_end == 99
    assert len(bpy.data.actions) == actions_before
    assert _our_curves(head) == []


def test_polls_say_why_an_operator_is_disabled():
    assert not bpy.ops.turkish_lipsync.generate.poll()  # no head, no text
    head = _default_head_with_keys()
    assert not bpy.ops.turkish_lipsync.generate.poll()  # still no text
    _speak("merhaba")
    assert bpy.ops.turkish_lipsync.generate.poll()
    _settings().head = None
    bpy.context.view_layer.objects.active = None
    assert not bpy.ops.turkish_lipsync.generate.poll()
    _settings().head = head
    assert bpy.ops.turkish_lipsync.render.poll()
    _settings().output_path = ""
    assert not bpy.ops.turkish_lipsync.render.poll()


def test_render_operator_writes_a_short_cycles_video(tmp_path):
    _default_head_with_keys()
    _speak("ama")
    assert bpy.ops.turkish_lipsync.generate() == {"FINISHED"}
    scene = bpy.context.scene
    scene.frame_end = scene.frame_start + 1  # two frames are enough to prove the operator renders
    scene.render.resolution_x, scene.render.resolution_y = 64, 36
    settings = _settings()
    settings.render_engine = "CYCLES"
    settings.render_samples = 1
    settings.output_path = str(tmp_path / "ama.mp4")
    assert bpy.ops.turkish_lipsync.render() == {"FINISHED"}
    assert (tmp_path / "ama.mp4").stat().st_size > 0
    assert scene.camera is not None and scene.camera.name == "TR_camera"
    assert scene.render.engine == "CYCLES"


@pytest.mark.parametrize(
    "relative_path",
    [
        "makehuman/mh_head_expression_units.glb",
        "mediapipe/canonical_face_model.obj",
        "mediapipe/canonical_face_model.fbx",
        "makehuman/base.obj",
    ],
)
def test_operators_work_on_the_shared_heads(relative_path):
    path = HEADS / relative_path
    if not path.is_file():
        pytest.skip(f"{path} is not on this machine")
    head = heads.find_head(heads.import_head(path))
    _settings().head = head
    assert bpy.ops.turkish_lipsync.build_shape_keys() == {"FINISHED"}
    _speak("<SENT><SURPRISED>merhaba</SURPRISED>, benim adım erdem</SENT>")
    assert bpy.ops.turkish_lipsync.generate() == {"FINISHED"}
    assert _our_curves(head)
    assert bpy.context.scene.frame_end > 25
