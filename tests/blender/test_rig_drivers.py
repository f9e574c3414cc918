"""A head whose ARKit keys a control rig drives (as Faceit's does): Generate keys the controls, not the keys
underneath them, and refuses drivers it cannot move with what to do."""

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from mathutils import Quaternion  # noqa: E402

from tests.blender.evaluated import evaluated_world  # noqa: E402
from turkish_lipsync.blender import compat, heads, mesh, shapekeys  # noqa: E402
from turkish_lipsync.blender.generate import generate  # noqa: E402
from turkish_lipsync.blender.marked_curves import FACE_RIG  # noqa: E402
from turkish_lipsync.core.base.errors import HeadError  # noqa: E402
from turkish_lipsync.core.faces.measure import FaceMeasure  # noqa: E402
from turkish_lipsync.core.faces.reference import load_reference_head  # noqa: E402

pytestmark = pytest.mark.usefixtures("registered_extension")

TEXT = "Ama babam dedi ki."
# control bone -> (unit it drives, the channel its driver reads, the driver's expression of it as "v"):
# location and rotation channels, scaled, clamped and some read the other way, as control rigs do.
CONTROLS = {
    "c_jaw": ("jawOpen", "ROT_X", "max(0, min(1, v / 0.4))"),
    "c_lips": ("mouthClose", "LOC_Z", "max(0, min(1, v * 40))"),
    "c_press": ("mouthPressLeft", "LOC_Z", "max(0, min(1, -v * 25))"),
    "c_smile.L": ("mouthSmileLeft", "LOC_X", "max(0, min(1, v * 30))"),
    "c_blink.L": ("eyeBlinkLeft", "LOC_Z", "max(0, min(1, -v * 50))"),
}


def _controlled_head():
    """The default head with ARKit keys of its own (the reference's units), driven by a control rig."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.render.fps = 25
    head = heads.create_reference_head(bpy.context)["head"]
    reference = load_reference_head()
    skin = reference.parts["skin"]
    head.shape_key_add(name="Basis")
    rest = mesh.rest_coordinates(head)
    for unit in (
        "jawOpen",
        "mouthClose",
        "mouthPressLeft",
        "mouthPressRight",
        "mouthSmileLeft",
        "eyeBlinkLeft",
    ):
        block = head.shape_key_add(name=unit)
        block.points.foreach_set("co", (rest + reference.units[unit][skin]).ravel())
        block.value = 0.0
    shapekeys.build_shape_keys(head)  # the TR keys from the head's own units
    armature = bpy.data.objects.new("ControlRig", bpy.data.armatures.new("ControlRig"))
    bpy.context.scene.collection.objects.link(armature)
    bpy.context.view_layer.objects.active = armature
    bpy.ops.object.mode_set(mode="EDIT")
    for number, name in enumerate(CONTROLS):
        bone = armature.data.edit_bones.new(name)
        bone.head, bone.tail = (0.1 * number, -0.3, 1.0), (0.1 * number, -0.3, 1.05)
    bpy.ops.object.mode_set(mode="OBJECT")
    for bone, (unit, channel, expression) in CONTROLS.items():
        fcurve = head.data.shape_keys.key_blocks[unit].driver_add("value")
        variable = fcurve.driver.variables.new()
        variable.name = "v"
        variable.type = "TRANSFORMS"
        variable.targets[0].id = armature
        variable.targets[0].bone_target = bone
        variable.targets[0].transform_type = channel
        variable.targets[0].transform_space = "LOCAL_SPACE"
        fcurve.driver.expression = expression
    bpy.context.view_layer.update()
    assert (
        head.data.shape_keys.evaluated_get(bpy.context.evaluated_depsgraph_get()).key_blocks["jawOpen"].value
        == 0
    )
    return head, armature


def test_a_control_rig_that_drives_the_keys_is_keyed_instead_of_the_keys():
    head, armature = _controlled_head()
    result = generate(bpy.context, TEXT, head=head)
    action = armature.animation_data.action
    ours = set(action[FACE_RIG.curves_property])
    assert {'pose.bones["c_jaw"].rotation_quaternion', 'pose.bones["c_lips"].location'} <= ours
    key_action = head.data.shape_keys.animation_data.action if head.data.shape_keys.animation_data else None
    keyed = {fc.data_path for fc in compat.all_action_fcurves(key_action)} if key_action else set()
    # Nothing the rig moves is keyed underneath it (the keys of visemes none of its units make stay free).
    for viseme in ("a", "bpa", "ma", "e"):
        assert f'key_blocks["TR_viseme_{viseme}"].value' not in keyed
    # The driven jawOpen follows what the visemes ask of it, through the control.
    a = result.tracks.track("TR_viseme_a")
    peak = 1 + int(a.frames[np.argmax(a.values)])
    bpy.context.scene.frame_set(peak)
    evaluated = head.data.shape_keys.evaluated_get(bpy.context.evaluated_depsgraph_get())
    names, weights = result.tracks.sample(np.array([peak - 1.0]))
    from turkish_lipsync.core.faces.recipes import load_recipes

    recipes = load_recipes().key_recipes()
    expected = sum(w * recipes.get(n, {}).get("jawOpen", 0.0) for n, w in zip(names, weights[0], strict=True))
    assert evaluated.key_blocks["jawOpen"].value == pytest.approx(expected, abs=0.03)
    rest = mesh.world_rest_coordinates(head).astype(np.float64)
    measure = FaceMeasure(
        rest, [list(p.vertices) for p in head.data.polygons], shapekeys.head_landmarks(head)
    )
    assert measure.lip_aperture(evaluated_world(head) - rest) > 5e-3
    assert armature.pose.bones["c_jaw"].rotation_quaternion.angle > 0.1


def test_the_probing_puts_every_control_back_as_it_was():
    head, armature = _controlled_head()
    jaw = armature.pose.bones["c_jaw"]
    jaw.rotation_quaternion = Quaternion((1, 0, 0), 0.05)
    before = tuple(jaw.rotation_quaternion)
    from turkish_lipsync.blender.rig_drivers import driven_face_rig

    face = driven_face_rig(head)
    assert tuple(jaw.rotation_quaternion) == pytest.approx(before)
    assert set(face.mapping.poses) == {unit for unit, _channel, _expression in CONTROLS.values()}
    # The press is read the other way: its pose moves its control down.
    assert face.mapping.poses["mouthPressLeft"].bones["c_press"].location[2] < 0


def test_keys_driven_by_something_no_bone_moves_are_refused_with_what_to_do():
    head, _armature = _controlled_head()
    empty = bpy.data.objects.new("Slider", None)
    bpy.context.scene.collection.objects.link(empty)
    fcurve = head.data.shape_keys.key_blocks["mouthPressRight"].driver_add("value")
    variable = fcurve.driver.variables.new()
    variable.type = "TRANSFORMS"
    variable.targets[0].id = empty
    variable.targets[0].transform_type = "LOC_X"
    with pytest.raises(HeadError, match="mouthPressRight.*overridden by it"):
        generate(bpy.context, TEXT, head=head)
