"""The living face read off the evaluated scene frame by frame, as a viewer sees it: gaze, saccades,
blinks, head motion and the CSV's rotations (lab/measure/living.py prints the figures, the tests check them).

Builds the head (default: the reference head), adds the render's camera, generates about `seconds` of
Turkish speech, then steps every frame (frame_set and the evaluated depsgraph) and fits a rotation to the
evaluated eyeball vertices (each eye) and to the skull (head vertices no key moves). The gaze is each
eyeball's turned forward axis, against the direction from the eye to the camera; pauses come from the
speech WAV's own silences and F0 from Praat's tracker on the WAV (parselmouth), not from ours.
"""

from __future__ import annotations

import contextlib
import tempfile
import wave
from pathlib import Path

import bpy
import numpy as np

from lab.kit.corpus import corpus_sentences
from turkish_lipsync.blender import compat, eye_keys, heads, keyframes, living, mesh, pipeline
from turkish_lipsync.blender.generate import generate
from turkish_lipsync.blender.living_rig import find_rig
from turkish_lipsync.core.base.model import BLINK_KEYS, OWNED_PREFIX
from turkish_lipsync.core.faces.eyes import own_look_keys, sphere_fit
from turkish_lipsync.core.interchange import export_text
from turkish_lipsync.core.interchange.arkit_csv import HEADER, ROTATION_COLUMNS
from turkish_lipsync.core.motion.living import measures
from turkish_lipsync.core.pipeline import LipSyncOptions

WORDS_PER_SECOND = 1.9  # eSpeak's Turkish voice reading the corpus, pauses included


CONTACT_DEGREES = 2.0  # gaze within this of the target is eye contact


def speech_text(seconds: float) -> str:
    sentences = corpus_sentences()
    chosen, words = [], 0
    for sentence in sentences * 10:
        if words >= seconds * WORDS_PER_SECOND:
            break
        chosen.append(sentence)
        words += len(sentence.split())
    return " ".join(chosen)


def _read_wav(path: str) -> tuple[np.ndarray, int]:
    with wave.open(path, "rb") as handle:
        rate = handle.getframerate()
        samples = np.frombuffer(handle.readframes(handle.getnframes()), dtype="<i2")
    return samples, rate


def _praat_f0(samples: np.ndarray, rate: int, times: np.ndarray) -> np.ndarray:
    import parselmouth

    sound = parselmouth.Sound(samples.astype(np.float64) / 32768.0, rate)
    pitch = sound.to_pitch(time_step=0.01, pitch_floor=70, pitch_ceiling=420)
    values = pitch.selected_array["frequency"]
    values[values == 0] = np.nan
    index = np.clip(np.round((times - pitch.xs()[0]) / 0.01).astype(int), 0, len(values) - 1)
    return values[index]


def _probes(rig, head: bpy.types.Object) -> dict[str, tuple[str, np.ndarray]]:
    """Per eye, the object and vertex indices that show its turn: the eye object, the eyeball island, or
    (painted eyes) what the look keys move on that side."""
    probes = {}
    world = mesh.world_rest_coordinates(head).astype(np.float64)
    islands = eye_keys._islands(rig, world, head)
    for side, eye in rig.eyes.items():
        if eye.object_name:
            obj = bpy.data.objects[eye.object_name]
            probes[side] = (eye.object_name, np.arange(len(obj.data.vertices)))
        elif side in islands:
            probes[side] = (head.name, islands[side])
        else:
            keys = head.data.shape_keys
            looks = {name for name, _ in own_look_keys(b.name for b in keys.key_blocks).values()}
            rest = mesh.read_coordinates(keys.reference_key.points, len(world))
            moved = np.zeros(len(world), bool)
            for name in looks:
                moved |= (
                    np.linalg.norm(
                        mesh.read_coordinates(keys.key_blocks[name].points, len(world)) - rest, axis=1
                    )
                    > 1e-4
                )
            across = rig.to_head(world)[:, 0]
            probes[side] = (head.name, np.flatnonzero(moved & ((across > 0) == (side == "left"))))
    return probes


