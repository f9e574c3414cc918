"""Several characters from one script in Blender: a head per speaker, its own action and record, the lines'
strips, Generate again replacing only ours, exports per character, a Papagayo project of the scene read back,
three characters, the panel's operators. Scenes are short and at 12 fps: the motion is the core's
(tests/core/test_scene.py measures it); here is what the scene holds."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from tests.blender.evaluated import evaluated_world  # noqa: E402
from tests.render_runs import run_render  # noqa: E402
from turkish_lipsync import blender  # noqa: E402
from turkish_lipsync.blender import compat, conversation, exports, living, pipeline, scene_record  # noqa: E402
from turkish_lipsync.blender.generate import generate  # noqa: E402
from turkish_lipsync.blender.living_rig import find_rig  # noqa: E402
from turkish_lipsync.core.base.model import viseme_key_name  # noqa: E402
from turkish_lipsync.core.motion.living import measures  # noqa: E402
from turkish_lipsync.core.pipeline import LipSyncOptions  # noqa: E402
from turkish_lipsync.core.scene import RoleChoice  # noqa: E402
from turkish_lipsync.core.scene.speech import SceneSources  # noqa: E402
from turkish_lipsync.core.speech.cues.papagayo_pgo import read_pgo_voices  # noqa: E402
from turkish_lipsync.core.text.script import read_script  # noqa: E402

TWO = (
    "AYŞE (to ALİ): Merhaba Ali, nasılsın?\nALİ: İyiyim, sağ ol. Sen nasılsın?\n"
    "AYŞE: <HAPPY>Ben de iyiyim.</HAPPY>"
)
THREE = "ZEYNEP (to MEHMET): Mehmet, bak!\nALİ: Ne oldu?\nMEHMET (to ALİ): Zeynep birinci olmuş."
FPS = 12


def _scene(tmp_path: Path, source: str = TWO, choices=None, sources=None):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.render.fps = FPS
    return generate(
        bpy.context,
        read_script(source).source,
        LipSyncOptions(),
        sources=sources,
        audio_folder=str(tmp_path / "audio"),
        choices=choices or {},
    )


def _strip_names() -> list[str]:
    strips = compat.sequencer_strips(bpy.context.scene, create=False)
    return sorted(strip.name for strip in strips) if strips is not None else []


def _lower_teeth_opening(head) -> float:
    teeth = next(o for o in pipeline.head_objects(head) if o.name.endswith("LowerTeeth"))
    rest = np.array([v.co for v in teeth.data.vertices])
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = teeth.evaluated_get(depsgraph)
    shape = evaluated.to_mesh()
    moved = np.array([v.co for v in shape.vertices])
    evaluated.to_mesh_clear()
    return float(np.linalg.norm(moved - rest, axis=1).mean())


def test_two_characters_each_speak_only_their_lines_and_look_at_each_other(tmp_path):
    result = _scene(tmp_path)
    assert set(result.heads) == {"Ayşe", "Ali"}
    heads = {name: bpy.data.objects[head] for name, head in result.heads.items()}
    # Two default heads beside each other, turned toward each other, in tones of their own.
    left, right = sorted(heads.values(), key=lambda head: head.location.x)
    assert right.location.x - left.location.x > 0.3
    assert left.rotation_euler.z > 0.2 and right.rotation_euler.z < -0.2
    assert heads["Ayşe"].data.materials[0] != heads["Ali"].data.materials[0]
    # One strip per line, named by speaker; the whole scene's sound recorded for the render.
    if compat.HAS_AUDIO:
        assert _strip_names() == ["TR_Ali 2", "TR_Ayşe 1", "TR_Ayşe 3"]
    assert Path(result.wav_path).is_file()
    # Each record holds only its own lines; the listener's jaw rests while the other speaks.
    for name, head in heads.items():
        record = pipeline.animation_record(head)
        assert record is not None and record.head_and_eyes is not None
        words = {word.text for word in record.timeline.words}
        assert ("merhaba" in words) == (name == "Ayşe") and ("iyiyim" in words)
    scene = bpy.context.scene
    lines = result.scene.speech.lines
    ali_line = lines[1]
    middle = scene.frame_start + round((ali_line.first_phone + ali_line.last_phone) / 2 * FPS)
    openings = {}
    for frame in range(scene.frame_start + round(ali_line.first_phone * FPS), middle + FPS):
        scene.frame_set(frame)
        for name, head in heads.items():
            openings.setdefault(name, []).append(_lower_teeth_opening(head))
    assert max(openings["Ali"]) > 0.001 and max(openings["Ayşe"]) < 0.05 * max(openings["Ali"])
    # While Ali speaks, Ayşe's eyes are on his face (within 5 degrees) most of the time, as the scene shows.
    with living.at_rest(scene):
        rigs = {name: find_rig(head) for name, head in heads.items()}
        rest = {
            side: evaluated_world(bpy.data.objects[eye.object_name])
            for side, eye in rigs["Ayşe"].eyes.items()
        }
    on_face = []
    for frame in range(scene.frame_start + round(ali_line.first_phone * FPS), middle + FPS):
        scene.frame_set(frame)
        gaze, centres = [], []
        for side, eye in rigs["Ayşe"].eyes.items():
            moved = evaluated_world(bpy.data.objects[eye.object_name])
            turn = measures.fit_rotation(rest[side], moved)
            gaze.append(turn @ rigs["Ayşe"].frame[:, 2])
            centres.append(moved.mean(axis=0))
        ali_eyes = np.mean(
            [
                evaluated_world(bpy.data.objects[eye.object_name]).mean(axis=0)
                for eye in rigs["Ali"].eyes.values()
            ],
            axis=0,
        )
        off = measures.angle_between(np.mean(gaze, axis=0), ali_eyes - np.mean(centres, axis=0))
        on_face.append(off < 5.0)
    assert np.mean(on_face) > 0.5


def test_generate_again_replaces_only_ours(tmp_path):
    first = _scene(tmp_path)
    scene = bpy.context.scene
    strips = compat.sequencer_strips(scene, create=True)
    theirs = strips.new_sound("music", first.wav_path, 9, 1) if compat.HAS_AUDIO else None
    ali = bpy.data.objects[first.heads["Ali"]]
    own = ali.shape_key_add(name="Smirk")
    own.value = 0.3
    prop = bpy.data.objects.new("Prop", None)
    scene.collection.objects.link(prop)
    prop.keyframe_insert("location", frame=3)
    objects_before = len(bpy.data.objects)
    actions_before = sorted(action.name for action in bpy.data.actions)
    again = generate(
        bpy.context, read_script(TWO).source, LipSyncOptions(), audio_folder=str(tmp_path / "audio")
    )
    assert again.heads == first.heads
    assert len(bpy.data.objects) == objects_before
    assert sorted(action.name for action in bpy.data.actions) == actions_before
    assert ali.data.shape_keys.key_blocks["Smirk"].value == pytest.approx(0.3)
    assert prop.animation_data.action is not None
    if theirs is not None:
        assert "music" in _strip_names() and len(_strip_names()) == 4
    # A shorter script: its strips replace all of ours; one head alone afterwards takes the strips away.
    generate(
        bpy.context,
        read_script("AYŞE: Evet.\nALİ: Hayır.").source,
        LipSyncOptions(),
        audio_folder=str(tmp_path),
    )
    if theirs is not None:
        assert _strip_names() == ["TR_Ali 2", "TR_Ayşe 1", "music"]
    generate(bpy.context, "Merhaba.", LipSyncOptions(), audio_folder=str(tmp_path), head=ali)
    assert scene_record.conversation_record(scene) is None
    if theirs is not None:
        assert _strip_names() == ["TR_speech", "music"]


def test_three_characters_address_whom_the_script_says(tmp_path):
    result = _scene(tmp_path, THREE)
    assert len(result.heads) == 3
    xs = sorted(bpy.data.objects[name].location.x for name in result.heads.values())
    assert xs[0] < xs[1] < xs[2]
    speech = result.scene.speech
    # Ali names nobody: he speaks to the last speaker.
    assert [line.addressee for line in speech.lines] == ["mehmet", "zeynep", "ali"]
    for line in speech.lines:
        middle = (line.first_phone + line.last_phone) / 2
        for character in result.scene.characters:
            attention = character.tracks.extra["attention"]
            mode, target = next((m, t) for s, e, m, t in attention if s <= middle <= e)
            if character.role.key == line.speaker:
                assert (mode, target) == ("speaking", line.addressee)
            else:
                assert (mode, target) == ("listening", line.speaker)
    # The two-shot (three-shot) camera sees every face.
    pipeline.frame_head(bpy.context.scene, None)
    bpy.context.view_layer.update()
    camera = bpy.context.scene.camera
    matrix = np.array(camera.matrix_world.inverted())
    for name in result.heads.values():
        point = matrix @ np.array([*bpy.data.objects[name].matrix_world.translation, 1.0])
        assert point[2] < 0  # in front of the camera
        assert abs(point[0] / point[2]) < 0.3  # within the 70 mm lens' half width


def test_exports_per_character_and_a_papagayo_project_that_times_the_scene_again(tmp_path):
    result = _scene(tmp_path)
    written = exports.export_scene(bpy.context, "rhubarb-json", tmp_path / "scene.json")
    assert sorted(p.path.name for p in written) == ["scene_Ali.json", "scene_Ayşe.json"]
    cues = json.loads((tmp_path / "scene_Ali.json").read_text(encoding="utf-8"))["mouthCues"]
    ali_line = result.scene.speech.lines[1]
    spoken = [c for c in cues if c["value"] != "X"]
    assert abs(spoken[0]["start"] - ali_line.first_phone) < 1.5 / FPS
    csvs = exports.export_scene(bpy.context, "arkit-csv", tmp_path / "scene.csv")
    assert len(csvs) == 2 and all(p.path.is_file() for p in csvs)
    (pgo,) = exports.export_scene(bpy.context, "papagayo-pgo", tmp_path / "scene.pgo")
    voices = read_pgo_voices(pgo.path)
    assert [voice.voice_name for voice in voices] == ["Ayşe", "Ali"]
    again = _scene(tmp_path, sources=SceneSources(cues=pgo.path))
    for before, after in zip(result.scene.speech.lines, again.scene.speech.lines, strict=True):
        assert abs(before.first_phone - after.first_phone) <= 1.01 / FPS
    assert again.scene.speech.timing == "cues"


def test_gltf_per_character_and_of_the_whole_scene(tmp_path):
    _scene(tmp_path)
    written = conversation.export_conversation_gltf(bpy.context, tmp_path / "scene.glb")
    assert [Path(w.path).name for w in written] == ["scene.glb", "scene_Ayşe.glb", "scene_Ali.glb"]
    assert written[0].animated_nodes >= 2 and all(Path(w.wav_path).is_file() for w in written)


def test_a_head_given_for_a_speaker_plays_them(tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    report = pipeline.build_keys(bpy.context, None)
    mine = bpy.data.objects[report.head]
    mine.location.x = 2.0
    result = generate(
        bpy.context,
        read_script(TWO).source,
        LipSyncOptions(),
        audio_folder=str(tmp_path),
        choices={"ali": RoleChoice(head=mine.name, variant="m7")},
    )
    assert result.heads["Ali"] == mine.name and mine.location.x == pytest.approx(2.0)
    assert pipeline.animation_record(mine).settings["voice"] == "m7"
    assert result.heads["Ayşe"] != mine.name


def test_the_panel_fills_the_cast_and_generates_the_scene(tmp_path):
    blender.register()
    try:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        bpy.context.scene.render.fps = FPS
        settings = bpy.context.scene.turkish_lipsync
        text = bpy.data.texts.new("scene")
        text.write(TWO)
        settings.source_kind, settings.text = "TEXT", text
        settings.audio_folder = str(tmp_path)
        assert bpy.ops.turkish_lipsync.fill_cast() == {"FINISHED"}
        assert [member.name for member in settings.cast] == ["Ayşe", "Ali"]
        settings.cast[1].voice = "m1"
        assert bpy.ops.turkish_lipsync.generate() == {"FINISHED"}
        heads = [member.head for member in settings.cast]
        assert all(head is not None for head in heads)
        assert pipeline.animation_record(heads[1]).settings["voice"] == "m1"
        curves = heads[0].data.shape_keys.animation_data.action
        assert any(
            fc.data_path.endswith(f'"{viseme_key_name("a")}"].value')
            for fc in compat.all_action_fcurves(curves)
        )
    finally:
        blender.unregister()


def test_render_script_casts_a_scene_from_the_command_line(tmp_path):
    source = tmp_path / "scene.txt"
    source.write_text(TWO, encoding="utf-8")
    saved = tmp_path / "scene.blend"
    completed = run_render(
        "--jsml", source, "--cast", "ali=default", "--voice", "Ayşe=f5:1.1", "--fps", FPS, "--no-render",
        "--save-blend", saved, "--export", f"rhubarb-tsv={tmp_path / 'cues.tsv'}",
    )  # fmt: skip
    assert completed.returncode == 0, completed.stderr
    assert "Generated 3 lines of 2 characters" in completed.stdout
    assert (tmp_path / "cues_Ayşe.tsv").is_file() and (tmp_path / "cues_Ali.tsv").is_file()
    bpy.ops.wm.open_mainfile(filepath=str(saved))
    record = scene_record.conversation_record(bpy.context.scene)
    assert set(record.names.values()) == {"Ayşe", "Ali"}
    ayse = bpy.data.objects[record.heads["ayşe"]]
    assert pipeline.animation_record(ayse).settings["voice"] == "f5"
    refused = run_render("--text", TWO, "--cast", "Veli=default", "--no-render")
    assert refused.returncode == 1 and "never speaks" in refused.stderr
    assert len(evaluated_world(ayse)) > 0


class _Layout:
    """A stand-in for Blender's UI layout that checks every property the panel draws exists."""

    def __init__(self, drawn: list):
        self.drawn = drawn

    def __getattr__(self, name):
        def call(*args, **kwargs):
            if name == "prop":
                data, prop = args[0], args[1]
                assert prop in data.bl_rna.properties, prop
                self.drawn.append(prop)
            if name == "template_list":
                self.drawn.append(args[0])
            if name == "panel":
                return _Layout(self.drawn), _Layout(self.drawn)
            return _Layout(self.drawn)

        return call


def test_the_panel_draws_the_cast_and_each_speakers_settings():
    from turkish_lipsync.blender import panel

    blender.register()
    try:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        settings = bpy.context.scene.turkish_lipsync
        member = settings.cast.add()
        member.name = "Ayşe"
        drawn: list = []
        panel.VIEW3D_PT_turkish_lipsync.draw_cast(_Layout(drawn), settings)
        assert {"TURKISH_LIPSYNC_UL_cast", "head", "voice", "pitch", "voice_rate", "recording"} <= set(drawn)
        row: list = []
        panel.TURKISH_LIPSYNC_UL_cast.draw_item(
            None, None, _Layout(row), settings, member, 0, settings, "cast_index"
        )
        assert row == ["head", "voice"]
    finally:
        blender.unregister()
