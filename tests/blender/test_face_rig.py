"""Heads whose face bones move: a game character's jaw bone and Rigify's face rig speak through their bones,
measured on the evaluated mesh against the shape-key path on the same head."""

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lab.kit import rigged_heads  # noqa: E402
from lab.kit.heads_on_disk import HEADS  # noqa: E402
from lab.kit.rigged_heads import lip_gaps, phone_frames  # noqa: E402
from turkish_lipsync.blender import compat, face_rig, heads, shapekeys  # noqa: E402
from turkish_lipsync.blender.generate import generate  # noqa: E402
from turkish_lipsync.blender.marked_curves import FACE_RIG, LIVING  # noqa: E402
from turkish_lipsync.core.base.errors import HeadError  # noqa: E402
from turkish_lipsync.core.faces.rig_mappings import OwnRig, rig_template  # noqa: E402
from turkish_lipsync.core.scene import RoleChoice  # noqa: E402

TEXT = "Merhaba, benim adım Erdem. Bu sabah vapura binip geçtim, ama bir de babamı gördüm."
FPS = 25
BILABIALS = set("bmp")
OPEN_VOWELS = set("aeo")

pytestmark = [
    pytest.mark.usefixtures("registered_extension"),
    pytest.mark.skipif(
        not rigged_heads.MAKEHUMAN_UNITS_HEAD.is_file(), reason=f"the shared heads are not in {HEADS}"
    ),
]


def _empty_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.render.fps = FPS


@pytest.fixture(scope="module")
def shape_key_path():
    """The same MakeHuman head speaking through shape keys built on it (its own keys taken off first)."""
    _empty_scene()
    head = rigged_heads.makehuman_with_our_keys()
    result = generate(bpy.context, TEXT, head=head)
    frames = np.arange(1, result.frame_end + 1)
    return result.timeline, frames, lip_gaps(head, frames)


def _jaw_character():
    _empty_scene()
    character = rigged_heads.jaw_bone_character(bpy.context)
    face_rig.store_setup(character["armature"], OwnRig("jaw_bone"))
    return character


def test_the_jaw_bone_opens_on_open_vowels_and_closes_on_b_m_p_as_the_shape_keys_do(shape_key_path):
    timeline, frames, keyed_gaps = shape_key_path
    character = _jaw_character()
    head = character["head"]
    assert head.data.shape_keys is None  # a head with no shape keys: its jaw is a bone
    result = generate(bpy.context, TEXT, head=head)
    assert [p.letter for p in result.timeline.phones] == [p.letter for p in timeline.phones]
    gaps = dict(zip(frames, lip_gaps(head, frames), strict=True))
    keyed = dict(zip(frames, keyed_gaps, strict=True))
    closures = phone_frames(timeline, BILABIALS)
    assert len(closures) >= 10
    for letter, span in closures:
        closed = min(span, key=lambda frame: keyed[frame])  # where the shape-key path closes the lips
        assert keyed[closed] < 0.5e-3, (letter, span)
        # Closed as the keys close them (their lips press on past contact; a jaw's stop there)
        assert gaps[closed] <= max(keyed[closed], 0.0) + 0.5e-3, (letter, closed, gaps[closed])
    for letter, span in phone_frames(timeline, OPEN_VOWELS):
        widest = max(span, key=lambda frame: keyed[frame])
        if keyed[widest] > 6e-3:
            assert gaps[widest] > 0.75 * keyed[widest], (letter, widest, gaps[widest], keyed[widest])
    assert np.corrcoef(list(gaps.values()), keyed_gaps)[0, 1] > 0.95


def test_the_jaw_characters_eyes_and_head_live_as_before():
    character = _jaw_character()
    result = generate(bpy.context, TEXT, head=character["head"])
    armature = character["armature"]
    action = armature.animation_data.action
    assert {path for path in action[LIVING.curves_property]} == {'pose.bones["head"].rotation_quaternion'}
    assert set(action[FACE_RIG.curves_property]) == {'pose.bones["jaw"].rotation_quaternion'}
    eye = character["eye_L"]
    turns = []
    for frame in range(1, result.frame_end, 5):
        bpy.context.scene.frame_set(frame)
        turns.append(np.array(eye.matrix_world.to_3x3()))
    assert max(np.abs(turn - turns[0]).max() for turn in turns) > 0.02  # the eyes look about
    assert any("blinks through neither" in warning for warning in result.warnings)


