"""The operators on the default head and on the shared heads: results, errors, undo, regenerate."""

import json
import math
import wave
from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from mathutils import Matrix  # noqa: E402

from lab.kit.heads_on_disk import HEADS  # noqa: E402
from turkish_lipsync.blender import compat, heads, landmarks, living, pipeline, sequencer  # noqa: E402
from turkish_lipsync.blender.generate import generate  # noqa: E402
from turkish_lipsync.core.base.model import EMOTIONS, emotion_key_name, viseme_key_name  # noqa: E402
from turkish_lipsync.core.faces.landmarks import LANDMARK_NAMES, LID_LANDMARK_NAMES  # noqa: E402
from turkish_lipsync.core.faces.reference import load_reference_head  # noqa: E402
from turkish_lipsync.core.speech import synthesize_timeline  # noqa: E402
from turkish_lipsync.core.text.utterance import build_utterance  # noqa: E402

pytestmark = pytest.mark.usefixtures("registered_extension")

# The thesis's 37 models (Table 5.1, Appendix B).
VISEMES = (
    "a bpa cjae dta fvae gkya la ma na ra sza ta e bpe dte gkye le me ne re sze I Ii o bpo cjo do fvo gkyo "
    "lo mo no ro szto oi u neutral"
).split()

SENTENCE = "Şu köşe yaz köşesi"


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
    result = generate(bpy.context, SENTENCE, head=head)
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

    # Teeth, tongue and lashes move with the speech; the eyes, which no key moves (they turn as objects),
    # carry no shape-key curve.
    parts = {obj.name: obj for obj in pipeline.head_objects(head)[1:] if obj.data.shape_keys is not None}
    moved = {name for name, obj in parts.items() if _our_curves(obj)}
    assert {"TR_Head_LowerTeeth", "TR_Head_Tongue", "TR_Head_EyelashesLeft"} <= moved
    assert not moved & {"TR_Head_EyeLeft", "TR_Head_EyeRight"}


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
    # The user's location key stays; beside it only our living motion, marked ours (delta transforms).
    action = head.animation_data.action
    ours = set(action.get(living.CURVES_PROPERTY, ()))
    paths = [fc.data_path for fc in compat.all_action_fcurves(action)]
    assert [path for path in paths if path not in ours] == ["location"]
    assert ours == {"delta_location", "delta_rotation_euler"} and len(paths) == 7
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


# ---------------------------------------------------------------- landmarks


def _reference_head():
    """The default head without keys (cheaper than a build), chosen in the panel."""
    head = heads.create_reference_head(bpy.context)["head"]
    _settings().head = head
    return head


def _markers(head) -> dict:
    return {obj[landmarks.LANDMARK_PROPERTY]: obj for obj in head.children if obj.type == "EMPTY"}


def _world_deltas(obj, key_name: str) -> np.ndarray:
    """A shape key's displacement from the basis in world axes."""
    blocks = obj.data.shape_keys.key_blocks
    count = len(obj.data.vertices)
    basis, shaped = np.empty(count * 3), np.empty(count * 3)
    obj.data.shape_keys.reference_key.points.foreach_get("co", basis)
    blocks[key_name].points.foreach_get("co", shaped)
    return (shaped - basis).reshape(-1, 3) @ np.array(obj.matrix_world)[:3, :3].T


def test_show_landmarks_puts_movable_markers_on_the_face_and_clear_removes_them():
    assert not bpy.ops.turkish_lipsync.show_landmarks.poll()  # no head yet
    head = _reference_head()
    assert not bpy.ops.turkish_lipsync.clear_landmarks.poll()  # nothing to clear
    assert bpy.ops.turkish_lipsync.show_landmarks() == {"FINISHED"}
    markers = _markers(head)
    # Its eyes are objects of their own; seen between the lids beside the head, they mark the lids too.
    assert set(markers) == set(LANDMARK_NAMES + LID_LANDMARK_NAMES)
    assert all(marker.name.startswith(landmarks.MARKER_PREFIX) for marker in markers.values())
    # The reference head sits where MakeHuman's mesh does, so its known landmarks are where the markers are.
    bpy.context.view_layer.update()
    for name, point in load_reference_head().landmarks.items():
        assert np.linalg.norm(np.array(markers[name].matrix_world.translation) - point) < 0.01, name
    # Showing again replaces the markers instead of adding a second set.
    assert bpy.ops.turkish_lipsync.show_landmarks() == {"FINISHED"}
    assert len([obj for obj in bpy.data.objects if obj.type == "EMPTY"]) == len(markers)
    assert bpy.ops.turkish_lipsync.clear_landmarks.poll()
    assert bpy.ops.turkish_lipsync.clear_landmarks() == {"FINISHED"}
    assert _markers(head) == {} and landmarks.read_landmark_markers(head) is None
    assert landmarks.COLLECTION_NAME not in bpy.data.collections


