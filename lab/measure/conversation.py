"""Measure a conversation on the evaluated scene: mouths, gaps, gaze, nods, blinks, head motion per character.

    .venv/bin/python -m lab.measure.conversation [--script examples/conversation.txt] [--fps 60]
        [--three examples/conversation_three.txt] [--only synthesis|recording|speakers|three] [--json]

Builds the default cast of the script (a default head per speaker on the arc, the render's two-shot camera)
and generates the scene four ways: synthesised; from ONE recording of the whole scene (the truth: each line
synthesised in its speaker's voice and joined with known gaps into one WAV, then aligned as one take); from
one recording per speaker (each speaker's lines alone at their true places, silence elsewhere); and a
script of three characters. Then it steps every frame (frame_set and the evaluated depsgraph) and reads what
a viewer sees: each character's jaw (its lower teeth's evaluated vertices, which only the mouth's keys
move), a rotation fitted to each eyeball (gaze) and to the skull (head), the lids' closure. Lines and
pauses come from each line's own audio (energy), phrase ends from the WAV's silences, not from our
timeline. Prints every figure of issue 32's "Done when" with its target.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

import bpy
import numpy as np

from lab import REPOSITORY
from lab.kit.living_scene import evaluated_world, lid_points, skull_points
from lab.kit.voices import cast_reading
from turkish_lipsync.blender import living, pipeline
from turkish_lipsync.blender.generate import generate
from turkish_lipsync.blender.living_rig import find_rig
from turkish_lipsync.core.motion.living import measures
from turkish_lipsync.core.pipeline import LipSyncOptions
from turkish_lipsync.core.scene import RoleChoice, cast_for, converse
from turkish_lipsync.core.scene.speech import SceneSources
from turkish_lipsync.core.speech import write_wav
from turkish_lipsync.core.text.script import CAMERA, read_script

ON_FACE_DEGREES = 5.0
# A mouth gets ready this long before its line's first sound and closes this long after its last; where a
# line overlaps another's end, that falls inside the other's line and is the speaker's own, not a listener's.
MOUTH_MARGIN = 0.15
SILENCE_DB = -35.0  # a line's own audio this far under its loud end is not speech

DONE_WHEN = {
    "jaw_in_others_lines_vs_own_median": (0.0, 0.05),
    "gap_min_s": (0.1, 0.6),
    "gap_max_s": (0.1, 0.6),
    "listening_gaze_on_speaker": (0.6, 1.0),
    "speaking_gaze_on_addressee": (0.3, 0.6),
    "nods_per_listening_minute": (2.0, 12.0),
    "nods_near_phrase_end_share": (0.5, 1.0),
    "blinks_per_min": (10.0, 35.0),
    "blink_gap_max_s": (0.0, 10.0),
    "head_about_its_target_rms_deg": (0.7, 6.0),
    "head_about_its_target_max_deg": (0.0, 15.0),
    "first_phone_error_max_ms": (0.0, 50.0),
    "first_phone_error_max_ms_lines_not_overlapping": (0.0, 50.0),
}


def new_scene(fps: float) -> bpy.types.Context:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps, scene.render.fps_base = round(fps), 1.0
    scene.render.resolution_x, scene.render.resolution_y = 960, 540
    return bpy.context


def generated_scene(source: str, fps: float, folder: str, sources: SceneSources | None = None, choices=None):
    context = new_scene(fps)
    script = read_script(source)
    result = generate(
        context, script.source, LipSyncOptions(), sources=sources, audio_folder=folder, choices=choices or {}
    )
    pipeline.frame_head(context.scene, None)  # the two-shot the render uses (it was where the eyes aimed)
    return context, result


# ---------------------------------------------------------------- what the scene shows


def sample(context, result) -> dict[str, dict]:
    """Per character, every frame: jaw opening, gaze direction, eyes' middle, head rotation, lids' closure."""
    scene = context.scene
    characters = {}
    for key, name in _heads(result).items():
        head = bpy.data.objects[name]
        with living.at_rest(scene):
            rig = find_rig(head)
        eyes = {side: bpy.data.objects[eye.object_name] for side, eye in rig.eyes.items()}
        teeth = next(o for o in pipeline.head_objects(head) if o.name.endswith("LowerTeeth"))
        lid, blink_motion = lid_points(head)
        depsgraph = context.evaluated_depsgraph_get()
        with living.at_rest(scene):
            depsgraph = context.evaluated_depsgraph_get()
            rest = {o.name: evaluated_world(o, depsgraph) for o in (head, *eyes.values())}
        characters[key] = {
            "head": head,
            "rig": rig,
            "eyes": eyes,
            "teeth": teeth,
            "teeth_rest": _local(teeth, depsgraph, rest=True),
            "skull": skull_points(head),
            "lid": lid,
            "blink_motion": blink_motion,
            "rest": rest,
            "samples": {name: [] for name in ("jaw", "gaze", "middle", "head", "closure")},
        }
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        depsgraph = context.evaluated_depsgraph_get()
        for character in characters.values():
            _sample_frame(character, depsgraph)
    return {
        key: {n: np.array(v) for n, v in c["samples"].items()} | {"rig": c["rig"]}
        for key, c in characters.items()
    }


def _heads(result) -> dict[str, str]:
    names = {role.name: role.key for role in result.scene.speech.cast.roles}
    return {names[name]: head for name, head in result.heads.items()}


def _local(obj, depsgraph, rest: bool = False) -> np.ndarray:
    """The evaluated mesh's vertices in the object's own frame: the shape keys' doing, not the motion's."""
    if rest:
        return np.array([v.co for v in obj.data.vertices], np.float64)
    evaluated = obj.evaluated_get(depsgraph)
    data = evaluated.to_mesh()
    try:
        flat = np.empty(len(data.vertices) * 3, np.float32)
        data.vertices.foreach_get("co", flat)
    finally:
        evaluated.to_mesh_clear()
    return flat.reshape(-1, 3).astype(np.float64)


def _sample_frame(character: dict, depsgraph) -> None:
    head, rig, rest = character["head"], character["rig"], character["rest"]
    samples = character["samples"]
    jaw = np.linalg.norm(_local(character["teeth"], depsgraph) - character["teeth_rest"], axis=1).mean()
    samples["jaw"].append(float(jaw))
    world = evaluated_world(head, depsgraph)
    skull = character["skull"]
    rotation = measures.fit_rotation(rest[head.name][skull], world[skull])
    samples["head"].append(rotation)
    gazes, centres = [], []
    for side, eye in character["eyes"].items():
        points = evaluated_world(eye, depsgraph)
        turned = measures.fit_rotation(rest[eye.name], points)
        gazes.append(turned @ rig.frame[:, 2])
        centres.append(points.mean(axis=0) + turned @ (rig.eyes[side].centre - rest[eye.name].mean(axis=0)))
    gaze = np.mean(gazes, axis=0)
    samples["gaze"].append(gaze / np.linalg.norm(gaze))
    samples["middle"].append(np.mean(centres, axis=0))
    lid = character["lid"]
    local = rotation.T @ (world[lid] - world[skull].mean(0)).T
    rest_local = (rest[head.name][lid] - rest[head.name][skull].mean(0)).T
    motion = character["blink_motion"].astype(np.float64) @ np.array(head.matrix_world)[:3, :3].T
    moved = (local - rest_local).T
    samples["closure"].append(
        float(np.einsum("ij,ij->", moved, motion) / np.einsum("ij,ij->", motion, motion))
    )


# ---------------------------------------------------------------- the figures


def line_spans(result, fps: float) -> list[tuple[str, str, float, float]]:
    """(speaker, addressee, first, last voiced second) of every line, read from its own audio where it has
    some (a piece of its own), else from its timeline (a recording holding several lines)."""
    spans = []
    pieces = {piece.line: piece for piece in result.scene.speech.pieces if piece.line is not None}
    for line in result.scene.speech.lines:
        first, last = line.first_phone, line.last_phone
        piece = pieces.get(line.index)
        if piece is not None:
            voiced = _voiced(piece.audio.samples, piece.audio.sample_rate)
            if voiced is not None:
                first, last = piece.start + voiced[0], piece.start + voiced[1]
        spans.append((line.speaker, line.addressee, first, last))
    return spans


def _voiced(samples: np.ndarray, rate: int) -> tuple[float, float] | None:
    hop = max(1, rate // 100)
    count = samples.size // hop
    power = (samples[: count * hop].astype(np.float64).reshape(count, hop) ** 2).mean(axis=1)
    level = 10 * np.log10(np.maximum(power, 1e-12) / max(np.percentile(power, 95), 1e-12))
    loud = np.flatnonzero(level > SILENCE_DB)
    return (loud[0] * hop / rate, (loud[-1] + 1) * hop / rate) if loud.size else None


def figures(result, sampled: dict, fps: float, camera: np.ndarray) -> dict:
    spans = line_spans(result, fps)
    out: dict = {}
    ordered = sorted(range(len(spans)), key=lambda i: spans[i][2])
    out["lines_in_script_order"] = ordered == list(range(len(spans)))
    gaps = [spans[i][2] - spans[i - 1][3] for i in range(1, len(spans))]
    overlapping = [line.overlaps for line in result.scene.speech.script.lines[1:]]
    turn_gaps = [g for g, o in zip(gaps, overlapping, strict=True) if not o]
    out["gap_min_s"], out["gap_max_s"] = min(turn_gaps), max(turn_gaps)
    out["gap_median_s"] = float(np.median(turn_gaps))
    mix = result.scene.speech.mix()
    pauses = measures.audio_pauses(mix.samples, mix.sample_rate) if mix is not None else []
    phrase_ends = np.array([start for start, _ in pauses if start > 0.1])
    per_character = {}
    for key, samples in sampled.items():
        count = len(samples["jaw"])
        times = np.arange(count) / fps
        own = np.zeros(count, bool)
        others = np.zeros(count, bool)
        preparing = np.zeros(count, bool)
        for speaker, _addressee, first, last in spans:
            inside = (times >= first) & (times <= last)
            (own if speaker == key else others)[inside] = True
            if speaker == key:
                preparing[(times >= first - MOUTH_MARGIN) & (times <= last + MOUTH_MARGIN)] = True
        figures_of = {}
        jaw = samples["jaw"]
        median = float(np.median(jaw[own])) if own.any() else np.nan
        figures_of["jaw_own_median_mm"] = median * 1000
        figures_of["jaw_in_others_lines_vs_own_median"] = float(jaw[others & ~preparing].max() / median)
        on = {"speaking": [], "listening": []}
        for speaker, addressee, first, last in spans:
            inside = (times >= first) & (times <= last)
            if speaker == key:
                target = camera if addressee == CAMERA else sampled[addressee]["middle"][inside]
                mode = "speaking"
            else:
                if own[inside].any():
                    inside &= ~own  # the overlap of its own line: it speaks then
                target = sampled[speaker]["middle"][inside]
                mode = "listening"
            off = measures.angle_between(samples["gaze"][inside], target - samples["middle"][inside])
            on[mode].append(off < ON_FACE_DEGREES)
        figures_of["listening_gaze_on_speaker"] = float(np.concatenate(on["listening"]).mean())
        figures_of["speaking_gaze_on_addressee"] = float(np.concatenate(on["speaking"]).mean())
        rig = samples["rig"]
        angles = measures.head_angles_of(samples["head"], rig.frame)
        listening = others & ~own
        found = measures.nods(angles[:, 1], fps)
        heard = [t for t in found if listening[min(int(round(t * fps)), count - 1)]]
        minutes = listening.sum() / fps / 60
        figures_of["nods_per_listening_minute"] = len(heard) / minutes if minutes else 0.0
        near = [np.min(np.abs(phrase_ends - t)) <= 0.5 for t in heard] if phrase_ends.size else []
        figures_of["nods_near_phrase_end_share"] = float(np.mean(near)) if near else 0.0
        blinks = measures.blinks(samples["closure"], fps)
        starts = np.array([b["start"] for b in blinks])
        figures_of["blinks_per_min"] = len(blinks) / (count / fps / 60)
        figures_of["blink_gap_max_s"] = float(np.diff(np.r_[0.0, starts, count / fps]).max())
        figures_of["blink_closing_ms"] = (
            float(np.median([b["closing"] for b in blinks]) * 1000) if blinks else 0
        )
        total = np.degrees(np.arccos(np.clip((np.einsum("nii->n", samples["head"]) - 1) / 2, -1, 1)))
        figures_of["head_rotation_rms_deg"] = float(np.sqrt(np.mean(total**2)))
        figures_of["head_rotation_max_deg"] = float(total.max())
        about = _about_target(angles, result, key, fps)
        figures_of["head_about_its_target_rms_deg"] = float(np.sqrt(np.mean(np.sum(about**2, axis=1))))
        figures_of["head_about_its_target_max_deg"] = float(np.abs(about).max())
        per_character[result.scene.speech.cast.role(key).name] = figures_of
    out["characters"] = per_character
    return out


def _about_target(angles: np.ndarray, result, key: str, fps: float) -> np.ndarray:
    """The head's yaw, pitch, roll less its median within each span of attention (whom it looks at): its
    motion about the turn toward its target."""
    attention = result.scene.character(key).tracks.extra["attention"]
    about = angles.copy()
    times = np.arange(len(angles)) / fps
    for start, end, _mode, _target in attention:
        inside = (times >= start + 0.6) & (times <= end)  # after the head has turned
        if inside.any():
            about[inside] -= np.median(angles[inside], axis=0)
        turning = (times >= start) & (times < start + 0.6)
        about[turning] = 0.0
    return about


def first_phone_errors(result, truth) -> list[float]:
    """Seconds between each line's first phone as aligned and where the truth put it."""
    return [
        abs(a.first_phone - b.first_phone)
        for a, b in zip(result.scene.speech.lines, truth.lines, strict=True)
    ]