def test_generate_again_replaces_only_ours_and_keeps_the_users_keys_and_nla():
    character = _jaw_character()
    armature = character["armature"]
    neck = armature.pose.bones["neck"]
    neck.rotation_quaternion = (0.99, 0.1, 0.0, 0.0)
    neck.keyframe_insert("rotation_quaternion", frame=1)
    users_action = armature.animation_data.action
    track = armature.animation_data.nla_tracks.new()
    strip_action = bpy.data.actions.new("users_strip")
    track.strips.new("users_strip", 1, strip_action)
    generate(bpy.context, TEXT, head=character["head"])
    first = sorted(
        (fc.data_path, fc.array_index, len(fc.keyframe_points))
        for fc in compat.all_action_fcurves(users_action)
    )
    generate(bpy.context, "Merhaba, benim adım Erdem.", head=character["head"])
    again = [(fc.data_path, fc.array_index) for fc in compat.all_action_fcurves(users_action)]
    assert armature.animation_data.action == users_action
    assert sorted(again) == sorted((path, index) for path, index, _count in first)  # nothing twice
    neck_curves = [fc for fc in compat.all_action_fcurves(users_action) if "neck" in fc.data_path]
    assert len(neck_curves) == 4 and all(len(fc.keyframe_points) == 1 for fc in neck_curves)
    assert [s.name for t in armature.animation_data.nla_tracks for s in t.strips] == ["users_strip"]
    # The user animates the jaw: ours leave it alone and say so.
    face_rig.remove_face_rig_motion(character["head"])
    jaw = armature.pose.bones["jaw"]
    jaw.keyframe_insert("rotation_quaternion", frame=3)
    result = generate(bpy.context, "Merhaba.", head=character["head"])
    jaw_curves = [fc for fc in compat.all_action_fcurves(users_action) if '"jaw"' in fc.data_path]
    assert all(len(fc.keyframe_points) == 1 for fc in jaw_curves)
    assert any("animated by" in warning for warning in result.warnings)


def test_undo_takes_the_rigs_generation_back():
    character = _jaw_character()
    settings = bpy.context.scene.turkish_lipsync
    settings.head = character["head"]
    text = bpy.data.texts.new("speech")
    text.write("Merhaba")
    settings.source_kind, settings.text = "TEXT", text
    bpy.ops.ed.undo_push(message="before generate")
    assert bpy.ops.turkish_lipsync.generate("EXEC_DEFAULT", True) == {"FINISHED"}
    assert bpy.data.objects["GameRig"].animation_data.action is not None
    bpy.ops.ed.undo()
    armature = bpy.data.objects["GameRig"]
    assert armature.animation_data is None or armature.animation_data.action is None


def test_a_head_with_neither_keys_nor_rig_is_refused_with_what_to_do():
    _empty_scene()
    character = rigged_heads.jaw_bone_character(bpy.context)
    with pytest.raises(HeadError, match="Build Shape Keys first, or set up its face rig"):
        generate(bpy.context, "Merhaba", head=character["head"])
    assert character["armature"].animation_data is None
    settings = bpy.context.scene.turkish_lipsync
    settings.head = character["head"]
    settings.face_rig, settings.jaw_bone = "jaw_bone", "no such bone"
    with pytest.raises(RuntimeError, match="has no jaw bone"):
        bpy.ops.turkish_lipsync.use_face_rig()
    assert face_rig.RIG_PROPERTY not in character["armature"]
    settings.jaw_bone = "jaw"
    assert bpy.ops.turkish_lipsync.use_face_rig() == {"FINISHED"}
    assert face_rig.stored_setup(character["armature"]) == OwnRig("jaw_bone", {"jaw": "jaw"})
    assert bpy.ops.turkish_lipsync.stop_face_rig() == {"FINISHED"}
    assert face_rig.RIG_PROPERTY not in character["armature"]
    settings.head = None
    assert not bpy.ops.turkish_lipsync.use_face_rig.poll()


def test_a_recorded_pose_replaces_the_mappings_and_an_action_frame_gives_one_too():
    character = _jaw_character()
    armature, head = character["armature"], character["head"]
    settings = bpy.context.scene.turkish_lipsync
    settings.head = head
    jaw = armature.pose.bones["jaw"]
    jaw.rotation_quaternion = (np.cos(0.3), np.sin(0.3), 0.0, 0.0)  # 34 degrees about its own x
    settings.pose_target = "TR_viseme_a"
    assert bpy.ops.turkish_lipsync.record_pose() == {"FINISHED"}
    jaw.rotation_quaternion = (1.0, 0.0, 0.0, 0.0)
    pose = face_rig.stored_setup(armature).poses["TR_viseme_a"]
    assert set(pose.bones) == {"jaw"} and pose.bones["jaw"].rotation == pytest.approx((0.6, 0.0, 0.0))
    result = generate(bpy.context, "Aaa", head=head)
    track = result.tracks.track("TR_viseme_a")
    peak = 1 + int(track.frames[np.argmax(track.values)])
    bpy.context.scene.frame_set(peak)
    assert jaw.rotation_quaternion.angle == pytest.approx(0.6 * track.values.max(), abs=0.02)
    # Posed over our speech keys: only what the user posed is recorded, not the jaw as our keys have it.
    neck = armature.pose.bones["neck"]
    neck.location = (0.0, 0.01, 0.0)
    settings.pose_target = "browInnerUp"
    assert bpy.ops.turkish_lipsync.record_pose() == {"FINISHED"}
    assert set(face_rig.stored_setup(armature).poses["browInnerUp"].bones) == {"neck"}
    neck.location = (0.0, 0.0, 0.0)
    assert bpy.ops.turkish_lipsync.clear_pose(target="browInnerUp") == {"FINISHED"}
    # A pose asset or any action: the pose it holds at a frame.
    action = bpy.data.actions.new("smile")
    armature.animation_data.action = None
    jaw.rotation_quaternion = (np.cos(0.1), np.sin(0.1), 0.0, 0.0)
    jaw.keyframe_insert("rotation_quaternion", frame=7)
    action = armature.animation_data.action
    armature.animation_data.action = None
    settings.pose_target, settings.pose_action, settings.pose_frame = "jawOpen", action, 7
    assert bpy.ops.turkish_lipsync.record_action_pose() == {"FINISHED"}
    assert face_rig.stored_setup(armature).poses["jawOpen"].bones["jaw"].rotation == pytest.approx(
        (0.2, 0, 0)
    )
    assert bpy.ops.turkish_lipsync.clear_pose(target="TR_viseme_a") == {"FINISHED"}
    assert set(face_rig.stored_setup(armature).poses) == {"jawOpen"}
    with pytest.raises(RuntimeError, match="no recorded pose"):
        bpy.ops.turkish_lipsync.clear_pose(target="TR_viseme_a")