def skull_points(head: bpy.types.Object) -> np.ndarray:
    """Head vertices our keys move least (the back and top of the head): under 2 % of the most any key
    moves, else the least-moved third."""
    keys = head.data.shape_keys
    count = len(head.data.vertices)
    rest = mesh.read_coordinates(keys.reference_key.points, count)
    moved = np.zeros(count)
    for block in keys.key_blocks:
        if block.name.startswith(OWNED_PREFIX):
            moved = np.maximum(
                moved, np.linalg.norm(mesh.read_coordinates(block.points, count) - rest, axis=1)
            )
    still = np.flatnonzero(moved < 0.02 * moved.max())
    return still if len(still) >= 50 else np.argsort(moved)[: count // 3]


def lid_points(head: bpy.types.Object) -> tuple[np.ndarray, np.ndarray]:
    """The vertices the left blink moves most and their motion under it (local), to read the closure."""
    keys = head.data.shape_keys
    count = len(head.data.vertices)
    rest = mesh.read_coordinates(keys.reference_key.points, count)
    delta = mesh.read_coordinates(keys.key_blocks[BLINK_KEYS[0]].points, count) - rest
    size = np.linalg.norm(delta, axis=1)
    top = np.flatnonzero(size >= 0.8 * size.max())
    return top, delta[top]


@contextlib.contextmanager
def _without_our_keys(head: bpy.types.Object):
    """The head with our shape-key curves muted and our keys at 0: its rest as the scene shows it (the
    head's own keys at the values it came with)."""
    keys = head.data.shape_keys
    action = keys.animation_data.action if keys.animation_data else None
    values = {block.name: block.value for block in keys.key_blocks if block.name.startswith(OWNED_PREFIX)}
    paths = {keyframes.curve_data_path(name) for name in values}
    curves = [fc for fc in compat.all_action_fcurves(action) if fc.data_path in paths] if action else []
    for fcurve in curves:
        fcurve.mute = True
    for name in values:
        keys.key_blocks[name].value = 0.0
    bpy.context.view_layer.update()
    try:
        yield
    finally:
        for fcurve in curves:
            fcurve.mute = False
        for name, value in values.items():
            keys.key_blocks[name].value = value
        bpy.context.view_layer.update()


def evaluated_world(obj: bpy.types.Object, depsgraph) -> np.ndarray:
    evaluated = obj.evaluated_get(depsgraph)
    data = evaluated.to_mesh()
    try:
        local = mesh.read_coordinates(data.vertices, len(data.vertices)).astype(np.float64)
    finally:
        evaluated.to_mesh_clear()
    matrix = np.array(evaluated.matrix_world)
    return local @ matrix[:3, :3].T + matrix[:3, 3]


def sample_scene(context, head, rig, frames) -> dict:
    """Every frame's fitted head rotation, each eye's gaze direction and centre, and the lids' closure."""
    scene = context.scene
    probes = _probes(rig, head)
    skull = skull_points(head)
    lid, blink_motion = lid_points(head)
    with living.at_rest(scene), _without_our_keys(head):
        depsgraph = context.evaluated_depsgraph_get()
        rest = {name: evaluated_world(bpy.data.objects[name], depsgraph) for name, _ in probes.values()}
        rest[head.name] = evaluated_world(head, depsgraph)
    centres = {
        side: sphere_fit(rest[name][indices])[0] if len(indices) > 12 else rest[name][indices].mean(0)
        for side, (name, indices) in probes.items()
    }
    result = (
        {"head": [], "closure": []}
        | {f"{side}_gaze": [] for side in probes}
        | {f"{side}_centre": [] for side in probes}
        | {f"{side}_shift": [] for side in probes}
    )
    forward = rig.frame[:, 2]
    for frame in frames:
        scene.frame_set(int(frame))
        depsgraph = context.evaluated_depsgraph_get()
        world = {
            name: evaluated_world(bpy.data.objects[name], depsgraph)
            for name in {head.name, *(n for n, _ in probes.values())}
        }
        head_rotation = measures.fit_rotation(rest[head.name][skull], world[head.name][skull])
        result["head"].append(head_rotation)
        for side, (name, indices) in probes.items():
            rotation = measures.fit_rotation(rest[name][indices], world[name][indices])
            moved = world[name][indices]
            centre = moved.mean(0) + rotation @ (centres[side] - rest[name][indices].mean(0))
            result[f"{side}_gaze"].append(rotation @ forward)
            result[f"{side}_centre"].append(centre)
            # Painted eyes: how far the eye's vertices slide on the face, in the head's frame.
            shift = head_rotation.T @ (moved.mean(0) - world[head.name][skull].mean(0)) - (
                rest[name][indices].mean(0) - rest[head.name][skull].mean(0)
            )
            result[f"{side}_shift"].append(shift @ rig.frame)
        local = head_rotation.T @ (world[head.name][lid] - world[head.name][skull].mean(0)).T
        rest_local = (rest[head.name][lid] - rest[head.name][skull].mean(0)).T
        linear = mesh.world_matrix(head)[:3, :3]
        motion = blink_motion.astype(np.float64) @ linear.T
        moved_by = (local - rest_local).T
        result["closure"].append(
            float(np.einsum("ij,ij->", moved_by, motion) / np.einsum("ij,ij->", motion, motion))
        )
    return {key: np.array(value) for key, value in result.items()}


def figures(
    samples: dict, rig, camera: np.ndarray, fps: float, wav: str, csv_text: str, probes_sides
) -> dict:
    frames = len(samples["head"])
    times = np.arange(frames) / fps
    audio, rate = _read_wav(wav)
    pauses = measures.audio_pauses(audio, rate)
    speaking = np.array([measures.distance_to_spans(t, pauses) > 0 for t in times])
    out: dict[str, float] = {}
    gaze = np.mean([samples[f"{side}_gaze"] for side in probes_sides], axis=0)
    if all(f"{side}_centre" in samples for side in probes_sides) and rig.eyes_turn_by in (
        "objects",
        "keys",
        "bones",
    ):
        off = np.mean(
            [
                measures.angle_between(samples[f"{s}_gaze"], camera - samples[f"{s}_centre"])
                for s in probes_sides
            ],
            axis=0,
        )
        out["gaze_p95_deg"] = float(np.percentile(off, 95))
        out["contact_share"] = float((off[speaking] < CONTACT_DEGREES).mean())
    # An eye behind shut lids is not seen, and an artist's blink may move the eyeball (Vitruvian's pulls it
    # in): fast gaze mostly behind half-shut lids is not a saccade (one that a blink accompanies comes
    # before the lids close).
    lidded = samples["closure"] > 0.5
    found = [
        (start, length, amplitude)
        for start, length, amplitude in measures.saccades(gaze, fps)
        if lidded[start : start + length + 1].mean() <= 0.5
    ]
    amplitudes = np.array([a for _, _, a in found])
    durations = np.array([n / fps * 1000 for _, n, _ in found])
    minutes = frames / fps / 60
    out["saccades_per_min"] = len(found) / minutes
    if len(found):
        out["saccades_under_15_share"] = float((amplitudes < 15).mean())
        out["saccade_duration_vs_main_sequence"] = float(np.median(durations / (25 + 2.4 * amplitudes)))
    blinks = measures.blinks(samples["closure"], fps)
    starts = np.array([b["start"] for b in blinks])
    out["blinks_per_min"] = len(blinks) / minutes
    out["blink_gap_max_s"] = float(np.diff(np.r_[0.0, starts, frames / fps]).max()) if len(blinks) else np.inf
    out["blink_closing_ms"] = float(np.median([b["closing"] for b in blinks]) * 1000) if blinks else np.nan
    out["blink_opening_ms"] = float(np.median([b["opening"] for b in blinks]) * 1000) if blinks else np.nan
    shifts = [start / fps for start, _, amplitude in found if amplitude > 10]
    near = [
        min(measures.distance_to_spans(t, pauses), min((abs(t - s) for s in shifts), default=np.inf)) <= 0.25
        for t in starts
    ]
    out["blinks_near_pause_or_shift_share"] = float(np.mean(near)) if near else 0.0
    angles = measures.head_angles_of(samples["head"], rig.frame)
    total = np.degrees(np.arccos(np.clip((np.einsum("nii->n", samples["head"]) - 1) / 2, -1, 1)))
    out["head_rms_deg"] = float(np.sqrt(np.mean(total**2)))
    out["head_max_deg"] = float(total.max())
    f0 = _praat_f0(audio, rate, times)
    voiced = np.isfinite(f0)
    out["head_pitch_f0_r"] = float(np.corrcoef(angles[voiced, 1], 12 * np.log2(f0[voiced]))[0, 1])
    rows = [line.split(",") for line in csv_text.strip().splitlines()[1:]]
    columns = {name: index for index, name in enumerate(HEADER)}
    csv_rotations = np.array([[float(row[columns[name]]) for name in ROTATION_COLUMNS] for row in rows])
    out["csv_rotation_columns_nonzero"] = int((np.abs(csv_rotations).max(axis=0) > 0).sum())
    count = min(len(csv_rotations), frames)
    out["csv_head_pitch_vs_scene_r"] = float(np.corrcoef(csv_rotations[:count, 1], angles[:count, 1])[0, 1])
    out["head_yaw_std_deg"], out["head_pitch_std_deg"], out["head_roll_std_deg"] = (
        float(v) for v in angles.std(0)
    )
    return out


def measure(head_path: Path | None, seconds: float, fps: float, seed: int, text: str | None = None) -> dict:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    context = bpy.context
    scene = context.scene
    scene.render.fps = round(fps)
    head = None if head_path is None else heads.find_head(heads.import_head(head_path))
    report = pipeline.build_keys(context, head)
    head = bpy.data.objects[report.head]
    pipeline.frame_head(scene, head)
    context.view_layer.update()
    camera = np.array(scene.camera.matrix_world.translation)
    with tempfile.TemporaryDirectory() as folder:
        result = generate(
            context, text or speech_text(seconds), LipSyncOptions(seed=seed), audio_folder=folder, head=head
        )
        with living.at_rest(scene):
            rig = find_rig(head)
        frames = np.arange(result.frame_start, result.frame_end + 1)
        samples = sample_scene(context, head, rig, frames)
        csv_text, _ = export_text("arkit-csv", result.timeline, result.tracks)
        out = figures(samples, rig, camera, result.fps, result.wav_path, csv_text, tuple(rig.eyes))
    out["seconds"] = result.duration
    out["blink_opening_slower"] = float(out["blink_opening_ms"] > out["blink_closing_ms"])
    out["eyes_turn_by"] = rig.eyes_turn_by
    out["samples"] = samples
    out["tracks"] = result.tracks
    out["rig"] = rig
    return out