def test_show_landmarks_follows_a_head_whose_transform_turns_and_scales_its_mesh():
    head = _reference_head()
    # As an import from a Y-up file in centimetres: the mesh lies on its back, the object stands it up.
    head.data.transform(Matrix.Rotation(-math.pi / 2, 4, "X") @ Matrix.Scale(100.0, 4))
    head.rotation_euler.x = math.pi / 2
    head.scale = (0.01, 0.01, 0.01)
    bpy.context.view_layer.update()
    assert bpy.ops.turkish_lipsync.show_landmarks() == {"FINISHED"}
    read = landmarks.read_landmark_markers(head)
    to_world = np.array(head.matrix_world)
    for name, point in load_reference_head().landmarks.items():
        world = to_world[:3, :3] @ read[name] + to_world[:3, 3]
        assert np.linalg.norm(world - point) < 0.01, name
    assert np.abs(read["chin"]).max() > 1.0  # stored in the mesh's own centimetres


def test_show_landmarks_keeps_the_users_markers_and_places_a_layout_where_no_face_is_found():
    bpy.ops.mesh.primitive_cube_add()
    cube = bpy.context.active_object
    _settings().head = cube
    # Markers placed by hand earlier are shown as they are, never replaced by a new search.
    placed = {"nose_tip": np.array([0.0, -1.0, 0.2]), "chin": np.array([0.0, -0.9, -0.6])}
    landmarks.show_landmark_markers(cube, placed)
    assert bpy.ops.turkish_lipsync.show_landmarks() == {"FINISHED"}
    read = landmarks.read_landmark_markers(cube)
    assert set(read) == set(placed)
    for name, point in placed.items():
        np.testing.assert_allclose(read[name], point, atol=1e-6)
    # Without markers, a cube has no face to find: every marker is laid out on its front to be moved.
    assert bpy.ops.turkish_lipsync.clear_landmarks() == {"FINISHED"}
    assert bpy.ops.turkish_lipsync.show_landmarks() == {"FINISHED"}
    read = landmarks.read_landmark_markers(cube)
    assert set(read) >= set(LANDMARK_NAMES)
    assert all(np.all(np.abs(point) <= 1.0 + 1e-6) for point in read.values())


def test_a_moved_marker_steers_the_transfer():
    head = _reference_head()
    _settings().key_source = "transfer"
    assert bpy.ops.turkish_lipsync.show_landmarks() == {"FINISHED"}
    assert bpy.ops.turkish_lipsync.build_shape_keys() == {"FINISHED"}
    as_found = _world_deltas(head, viseme_key_name("a"))
    assert np.abs(as_found).max() > 0.002  # the transfer opened the mouth

    # The user drags the left mouth corner 1 cm outward and builds again.
    bpy.context.view_layer.update()
    corner = _markers(head)["mouth_corner_left"]
    before = landmarks.read_landmark_markers(head)["mouth_corner_left"]
    world = corner.matrix_world.copy()
    world.translation.x += 0.01
    corner.matrix_world = world
    np.testing.assert_allclose(
        landmarks.read_landmark_markers(head)["mouth_corner_left"], before + [0.01, 0.0, 0.0], atol=1e-6
    )
    assert bpy.ops.turkish_lipsync.build_shape_keys() == {"FINISHED"}
    moved = _world_deltas(head, viseme_key_name("a"))
    assert np.abs(moved - as_found).max() > 1e-4  # the registration used the moved marker
    assert set(_markers(head)) == set(LANDMARK_NAMES + LID_LANDMARK_NAMES)  # kept for the next build


# ---------------------------------------------------------------- shape-key sources and empowered emotions


def _write_obj(path: Path, vertices: np.ndarray) -> None:
    """An OBJ in its usual Y-up axes, as Blender's exporter writes a Z-up mesh (x, z, -y)."""
    rows = np.stack([vertices[:, 0], vertices[:, 2], -vertices[:, 1]], axis=1)
    np.savetxt(path, rows, fmt="v %.6f %.6f %.6f")


def _basis(obj) -> np.ndarray:
    flat = np.empty(len(obj.data.vertices) * 3)
    obj.data.vertices.foreach_get("co", flat)
    return flat.reshape(-1, 3)


def _key_coordinates(obj) -> dict[str, np.ndarray]:
    result = {}
    for block in obj.data.shape_keys.key_blocks:
        flat = np.empty(len(obj.data.vertices) * 3)
        block.points.foreach_get("co", flat)
        result[block.name] = flat
    return result