# ---------------------------------------------------------------- Rigify's face rig


@pytest.fixture(scope="module")
def rigify_file(tmp_path_factory):
    if not rigged_heads.rigify_available():
        pytest.skip("this Blender does not ship the Rigify add-on")
    _empty_scene()
    rigged_heads.rigify_face_character(bpy.context)
    path = tmp_path_factory.mktemp("rigify") / "rigify_face.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    return path


@pytest.fixture(scope="module")
def reference_gaps():
    _empty_scene()
    head = heads.create_reference_head(bpy.context)["head"]
    shapekeys.build_shape_keys(head)
    result = generate(bpy.context, TEXT, head=head)
    frames = np.arange(1, result.frame_end + 1)
    return frames, lip_gaps(head, frames)


def test_the_rigify_mapping_moves_controls_the_generated_rig_has(rigify_file):
    bpy.ops.wm.open_mainfile(filepath=str(rigify_file))
    rig = bpy.data.objects["rig"]
    controls = {bone.name for bone in rig.data.bones if not bone.name.startswith(("DEF-", "ORG-", "MCH-"))}
    needed = rig_template("rigify_face").bones_needed()
    assert needed <= controls, sorted(needed - controls)
    in_face = {
        bone.name
        for collection in rig.data.collections_all
        if collection.name.startswith("Face")
        for bone in collection.bones
    }
    assert needed <= in_face


def test_the_rigify_face_opens_and_closes_the_mouth_as_the_shape_keys_do(rigify_file, reference_gaps):
    frames, keyed = reference_gaps
    bpy.ops.wm.open_mainfile(filepath=str(rigify_file))
    bpy.context.scene.render.fps = FPS
    head, rig = bpy.data.objects["TR_Head"], bpy.data.objects["rig"]
    face_rig.store_setup(rig, OwnRig("rigify_face"))
    result = generate(bpy.context, TEXT, head=head)
    assert not any("blinks" in warning for warning in result.warnings)
    ours = set(rig.animation_data.action[FACE_RIG.curves_property])
    for control in ("jaw_master", "lips.L", "lips.R", "lip.T", "lip.B", "lid.T.L.002", "eye.L"):
        assert any(f'"{control}"' in path for path in ours), control
    gaps = lip_gaps(head, frames)
    assert np.corrcoef(gaps, keyed)[0, 1] >= 0.9
    assert gaps.max() > 0.6 * keyed.max()
    # The eyes look through Rigify's eye targets, not as objects of their own.
    eye = bpy.data.objects["TR_Head_EyeLeft"]
    assert eye.animation_data is None or eye.animation_data.action is None


def test_a_conversation_character_speaks_through_its_face_rig(tmp_path):
    """One Generate for one head and many: cast in a script, the jaw-bone character moves its jaw bone (no
    shape keys are built on it), the other speaker its default head's keys."""
    character = _jaw_character()
    head = character["head"]
    script = "AYŞE: Merhaba, benim adım Ayşe.\nALİ: Bu sabah babamı gördüm."
    result = generate(
        bpy.context, script, choices={"Ali": RoleChoice(head=head.name)}, audio_folder=str(tmp_path)
    )
    assert result.heads["Ali"] == head.name and head.data.shape_keys is None
    action = character["armature"].animation_data.action
    jaw = [c for c in compat.all_action_fcurves(action) if "jaw" in c.data_path.lower()]
    assert jaw and any(np.ptp([k.co[1] for k in c.keyframe_points]) > 0.01 for c in jaw)
    ayse = bpy.data.objects[result.heads["Ayşe"]]
    assert any(name.startswith("TR_viseme_") for name in ayse.data.shape_keys.key_blocks.keys())
