"""The .glb export, read back: re-imported into Blender it plays the same weights at the same frames."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lab.kit.heads_on_disk import HEADS  # noqa: E402
from turkish_lipsync import blender  # noqa: E402
from turkish_lipsync.blender import gltf_export, heads, shapekeys  # noqa: E402
from turkish_lipsync.blender.generate import generate  # noqa: E402
from turkish_lipsync.core.base.errors import LipSyncError  # noqa: E402
from turkish_lipsync.core.pipeline import LipSyncOptions  # noqa: E402

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "render.py"
VITRUVIAN = HEADS / "vitruvian" / "vitruvian_head_facs.glb"
TEXT = "<SENT><HAPPY>Merhaba</HAPPY>, benim adım Erdem.</SENT>"


def _weights(objects, frames):
    """object name -> (frames, keys) array of every non-basis key's value as the scene plays."""
    scene = bpy.context.scene
    result = {obj.name: [] for obj in objects}
    for frame in frames:
        scene.frame_set(frame)
        for obj in objects:
            result[obj.name].append([block.value for block in obj.data.shape_keys.key_blocks[1:]])
    return {name: np.array(values) for name, values in result.items()}


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    folder = tmp_path_factory.mktemp("glb")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = 30
    objects = heads.create_reference_head(bpy.context)
    head, teeth = objects["head"], objects["lower_teeth"]
    shapekeys.build_shape_keys(head)
    generated = generate(bpy.context, TEXT, LipSyncOptions(), audio_folder=str(folder), head=head)
    frames = range(scene.frame_start, scene.frame_end + 1)
    played = _weights([head, teeth], frames)
    key_names = {obj.name: [b.name for b in obj.data.shape_keys.key_blocks[1:]] for obj in (head, teeth)}
    teeth.select_set(True)
    bpy.context.view_layer.objects.active = teeth
    result = gltf_export.export_gltf(bpy.context, head, folder / "speech")
    selection = (teeth.select_get(), head.select_get(), bpy.context.view_layer.objects.active.name)
    return result, generated, frames, played, key_names, selection


def test_the_glb_and_the_wav_beside_it(exported):
    result, generated, frames, _, _, selection = exported
    assert result.path.endswith("speech.glb")
    # 37 visemes, 6 emotions + 6 releases, 2 blinks, a brow raise, 8 look keys (each eye four ways)
    assert result.morph_targets == 60
    assert result.animated_nodes >= 2  # the head and at least the teeth and tongue that follow the jaw
    assert (result.frame_start, result.frame_end) == (frames.start, frames.stop - 1)
    with open(generated.wav_path, "rb") as spoken, open(result.wav_path, "rb") as beside:
        assert spoken.read() == beside.read()
    assert result.wav_path.endswith("speech.wav")
    assert selection == (True, False, "TR_Head_LowerTeeth")  # the user's selection came back


def test_reimported_glb_plays_the_same_weights_at_the_same_frames(exported):
    result, _, frames, played, key_names, _ = exported
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.render.fps = 30
    bpy.ops.import_scene.gltf(filepath=result.path)
    imported = [bpy.data.objects[name] for name in played]
    for obj in imported:
        assert [b.name for b in obj.data.shape_keys.key_blocks[1:]] == key_names[obj.name]
    replayed = _weights(imported, frames)
    for name, weights in played.items():
        assert weights.max() > 0.5  # the speech moves the keys
        np.testing.assert_allclose(replayed[name], weights, atol=1e-4, err_msg=name)


def test_a_head_without_animation_is_refused(tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    head = heads.create_reference_head(bpy.context)["head"]
    with pytest.raises(LipSyncError, match="Build"):
        gltf_export.export_gltf(bpy.context, head, tmp_path / "x.glb")
    shapekeys.build_shape_keys(head)
    with pytest.raises(LipSyncError, match="Generate Animation"):
        gltf_export.export_gltf(bpy.context, head, tmp_path / "x.glb")
    assert not (tmp_path / "x.glb").exists()


def test_the_panels_export_operator(tmp_path):
    blender.register()
    try:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        head = heads.create_reference_head(bpy.context)["head"]
        settings = bpy.context.scene.turkish_lipsync
        settings.head = head
        settings.gltf_path = str(tmp_path / "panel.glb")
        shapekeys.build_shape_keys(head)
        with pytest.raises(RuntimeError, match="Generate the animation first"):
            bpy.ops.turkish_lipsync.export_gltf()
        generate(bpy.context, "Merhaba", LipSyncOptions(timing="table"), head=head)
        assert bpy.ops.turkish_lipsync.export_gltf() == {"FINISHED"}
        assert gltf_export.read_glb_document(tmp_path / "panel.glb")["animations"]
    finally:
        blender.unregister()


@pytest.mark.skipif(not VITRUVIAN.is_file(), reason="shared heads not found")
def test_render_script_writes_the_glb_of_a_head_with_its_own_visemes(tmp_path):
    out = tmp_path / "vitruvian.glb"
    completed = subprocess.run(
        [sys.executable, str(SCRIPT), "--text", "Merhaba, benim adım Erdem.", "--head", str(VITRUVIAN),
         "--no-render", "--gltf", str(out)],
        capture_output=True, text=True, timeout=600, check=False,
    )  # fmt: skip
    assert completed.returncode == 0, completed.stderr
    assert "from Azure / Microsoft visemes" in completed.stdout
    document = gltf_export.read_glb_document(out)
    names = document["meshes"][0]["extras"]["targetNames"]
    assert {"aa_02", "p_b_m_21", "TR_viseme_a", "TR_viseme_bpa"} <= set(names)  # its own keys and ours
    assert document["animations"]
    assert out.with_suffix(".wav").is_file()


def test_render_script_refuses_a_gltf_path_without_glb():
    completed = subprocess.run(
        [sys.executable, str(SCRIPT), "--text", "Merhaba", "--no-render", "--gltf", "x.gltf"],
        capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert completed.returncode != 0
    assert "must end in .glb" in completed.stderr


def test_the_head_and_eyes_turn_as_node_animation(exported):
    """The living layers' rotations travel as node animation: the head and both eye objects, turned as the
    scene turns them (the head's yaw over the take is what the tracks say, within the sampling)."""
    result, generated, _frames, _, _, _ = exported
    document = gltf_export.read_glb_document(result.path)
    names = [node.get("name") for node in document["nodes"]]
    turned = {
        names[channel["target"]["node"]]
        for animation in document["animations"]
        for channel in animation["channels"]
        if channel["target"]["path"] == "rotation"
    }
    assert {"TR_Head", "TR_Head_EyeLeft", "TR_Head_EyeRight"} <= turned
    motion = generated.tracks.head_and_eyes
    assert np.abs(motion.head).max() > 0.5 and np.abs(motion.left_eye[:, 0]).max() > 0.5