# ---------------------------------------------------------------- runs


def measure_synthesis(source: str, fps: float, folder: str) -> dict:
    context, result = generated_scene(source, fps, folder)
    camera = np.array(context.scene.camera.matrix_world.translation)
    sampled = sample(context, result)
    out = figures(result, sampled, fps, camera)
    out["duration_s"] = result.duration
    out["lines"] = len(result.scene.speech.lines)
    return out


def truth_recordings(source: str, folder: Path, reading: dict[str, float]) -> tuple:
    """The scene synthesised by the core (its lines at known places) as one WAV and as one per speaker; read
    in the cast's own voices, or (reading) faster or lower than the voices the alignment hears."""
    script = read_script(source)
    cast = cast_for(script)
    choices = cast_reading(cast, reading)
    truth = converse(script, cast_for(script, choices), LipSyncOptions(fps=25)).speech
    stem = "_".join(f"{k}{v:g}" for k, v in reading.items()) or "same"
    scene_wav = write_wav(folder / f"scene_truth_{stem}.wav", truth.mix())
    tracks = {
        role.name: write_wav(folder / f"truth_{stem}_{role.key}.wav", truth.voice_of(role.key))
        for role in cast.roles
    }
    return truth, scene_wav, tracks


def measure_recordings(source: str, fps: float, folder: str, wanted: set[str]) -> dict:
    results = {}
    for reading, named in (
        ({}, "the cast's voices"),
        ({"rate": 1.12, "pitch": 0.9}, "a faster, lower reading"),
    ):
        truth, scene_wav, tracks = truth_recordings(source, Path(folder), reading)
        runs = []
        if "recording" in wanted:
            runs.append(("one recording of the scene", SceneSources(scene_recording=scene_wav), None))
        if "speakers" in wanted:
            choices = {name: RoleChoice(recording=path) for name, path in tracks.items()}
            runs.append(("one recording per speaker", None, choices))
        for label, sources, choices in runs:
            context, result = generated_scene(source, fps, folder, sources, choices)
            errors = first_phone_errors(result, truth)
            camera = np.array(context.scene.camera.matrix_world.translation)
            measured = figures(result, sample(context, result), fps, camera)
            overlapping = [line.overlaps for line in result.scene.speech.script.lines]
            turns = [e for e, o in zip(errors, overlapping, strict=True) if not o]
            results[f"{label}, {named}"] = {
                "first_phone_error_max_ms": max(errors) * 1000,
                "first_phone_error_median_ms": float(np.median(errors)) * 1000,
                "first_phone_error_max_ms_lines_not_overlapping": max(turns) * 1000,
                "lines_within_50_ms": f"{sum(e <= 0.05 for e in errors)} of {len(errors)}",
                "characters": {
                    name: {"jaw_in_others_lines_vs_own_median": c["jaw_in_others_lines_vs_own_median"]}
                    for name, c in measured["characters"].items()
                },
                "warnings": len(result.warnings),
            }
    return results


