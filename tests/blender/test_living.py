"""The living face on the evaluated scene, on every kind of head: eye objects, eyeball islands, painted eyes
turned by VRM look keys with a head bone. Measured as a viewer sees it (lab/kit/living_scene.py: frame_set,
the evaluated depsgraph, rotations fitted to the eyeballs and the skull), never on the keys."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lab.kit import living_scene  # noqa: E402
from lab.kit.heads_on_disk import HEADS  # noqa: E402
from turkish_lipsync.blender import living, pipeline  # noqa: E402
from turkish_lipsync.blender.generate import generate  # noqa: E402
from turkish_lipsync.core.pipeline import LipSyncOptions  # noqa: E402

TEXT = (
    "Bugün hava çok güzel, parka gidip biraz yürüyüş yapalım mı? Sonra eve dönüp birlikte yemek yeriz. "
    "Akşam da kitap okuruz, dedi annem."
)
FPS = 60


def _measured(head_path):
    if head_path is not None and not head_path.is_file():
        pytest.skip(f"{head_path} is not on this machine")
    return living_scene.measure(head_path, 30, FPS, 0)


def _kinds_of_motion(result) -> None:
    """What every head must show: a head that turns a few degrees with the voice, blinks, glances."""
    assert 0.7 <= result["head_rms_deg"] <= 6 and result["head_max_deg"] <= 15
    assert abs(result["head_pitch_f0_r"]) >= 0.25
    assert result["blinks_per_min"] >= 10 and result["blink_gap_max_s"] <= 10
    assert result["blink_closing_ms"] <= 120 and result["blink_opening_ms"] > result["blink_closing_ms"]
    assert result["saccades_per_min"] >= 6


@pytest.mark.parametrize(
    "head",
    [
        None,
        HEADS / "makehuman" / "mh_head_expression_units.glb",
        HEADS / "vitruvian" / "vitruvian_head_facs.glb",
    ],
    ids=[
        "default head (eye objects, children)",
        "MakeHuman glb (eye objects beside it)",
        "Vitruvian (eyeballs in the mesh)",
    ],
)
def test_eyeballs_seek_the_camera_and_dart_away_while_the_head_moves(head):
    result = _measured(head)
    _kinds_of_motion(result)
    assert result["gaze_p95_deg"] >= 3
    assert 0.25 <= result["contact_share"] <= 0.7
    assert result["saccades_under_15_share"] >= 0.8
    assert 0.6 <= result["saccade_duration_vs_main_sequence"] <= 1.7
    assert result["csv_rotation_columns_nonzero"] == 9 and result["csv_head_pitch_vs_scene_r"] >= 0.8


def test_godette_turns_its_head_bone_and_its_painted_eyes_with_its_look_keys():
    result = _measured(HEADS / "godette" / "Godette_vrm_v4_named.glb")
    assert result["eyes_turn_by"] == "keys" and result["rig"].head_bone == "head_Armature"
    _kinds_of_motion(result)
    samples, motion = result["samples"], result["tracks"].head_and_eyes
    count = len(samples["left_shift"])
    for side in ("left", "right"):
        shift = samples[f"{side}_shift"]
        angles = getattr(motion, f"{side}_eye")[:count]
        # The painted eye slides toward the character's left as the eye turns left, up as it looks up.
        assert np.corrcoef(shift[:, 0], angles[:, 0])[0, 1] > 0.9
        assert np.corrcoef(shift[:, 1], angles[:, 1])[0, 1] > 0.3
        assert np.ptp(shift[:, 0]) > 0.002  # metres: visibly


def test_generate_again_replaces_only_our_motion_and_keeps_the_users_keys(tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    context = bpy.context
    report = pipeline.build_keys(context, None)
    head = bpy.data.objects[report.head]
    eye = bpy.data.objects[f"{head.name}_EyeLeft"]
    # The user's own: a location key on the head, a static delta on the eye, a constraint.
    head.location.x = 0.05
    head.keyframe_insert("location", index=0, frame=1)
    eye.delta_location = (0.0, 0.0, 0.001)
    head.constraints.new("LIMIT_SCALE")
    for _ in range(2):
        generate(context, TEXT, LipSyncOptions(), audio_folder=str(tmp_path), head=head)
    action = head.animation_data.action
    paths = sorted({fc.data_path for fc in action.fcurves}) if hasattr(action, "fcurves") else None
    curves = [fc.data_path for fc in living.compat.all_action_fcurves(action)]
    assert curves.count("location") == 1  # the user's key, once
    assert curves.count("delta_location") == 3 and curves.count("delta_rotation_euler") == 3  # ours, once
    assert paths is None or "location" in paths
    assert len(head.constraints) == 1
    # Off again: our motion goes, the user's delta comes back.
    generate(
        context, TEXT, LipSyncOptions(gaze=False, head_motion=False), audio_folder=str(tmp_path), head=head
    )
    assert [fc.data_path for fc in living.compat.all_action_fcurves(head.animation_data.action)] == [
        "location"
    ]
    assert tuple(eye.delta_location) == pytest.approx((0.0, 0.0, 0.001))
    assert eye.animation_data is None or eye.animation_data.action is None


def test_thesis_mode_keeps_the_thesis_still_unless_asked(tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    context = bpy.context
    head = bpy.data.objects[pipeline.build_keys(context, None).head]
    still = generate(context, TEXT, LipSyncOptions(motion="thesis"), audio_folder=str(tmp_path), head=head)
    assert still.tracks.head_and_eyes is None and head.animation_data is None
    moving = generate(
        context,
        TEXT,
        LipSyncOptions(motion="thesis", head_motion=True),
        audio_folder=str(tmp_path),
        head=head,
    )
    assert np.abs(moving.tracks.head_and_eyes.head).max() > 0.5
    assert head.animation_data.action is not None
