"""A character kept in its own file, linked into a shot with a library override: Generate animates the
override in the shot (its keys' properties, its bones, its head and eyes, the strip), the shot saves and
reopens with it, and the character's file is never written."""

import hashlib
import subprocess
import sys

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lab.kit import rigged_heads  # noqa: E402
from tests.render_runs import REPOSITORY, run_render  # noqa: E402
from turkish_lipsync.blender import compat, face_rig, heads, linking, pipeline, sequencer, shapekeys  # noqa: E402
from turkish_lipsync.blender.generate import generate  # noqa: E402
from turkish_lipsync.blender.marked_curves import FACE_RIG, LINKED_KEYS, LIVING  # noqa: E402
from turkish_lipsync.core.base.errors import HeadError  # noqa: E402
from turkish_lipsync.core.faces.rig_mappings import OwnRig  # noqa: E402

pytestmark = pytest.mark.usefixtures("registered_extension")

FPS = 25
TEXT = "Merhaba, benim adım Erdem."
COLLECTION = "Character"


def _empty_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.render.fps = FPS


def _save_character(path) -> None:
    """Everything of the scene into one collection, saved as the character's own file."""
    scene = bpy.context.scene
    collection = bpy.data.collections.new(COLLECTION)
    scene.collection.children.link(collection)
    for obj in list(scene.collection.objects):
        collection.objects.link(obj)
        scene.collection.objects.unlink(obj)
    bpy.ops.wm.save_as_mainfile(filepath=str(path))


def _keys_character(path, linkable: bool = True) -> None:
    _empty_scene()
    objects = heads.create_reference_head(bpy.context)
    shapekeys.build_shape_keys(objects["head"])
    if linkable:
        linking.make_keys_linkable(objects["head"], heads.find_head_parts(objects["head"]))
    _save_character(path)


def _shot(character_path, shot_path) -> None:
    """A shot that links the character's collection and overrides it (as Outliner > Library Override does)."""
    _empty_scene()
    with bpy.data.libraries.load(str(character_path), link=True) as (_source, target):
        target.collections = [COLLECTION]
    linked = target.collections[0]
    bpy.context.scene.collection.children.link(linked)
    linked.override_hierarchy_create(bpy.context.scene, bpy.context.view_layer, do_fully_editable=False)
    if linked.name in bpy.context.scene.collection.children:
        bpy.context.scene.collection.children.unlink(linked)
    bpy.ops.wm.save_as_mainfile(filepath=str(shot_path))