def _verdict(name: str, value) -> str:
    bounds = DONE_WHEN.get(name)
    if bounds is None or not isinstance(value, int | float):
        return ""
    return f"   [{bounds[0]:g}, {bounds[1]:g}] " + (
        "ok" if bounds[0] <= value <= bounds[1] else "OUT OF RANGE"
    )


def show(title: str, out: dict) -> None:
    print(f"\n== {title}")
    for name, value in out.items():
        if name == "characters":
            for character, values in value.items():
                print(f"  {character}:")
                for key, number in values.items():
                    print(f"    {key:40s} {number:10.3f}{_verdict(key, number)}")
        elif isinstance(value, float):
            print(f"  {name:42s} {value:10.3f}{_verdict(name, value)}")
        else:
            print(f"  {name:42s} {value!s:>10s}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--script", type=Path, default=REPOSITORY / "examples" / "conversation.txt")
    parser.add_argument("--three", type=Path, default=REPOSITORY / "examples" / "conversation_three.txt")
    parser.add_argument("--fps", type=float, default=60.0)
    parser.add_argument("--only", choices=("synthesis", "recording", "speakers", "three"), action="append")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else None)
    wanted = set(args.only or ("synthesis", "recording", "speakers", "three"))
    source = args.script.read_text(encoding="utf-8")
    report = {}
    with tempfile.TemporaryDirectory() as folder:
        if "synthesis" in wanted:
            report["two characters, synthesised"] = measure_synthesis(source, args.fps, folder)
        if wanted & {"recording", "speakers"}:
            for label, values in measure_recordings(source, args.fps, folder, wanted).items():
                report[f"two characters, {label}"] = values
        if "three" in wanted:
            report["three characters, synthesised"] = measure_synthesis(
                args.three.read_text(encoding="utf-8"), args.fps, folder
            )
    if args.json:
        print(json.dumps(report, indent=1, ensure_ascii=False, default=str))
        return 0
    for title, out in report.items():
        show(title, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