def test_obj_folder_source_reads_the_thesis_models(tmp_path):
    head = _reference_head()
    basis = _basis(head)
    folder = tmp_path / "models"
    folder.mkdir()
    _write_obj(folder / "Neutral.obj", basis)
    for viseme in VISEMES:
        if viseme != "neutral":
            _write_obj(folder / f"{viseme}.obj", basis + ([0.0, 0.0, -0.005] if viseme == "a" else 0.0))
    settings = _settings()
    settings.key_source = "obj_folder"
    assert not bpy.ops.turkish_lipsync.build_shape_keys.poll()  # no folder chosen yet
    settings.obj_folder = str(folder)
    assert bpy.ops.turkish_lipsync.build_shape_keys() == {"FINISHED"}
    keys = _key_coordinates(head)
    reference = keys[head.data.shape_keys.reference_key.name].reshape(-1, 3)
    np.testing.assert_allclose(
        keys[viseme_key_name("a")].reshape(-1, 3) - reference, [[0, 0, -0.005]] * len(basis), atol=2e-6
    )
    np.testing.assert_allclose(keys[viseme_key_name("e")].reshape(-1, 3), reference, atol=2e-6)
    assert {emotion_key_name(e) for e in EMOTIONS} <= set(keys)


def test_a_bad_obj_folder_changes_nothing_not_even_a_new_head(tmp_path):
    (tmp_path / "a.obj").write_text("v 0 0 0\n")  # no Neutral.obj
    settings = _settings()
    settings.key_source = "obj_folder"
    settings.obj_folder = str(tmp_path)
    with pytest.raises(RuntimeError, match="no Neutral.obj"):
        bpy.ops.turkish_lipsync.build_shape_keys()
    # No head was chosen: the reference head made for the build is gone again with its meshes.
    assert len(bpy.data.objects) == 0 and len(bpy.data.meshes) == 0
    assert settings.head is None


def test_own_arkit_source_refuses_a_head_without_them_and_changes_nothing():
    settings = _settings()
    settings.key_source = "arkit"
    assert not bpy.ops.turkish_lipsync.build_shape_keys.poll()  # the reference head would have none
    settings.key_source = "auto"
    head = _default_head_with_keys()
    before = _key_coordinates(head)
    settings.key_source = "arkit"
    assert bpy.ops.turkish_lipsync.build_shape_keys.poll()
    with pytest.raises(RuntimeError, match="lacks ARKit shape keys"):
        bpy.ops.turkish_lipsync.build_shape_keys()
    after = _key_coordinates(head)
    assert list(after) == list(before)
    assert all(np.array_equal(after[name], before[name]) for name in before)


def test_empowered_emotions_are_rho_times_the_plain_ones():
    head = _default_head_with_keys()
    happy = emotion_key_name("happy")
    plain = _world_deltas(head, happy)
    plain_viseme = _world_deltas(head, viseme_key_name("a"))
    assert np.abs(plain).max() > 0.001
    settings = _settings()
    settings.empowered = True
    assert settings.rho == pytest.approx(3.0)  # the thesis's constant is the default
    assert bpy.ops.turkish_lipsync.build_shape_keys() == {"FINISHED"}
    np.testing.assert_allclose(_world_deltas(head, happy), 3.0 * plain, atol=1e-5)
    np.testing.assert_allclose(_world_deltas(head, viseme_key_name("a")), plain_viseme, atol=1e-6)
    settings.rho = 2.0
    assert bpy.ops.turkish_lipsync.build_shape_keys() == {"FINISHED"}
    np.testing.assert_allclose(_world_deltas(head, happy), 2.0 * plain, atol=1e-5)


# ---------------------------------------------------------------- the user's own recording