def _digest(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _override(name: str) -> bpy.types.Object:
    obj = bpy.data.objects[name]
    assert obj.override_library is not None and obj.library is None
    return obj


def _key_values(head, names, frames) -> np.ndarray:
    """The head's keys as Blender evaluates them (drivers included) at the frames."""
    values = []
    for frame in frames:
        bpy.context.scene.frame_set(int(frame))
        evaluated = head.data.shape_keys.evaluated_get(bpy.context.evaluated_depsgraph_get())
        values.append([evaluated.key_blocks[name].value for name in names])
    return np.array(values)


def _counts() -> tuple:
    actions = sorted(
        (a.name, len(compat.all_action_fcurves(a))) for a in bpy.data.actions if a.library is None
    )
    strips = compat.sequencer_strips(bpy.context.scene, create=False)
    overrides = sorted(
        i.name for i in (*bpy.data.objects, *bpy.data.meshes) if i.override_library is not None
    )
    return actions, len(strips) if strips is not None else 0, overrides


def test_a_linked_character_with_linkable_keys_speaks_in_the_shot_and_keeps_it(tmp_path):
    character, shot = tmp_path / "character.blend", tmp_path / "shot.blend"
    _keys_character(character)
    before = _digest(character)
    _shot(character, shot)
    bpy.ops.wm.open_mainfile(filepath=str(shot))
    head = _override("TR_Head")
    result = generate(bpy.context, TEXT, head=head)
    action = head.animation_data.action
    assert action.library is None and LINKED_KEYS.curves_property in action
    names = ["TR_viseme_a", "TR_viseme_me"]
    frames = np.arange(1, result.frame_end + 1)
    tracks = np.column_stack(
        [np.interp(frames - 1, t.frames, t.values) for t in map(result.tracks.track, names)]
    )
    np.testing.assert_allclose(_key_values(head, names, frames), tracks, atol=1e-3)
    teeth = bpy.data.objects["TR_Head_LowerTeeth"]
    assert _key_values(teeth, ["TR_viseme_a"], frames).max() > 0.5  # its parts follow the head's properties
    if compat.HAS_AUDIO:
        assert sequencer.speech_strip(bpy.context.scene) is not None
    first = _counts()
    generate(bpy.context, TEXT, head=head)
    assert _counts() == first  # Generate again adds nothing twice
    saved = _key_values(head, names, frames)
    bpy.ops.wm.save_mainfile()
    bpy.ops.wm.open_mainfile(filepath=str(shot))
    head = _override("TR_Head")
    action = head.animation_data.action
    np.testing.assert_allclose(_key_values(head, names, frames), saved, atol=1e-6)
    assert _counts() == first
    # The head turns and the eyes look about in the shot too (their overrides' delta transforms).
    assert {"delta_rotation_euler", '["TR_viseme_a"]'} <= {
        fc.data_path for fc in compat.all_action_fcurves(action)
    }
    eye = _override("TR_Head_EyeLeft")
    assert LIVING.curves_property in eye.animation_data.action
    assert _digest(character) == before  # the library file is never written
    # The character's file changes (a prop added to the character): the shot, resynced, keeps its speech.
    bpy.ops.wm.open_mainfile(filepath=str(character))
    bpy.data.collections[COLLECTION].objects.link(bpy.data.objects.new("Hat", None))
    bpy.ops.wm.save_mainfile()
    bpy.ops.wm.open_mainfile(filepath=str(shot))
    assert "Hat" in bpy.context.scene.objects
    np.testing.assert_allclose(_key_values(_override("TR_Head"), names, frames), saved, atol=1e-6)


def test_a_linked_character_with_a_face_rig_speaks_through_its_bones_in_the_shot(tmp_path):
    character, shot = tmp_path / "game_character.blend", tmp_path / "shot.blend"
    _empty_scene()
    rigged = rigged_heads.jaw_bone_character(bpy.context)
    face_rig.store_setup(rigged["armature"], OwnRig("jaw_bone"))
    _save_character(character)
    before = _digest(character)
    _shot(character, shot)
    bpy.ops.wm.open_mainfile(filepath=str(shot))
    armature = _override("GameRig")
    result = generate(bpy.context, TEXT, head=_override("head"))
    jaw = armature.pose.bones["jaw"]

    def jaw_angles():
        angles = []
        for frame in range(1, result.frame_end + 1):
            bpy.context.scene.frame_set(frame)
            angles.append(jaw.rotation_quaternion.angle)
        return np.degrees(angles)

    assert jaw_angles().max() > 8 and jaw_angles().min() < 1
    first = _counts()
    generate(bpy.context, TEXT, head=_override("head"))
    assert _counts() == first
    opened = jaw_angles()
    assert FACE_RIG.curves_property in armature.animation_data.action
    bpy.ops.wm.save_mainfile()
    bpy.ops.wm.open_mainfile(filepath=str(shot))
    armature = _override("GameRig")
    jaw = armature.pose.bones["jaw"]
    np.testing.assert_allclose(jaw_angles(), opened, atol=1e-3)
    assert _digest(character) == before
    # A set-up is the character's: the shot may not change it.
    with pytest.raises(HeadError, match="in the character's own file"):
        face_rig.store_setup(armature, OwnRig())


def test_a_linked_character_without_keys_or_rig_says_where_to_build_them(tmp_path):
    character, shot = tmp_path / "bare.blend", tmp_path / "shot.blend"
    _empty_scene()
    heads.create_reference_head(bpy.context)
    _save_character(character)
    _shot(character, shot)
    bpy.ops.wm.open_mainfile(filepath=str(shot))
    head = _override("TR_Head")
    with pytest.raises(HeadError, match=f"linked from {character}.*Build Shape Keys there") as error:
        generate(bpy.context, TEXT, head=head)
    assert "reload the library" in str(error.value)
    assert head.animation_data is None or head.animation_data.action is None
    with pytest.raises(HeadError, match="build its shape keys there"):
        pipeline.build_keys(bpy.context, head)
    settings = bpy.context.scene.turkish_lipsync
    settings.head = head
    assert not bpy.ops.turkish_lipsync.generate.poll()
    with pytest.raises(RuntimeError, match="build its shape keys there"):
        bpy.ops.turkish_lipsync.build_shape_keys()


def test_keys_that_are_not_linkable_are_refused_in_the_shot_with_what_to_do(tmp_path):
    character, shot = tmp_path / "plain.blend", tmp_path / "shot.blend"
    _keys_character(character, linkable=False)
    _shot(character, shot)
    bpy.ops.wm.open_mainfile(filepath=str(shot))
    with pytest.raises(HeadError, match="press Make Keys Linkable"):
        generate(bpy.context, TEXT, head=_override("TR_Head"))


def test_render_script_animates_the_override_of_an_open_shot(tmp_path):
    character, shot = tmp_path / "character.blend", tmp_path / "shot.blend"
    _keys_character(character)
    _shot(character, shot)
    before = _digest(character)
    # With the bpy module: --open.
    opened = run_render(
        "--open",
        shot,
        "--object",
        "TR_Head",
        "--text",
        TEXT,
        "--no-render",
        "--save-blend",
        tmp_path / "a.blend",
    )
    assert opened.returncode == 0, opened.stderr
    # As Blender runs it: blender -b shot.blend -P scripts/render.py -- --object ...
    as_blender = (
        "import bpy, runpy, sys; "
        f"bpy.ops.wm.open_mainfile(filepath={str(shot)!r}); "
        f"sys.argv = ['blender', '--', '--object', 'TR_Head', '--text', {TEXT!r}, '--no-render', "
        f"'--save-blend', {str(tmp_path / 'b.blend')!r}]; "
        f"runpy.run_path({str(REPOSITORY / 'scripts' / 'render.py')!r}, run_name='__main__')"
    )
    blender_run = subprocess.run(
        [sys.executable, "-c", as_blender], capture_output=True, text=True, timeout=600, cwd=REPOSITORY
    )
    assert blender_run.returncode == 0, blender_run.stderr
    for saved in ("a.blend", "b.blend"):
        bpy.ops.wm.open_mainfile(filepath=str(tmp_path / saved))
        head = _override("TR_Head")
        assert LINKED_KEYS.curves_property in head.animation_data.action
    missing = run_render("--open", shot, "--object", "Nobody", "--text", TEXT, "--no-render")
    assert missing.returncode == 1 and "--object 'Nobody'" in missing.stderr and "TR_Head" in missing.stderr
    assert _digest(character) == before