LEAD_IN = 0.6  # seconds of silence before the recorded speech


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    """'merhaba dünya' read slower by eSpeak NG after a silence: a stand-in for the user's voice."""
    slow = build_utterance('<PROS RATE="-30%">merhaba dünya</PROS>')
    synthesis = synthesize_timeline(slow).synthesis
    voice = synthesis.samples.astype(np.int16)
    silence = np.zeros(int(LEAD_IN * synthesis.sample_rate), np.int16)
    path = tmp_path_factory.mktemp("recording") / "okuma.wav"
    with wave.open(str(path), "wb") as handle:
        handle.setnchannels(1)
        handle.setsampwidth(2)
        handle.setframerate(synthesis.sample_rate)
        handle.writeframes(np.concatenate((silence, voice, silence[: len(silence) // 2])).tobytes())
    return path


def _first_open_mouth_frame(head) -> float:
    """The first frame where a viseme other than neutral is keyed above one half."""
    frames = [
        point.co[0]
        for fcurve in _our_curves(head)
        if fcurve.data_path.startswith('key_blocks["TR_viseme_')
        and viseme_key_name("neutral") not in fcurve.data_path
        for point in fcurve.keyframe_points
        if point.co[1] > 0.5
    ]
    return min(frames)


def test_generate_follows_the_users_recording_and_uses_it_as_the_sound(recording, tmp_path):
    head = _default_head_with_keys()
    _speak("merhaba dünya")
    settings = _settings()
    settings.audio_folder = str(tmp_path)
    assert bpy.ops.turkish_lipsync.generate() == {"FINISHED"}
    synthetic_start = _first_open_mouth_frame(head)
    settings.recording = str(recording)
    assert bpy.ops.turkish_lipsync.generate() == {"FINISHED"}
    # The mouth waits for the recorded voice, which starts after the silence.
    assert synthetic_start < 1 + 0.3 * 25
    assert _first_open_mouth_frame(head) > 1 + (LEAD_IN - 0.2) * 25
    # The sound is the recording: its length, placed once.
    scene = bpy.context.scene
    with wave.open(str(recording), "rb") as handle:
        recorded_seconds = handle.getnframes() / handle.getframerate()
    with wave.open(str(sequencer.speech_wav_of(scene)), "rb") as handle:
        assert handle.getnframes() / handle.getframerate() == pytest.approx(recorded_seconds, abs=0.02)
    assert scene.frame_end - scene.frame_start + 1 == pytest.approx(recorded_seconds * 25, abs=1)
    if compat.HAS_AUDIO:
        assert [s.name for s in compat.sequencer_strips(scene)] == [sequencer.SPEECH_STRIP_NAME]


def test_a_missing_recording_is_reported_and_changes_nothing(tmp_path):
    head = _default_head_with_keys()
    _speak("merhaba")
    settings = _settings()
    settings.recording = str(tmp_path / "yok.wav")
    settings.timing = "table"
    assert not bpy.ops.turkish_lipsync.generate.poll()  # mean durations cannot follow a voice
    settings.timing = "phone"
    scene = bpy.context.scene
    scene.frame_end = 99
    actions_before = len(bpy.data.actions)
    with pytest.raises(RuntimeError, match="does not exist"):
        bpy.ops.turkish_lipsync.generate()
    assert scene.frame_end == 99
    assert len(bpy.data.actions) == actions_before
    assert _our_curves(head) == []
    assert sequencer.speech_wav_of(scene) is None


def test_the_panel_warns_of_a_word_the_recording_leaves_out_and_refuses_another_text(tmp_path, capfd):
    from tests.core.test_speech_recording import OTHER_TEXT, noisy_take, other_voice

    head = _default_head_with_keys()
    _speak(OTHER_TEXT)
    settings = _settings()
    settings.audio_folder = str(tmp_path)
    voice, _ = other_voice(OTHER_TEXT.replace("bütün ", ""))
    settings.recording = str(noisy_take(tmp_path / "take.wav", voice, snr=40))
    capfd.readouterr()
    assert bpy.ops.turkish_lipsync.generate() == {"FINISHED"}
    printed = capfd.readouterr()
    assert "Warning:" in printed.out + printed.err and "'bütün'" in printed.out + printed.err
    action = head.data.shape_keys.animation_data.action
    frame_end = bpy.context.scene.frame_end

    # A recording of another text: refused, and the animation, frame range and sound stay as they were.
    other = "Kütüphaneden aldığım kitabı iki hafta içinde geri vermem gerekiyor. Yarın hava çok soğuk olacak."
    voice, _ = other_voice(other)
    settings.recording = str(noisy_take(tmp_path / "other.wav", voice, snr=40))
    wav_before = sequencer.speech_wav_of(bpy.context.scene)
    with pytest.raises(RuntimeError, match="does not read this text"):
        bpy.ops.turkish_lipsync.generate()
    assert head.data.shape_keys.animation_data.action == action
    assert bpy.context.scene.frame_end == frame_end
    assert sequencer.speech_wav_of(bpy.context.scene) == wav_before


def test_an_eee_said_between_two_words_of_the_users_take_is_said_by_the_mouth(tmp_path):
    """A person's "eee" in a pause of their take: on the evaluated head the mouth holds an e through it
    (the e key dominant, as the timeline's hesitation asks), where it used to rest."""
    from tests.core.test_speech_recording import OTHER_TEXT
    from tests.core.test_speech_recording_person import quiet_room, said_aloud, take_of, written

    take = quiet_room(said_aloud(take_of(OTHER_TEXT), "eeeeee"))
    head = _default_head_with_keys()
    _speak(OTHER_TEXT)
    settings = _settings()
    settings.audio_folder = str(tmp_path)
    settings.recording = str(written(take, tmp_path / "take.wav"))
    assert bpy.ops.turkish_lipsync.generate() == {"FINISHED"}
    hesitations = pipeline.animation_record(head).timeline.hesitations
    assert hesitations and {h.sound for h in hesitations} == {"e"}
    scene = bpy.context.scene
    for hesitation in hesitations:
        scene.frame_set(scene.frame_start + round((hesitation.start + hesitation.end) / 2 * 25))
        keys = head.data.shape_keys.evaluated_get(bpy.context.evaluated_depsgraph_get()).key_blocks
        visemes = {name: keys[viseme_key_name(name)].value for name in VISEMES}
        assert max(visemes, key=visemes.get) == "e" and visemes["e"] > 0.5, visemes


def test_panel_texts_are_translated():
    import inspect
    import re

    from turkish_lipsync.blender import panel, translations

    source = inspect.getsource(panel)
    texts = re.findall(r'(?:text|heading)="([^"]+)"', source)
    assert "Head" in texts
    assert [text for text in texts if text not in translations.TURKISH] == []


def test_undo_takes_the_landmark_markers_back():
    head = _reference_head()
    bpy.ops.ed.undo_push(message="before landmarks")
    assert bpy.ops.turkish_lipsync.show_landmarks("EXEC_DEFAULT", True) == {"FINISHED"}
    assert len(_markers(bpy.data.objects[head.name])) == len(LANDMARK_NAMES + LID_LANDMARK_NAMES)
    bpy.ops.ed.undo()
    head = bpy.data.objects["TR_Head"]
    assert _markers(head) == {}
    assert not [obj for obj in bpy.data.objects if obj.name.startswith(landmarks.MARKER_PREFIX)]


def test_a_recording_with_an_empty_text_is_recognised_keyed_and_placed_as_the_sound(tmp_path):
    """No script: the panel's recording and an empty Text still animate the mouth, closing on b, m, p."""
    from lab.kit.voices import TEST_VOICES, make_take

    head = _default_head_with_keys()
    settings = _settings()
    settings.audio_folder = str(tmp_path)
    text = "Bu sabah babam bana mavi bir kalem aldı."
    take, truth, lead, _ = make_take(
        text, TEST_VOICES["m3"], "30 dB, leading noise", tmp_path, np.random.default_rng(3)
    )
    settings.recording = str(take)
    settings.source_kind = "TEXT"
    settings.text = None
    assert bpy.ops.turkish_lipsync.generate.poll()
    _speak("")
    assert bpy.ops.turkish_lipsync.generate.poll()
    assert bpy.ops.turkish_lipsync.generate() == {"FINISHED"}
    scene = bpy.context.scene
    blocks = head.data.shape_keys.key_blocks
    bilabials = [viseme_key_name(v) for v in ("bpa", "bpe", "bpo", "ma", "me", "mo")]
    # Each b, m, p the variant spoke: the lips close (some bilabial key near full weight) within its span.
    closed = 0
    spoken = [phone for phone in truth.phones if phone.letter in "bmp"]
    for phone in spoken:
        frames = range(int((phone.start + lead) * 25) - 1, int((phone.end + lead) * 25) + 3)
        peak = 0.0
        for frame in frames:
            scene.frame_set(scene.frame_start + frame)
            peak = max(peak, max(blocks[name].value for name in bilabials))
        closed += peak > 0.9
    assert closed >= 0.8 * len(spoken)
    # Nothing moves in the noise before the voice; the sound is the recording.
    assert _first_open_mouth_frame(head) > 1 + (lead - 0.15) * 25
    with wave.open(str(take), "rb") as handle:
        recorded_seconds = handle.getnframes() / handle.getframerate()
    with wave.open(str(sequencer.speech_wav_of(scene)), "rb") as handle:
        assert handle.getnframes() / handle.getframerate() == pytest.approx(recorded_seconds, abs=0.02)
    # The panel exports what was keyed: the Rhubarb cues close (A) where the heard b, m, p are.
    settings.export_format, settings.export_path = "rhubarb-json", str(tmp_path / "heard.json")
    assert bpy.ops.turkish_lipsync.export_animation() == {"FINISHED"}
    cues = json.loads((tmp_path / "heard.json").read_text())["mouthCues"]
    assert cues[0]["value"] == "X" and sum(cue["value"] == "A" for cue in cues) >= 0.8 * len(spoken)
