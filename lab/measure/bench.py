"""Benchmarks: speed, memory and scale of the whole pipeline. Prints one JSON object.

    .venv/bin/python -m lab.measure.bench [--runs 3] [--render-frames 3] [--no-render]
    .venv/bin/python -m lab.measure.bench --noise PAIRS  (how far the living layers' cost strays where it's 0)

Every figure is the median of --runs runs, each run in a fresh process (so peak memory is that run's own);
comparisons are ratios measured inside one run. Heads: the default (reference) head and a 27,000-vertex head
(the reference head subdivided, so it has no keys and no reference vertex order: keys must be transferred).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from lab import REPOSITORY

TEN_MINUTE_WORDS = 1500
FPS = 25
PLAYBACK_FRAMES = 500
# Generate's progress reports, by the share of the work they announce: the stage each begins.
GENERATE_STAGES = {
    0.05: "text_to_tracks",
    0.45: "speech_wav",
    0.6: "head_and_eyes",
    0.7: "shape_key_curves",
    0.85: "sound_strip",
}
SLOW_KEYFRAME_SUBSET = 5000  # per-key keyframe_insert is timed on whole tracks of about this many keys


def ten_minute_text() -> str:
    """About 1,500 words of real Turkish sentences (the corpus, repeated in a shuffled order)."""
    import random

    from lab.kit.corpus import corpus_sentences

    sentences = corpus_sentences()
    chosen, words, generator = [], 0, random.Random(7)
    while words < TEN_MINUTE_WORDS:
        order = sentences[:]
        generator.shuffle(order)
        for sentence in order:
            chosen.append(sentence)
            words += len(sentence.split())
            if words >= TEN_MINUTE_WORDS:
                break
    return "\n".join(chosen)


# ---------------------------------------------------------------- one run, inside a fresh process


def _fresh_scene():
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = FPS
    return bpy.context


def _dense_head(context):
    """A 27,000-vertex head without keys: the reference subdivided, its face (the front fifth) twice.

    Denser at the face, as artists' heads are; no longer in the reference's vertex order, so its keys must be
    transferred.
    """
    import bmesh
    import numpy as np

    from turkish_lipsync.blender import heads

    objects = heads.create_reference_head(context, name="Dense_Head")
    head = objects["head"]
    mesh = bmesh.new()
    mesh.from_mesh(head.data)
    bmesh.ops.subdivide_edges(mesh, edges=mesh.edges[:], cuts=1, use_grid_fill=True)
    front = np.quantile([vertex.co.y for vertex in mesh.verts], 0.2)
    face_edges = [edge for edge in mesh.edges if max(vertex.co.y for vertex in edge.verts) < front]
    bmesh.ops.subdivide_edges(mesh, edges=face_edges, cuts=1, use_grid_fill=True)
    mesh.to_mesh(head.data)
    mesh.free()
    for obj in objects.values():
        obj.pop(heads.REFERENCE_PART_PROPERTY, None)
    return head


def run_end_to_end(head_kind: str, living_on: bool = True) -> dict:
    """Text to a speaking head as Build Shape Keys and Generate Animation make it, no render: the keys built,
    the text read, spoken, timed and keyed, its record kept, the sound written and placed; with the living
    layers (gaze, blinks, head motion, expression: pitch tracking included) or without."""
    context = _fresh_scene()
    import bpy

    from turkish_lipsync.blender import compat, heads, shapekeys
    from turkish_lipsync.blender.generate import generate
    from turkish_lipsync.core import pipeline as core_pipeline
    from turkish_lipsync.core.pipeline import LIVING_LAYERS, LipSyncOptions

    # The speech engine's own time (synthesis and alignment), timed where Generate calls it: the same work
    # with the living layers or without, and the most variable part of a run.
    engine_seconds = []
    speak = core_pipeline.speak

    def timed_speak(request):
        started = time.perf_counter()
        try:
            return speak(request)
        finally:
            engine_seconds.append(time.perf_counter() - started)

    core_pipeline.speak = timed_speak

    text = ten_minute_text()
    head = heads.create_reference_head(context)["head"] if head_kind == "default" else _dense_head(context)
    options = LipSyncOptions(fps=FPS, **({} if living_on else dict.fromkeys(LIVING_LAYERS, False)))
    stages, marks = {}, []

    def progress(fraction: float, message: str) -> None:
        marks.append((time.perf_counter(), GENERATE_STAGES.get(fraction, message)))

    with tempfile.TemporaryDirectory() as folder:
        started, cpu_started = time.perf_counter(), time.process_time()
        report = shapekeys.build_shape_keys(head)
        stages["shape_keys_s"] = time.perf_counter() - started
        result = generate(context, text, options, audio_folder=folder, progress=progress, head=head)
        total = time.perf_counter() - started
        cpu = time.process_time() - cpu_started
    # Generate's own stages, between its progress reports.
    for (mark, stage), (following, _) in zip(marks, marks[1:], strict=False):
        stages[f"{stage}_s"] = following - mark
    speech_minutes = result.duration / 60
    keys = sum(
        len(fcurve.keyframe_points)
        for action in bpy.data.actions
        for fcurve in compat.all_action_fcurves(action)
    )
    return {
        "end_to_end_s": total,
        # The process's own CPU time: on a shared machine it varies less than the wall clock.
        "end_to_end_cpu_s": cpu,
        "speech_engine_s": sum(engine_seconds),
        "speech_minutes": speech_minutes,
        "s_per_minute_of_speech": total / speech_minutes,
        "words": len(result.timeline.words),
        "phones": result.phone_count,
        "keyframes": keys,
        "vertices": len(head.data.vertices),
        "key_source": report.source,
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        **stages,
    }


def run_keyframes() -> dict:
    """Our bulk writer against Blender's per-key keyframe_insert on the same tracks."""
    context = _fresh_scene()
    from turkish_lipsync.blender import heads, keyframes, pipeline, shapekeys
    from turkish_lipsync.core.motion import weight_tracks
    from turkish_lipsync.core.speech import synthesize_timeline
    from turkish_lipsync.core.text.utterance import build_utterance

    head = heads.create_reference_head(context)["head"]
    shapekeys.build_shape_keys(head)
    timeline = synthesize_timeline(build_utterance(ten_minute_text()), "phone").timeline
    tracks = weight_tracks(timeline, FPS)
    started = time.perf_counter()
    written = keyframes.write_weight_tracks([head], tracks, 1, "TR_bench")
    fast_seconds = time.perf_counter() - started
    fast_keys = sum(w.key_count for w in written)

    keyframes.remove_weight_tracks(pipeline.head_objects(head))
    blocks = head.data.shape_keys.key_blocks
    # Per-key inserts slow down as a curve grows, so the subset is made of whole tracks of typical length
    # (those nearest the median key count), not the cheap first keys of one curve.
    keyed = [t for t in tracks.tracks if t.name in blocks]
    median = statistics.median(len(t.frames) for t in keyed)
    subset = []
    for track in sorted(keyed, key=lambda t: abs(len(t.frames) - median)):
        subset += [(blocks[track.name], f, v) for f, v in zip(track.frames, track.values, strict=True)]
        if len(subset) >= SLOW_KEYFRAME_SUBSET:
            break
    started = time.perf_counter()
    for block, frame, value in subset:
        block.value = value
        block.keyframe_insert("value", frame=frame + 1)
    slow_seconds = time.perf_counter() - started
    per_key_fast = fast_seconds / fast_keys
    per_key_slow = slow_seconds / len(subset)
    return {
        "keyframe_writer_s": fast_seconds,
        "keyframe_writer_keys": fast_keys,
        "keyframe_insert_s_per_key": per_key_slow,
        "keyframe_insert_subset_keys": len(subset),
        "keyframe_speedup": per_key_slow / per_key_fast,
    }


def run_build() -> dict:
    """The 43 keys from a head's own ARKit keys, and by transfer, on the 27,000-vertex head."""
    context = _fresh_scene()
    from turkish_lipsync.blender import owned_keys, shapekeys
    from turkish_lipsync.core.faces.arkit_names import ARKIT_UNITS

    head = _dense_head(context)
    started = time.perf_counter()
    transferred = shapekeys.build_shape_keys(head, source="transfer", arkit_keys=True)
    transfer_seconds = time.perf_counter() - started
    # The head now carries the 52 ARKit units: hand them over as if an artist had made them, and rebuild.
    owned_keys.disown(head, ARKIT_UNITS)
    started = time.perf_counter()
    own = shapekeys.build_shape_keys(head, source="arkit")
    own_seconds = time.perf_counter() - started
    return {
        "transfer_build_s": transfer_seconds,
        "shape_keys_build_s": own_seconds,
        "build_vertices": len(head.data.vertices),
        "transfer_source": transferred.source,
        "own_source": own.source,
    }


def run_playback() -> dict:
    """scene.frame_set plus the evaluated mesh, over 500 animated frames of the 27,000-vertex head."""
    import numpy as np

    context = _fresh_scene()
    from turkish_lipsync.blender import keyframes, pipeline, shapekeys
    from turkish_lipsync.core.motion import weight_tracks
    from turkish_lipsync.core.speech import synthesize_timeline
    from turkish_lipsync.core.text.utterance import build_utterance

    head = _dense_head(context)
    shapekeys.build_shape_keys(head, source="transfer")
    timeline = synthesize_timeline(build_utterance(ten_minute_text()), "phone").timeline
    keyframes.write_weight_tracks(pipeline.head_objects(head), weight_tracks(timeline, FPS), 1, "TR_bench")
    scene = context.scene
    coordinates = np.empty(len(head.data.vertices) * 3, dtype=np.float32)
    depsgraph = context.evaluated_depsgraph_get()
    animated = sum(1 for block in head.data.shape_keys.key_blocks if block.name.startswith("TR_"))
    started = time.perf_counter()
    for frame in range(1, PLAYBACK_FRAMES + 1):
        scene.frame_set(frame)
        head.evaluated_get(depsgraph).data.vertices.foreach_get("co", coordinates)
    seconds = time.perf_counter() - started
    return {
        "playback_fps": PLAYBACK_FRAMES / seconds,
        "playback_vertices": len(head.data.vertices),
        "playback_keys": animated,
    }


def run_render(frames: int) -> dict:
    """Cycles on the CPU at 640x640 with the demo's settings: seconds per frame."""
    context = _fresh_scene()
    from turkish_lipsync.blender import pipeline
    from turkish_lipsync.blender.generate import generate

    source = (REPOSITORY / "examples" / "demo.jsml").read_text(encoding="utf-8")
    head_name = pipeline.build_keys(context, None).head
    head = context.scene.objects[head_name]
    result = generate(context, source, head=head)
    context.scene.frame_end = result.frame_start + frames - 1
    with tempfile.TemporaryDirectory() as folder:
        rendered = pipeline.render_video(
            context, head, str(Path(folder) / "bench.mp4"), engine="CYCLES", resolution=(640, 640)
        )
    return {"render_s_per_frame": rendered.seconds / rendered.frame_count, "render_frames": frames}


# ---------------------------------------------------------------- the driver


def _in_fresh_process(part: str, *arguments: str) -> dict:
    command = [sys.executable, "-m", __spec__.name, "--part", part, *arguments]
    result = subprocess.run(command, capture_output=True, text=True, cwd=REPOSITORY)
    if result.returncode != 0:
        raise SystemExit(f"benchmark part {part} failed:\n{result.stderr[-3000:]}")
    return json.loads(result.stdout.strip().splitlines()[-1])


def _pair_costs(with_runs: list[dict], without_runs: list[dict], key: str) -> list[float]:
    """For each pair of runs, how much longer the one with the layers took than the one without."""
    return [a[key] / b[key] - 1.0 for a, b in zip(with_runs, without_runs, strict=True)]


def _pair_costs_beside_speech(with_runs: list[dict], without_runs: list[dict]) -> list[float]:
    """The same, each run's speech engine time set aside: what the layers add to the rest of the run, over
    the whole run without them."""
    return [
        ((a["end_to_end_s"] - a["speech_engine_s"]) - (b["end_to_end_s"] - b["speech_engine_s"]))
        / b["end_to_end_s"]
        for a, b in zip(with_runs, without_runs, strict=True)
    ]


def _living_pairs(pairs: int, both_off: bool = False) -> tuple[list[dict], list[dict]]:
    """Runs with and without the living layers in pairs, so both see the same load, each pair's first run the
    other kind than the last pair's: a run's place in its pair is worth a few per cent on a shared machine.
    both_off: the layers off in both (the estimators' noise)."""
    default_runs, still_runs = [], []
    for run in range(pairs):
        for living_on in (True, False) if run % 2 == 0 else (False, True):
            kind = [] if living_on and not both_off else ["--no-living"]
            (default_runs if living_on else still_runs).append(
                _in_fresh_process("end_to_end", "--head", "default", *kind)
            )
    return default_runs, still_runs


def _noise(pairs: int) -> dict:
    """The cost estimators over pairs of runs that differ in nothing: the spread a real cost must clear."""
    first, second = _living_pairs(pairs, both_off=True)
    spread = {
        "living_layers_cost": _pair_costs(first, second, "end_to_end_s"),
        "living_layers_cost_beside_speech": _pair_costs_beside_speech(first, second),
    }
    return {"pairs": pairs, "layers": "off in both runs of every pair"} | {
        name: {"min": min(costs), "median": statistics.median(costs), "max": max(costs)}
        for name, costs in spread.items()
    }


def _median_of(runs: list[dict]) -> dict:
    merged = {}
    for key, value in runs[0].items():
        values = [run[key] for run in runs]
        merged[key] = statistics.median(values) if isinstance(value, int | float) else value
    return merged


def _machine() -> str:
    cpu = next(
        (
            line.split(":", 1)[1].strip()
            for line in Path("/proc/cpuinfo").read_text().splitlines()
            if line.startswith("model name")
        ),
        platform.processor() or "unknown CPU",
    )
    memory_gib = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    return f"{os.cpu_count()} cores, {cpu}, {memory_gib:.0f} GiB, {platform.system()} {platform.release()}"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--render-frames", type=int, default=3)
    parser.add_argument("--no-render", action="store_true")
    parser.add_argument("--part", help=argparse.SUPPRESS)
    parser.add_argument("--head", default="default", help=argparse.SUPPRESS)
    parser.add_argument("--no-living", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument(
        "--noise",
        type=int,
        metavar="PAIRS",
        help="only the cost estimators' spread with the layers off in both",
    )
    args = parser.parse_args()

    if args.part:
        parts = {
            "end_to_end": lambda: run_end_to_end(args.head, not args.no_living),
            "keyframes": run_keyframes,
            "build": run_build,
            "playback": run_playback,
            "render": lambda: run_render(args.render_frames),
        }
        print(json.dumps(parts[args.part]()))
        return 0
    if args.noise:
        print(json.dumps(_noise(args.noise), indent=1))
        return 0

    import bpy

    runs = max(1, args.runs)
    default_runs, still_runs = _living_pairs(runs)
    default, still = _median_of(default_runs), _median_of(still_runs)
    dense = _median_of([_in_fresh_process("end_to_end", "--head", "dense") for _ in range(runs)])
    keyframe = _median_of([_in_fresh_process("keyframes") for _ in range(runs)])
    build = _median_of([_in_fresh_process("build") for _ in range(runs)])
    playback = _median_of([_in_fresh_process("playback") for _ in range(runs)])
    result = {
        "machine": _machine(),
        "blender": bpy.app.version_string,
        "runs": runs,
        "end_to_end_s_10min": default["end_to_end_s"] * 10 / default["speech_minutes"],
        "end_to_end_s_per_minute_of_speech": default["s_per_minute_of_speech"],
        "end_to_end_s_10min_dense_head": dense["end_to_end_s"] * 10 / dense["speech_minutes"],
        "end_to_end_s_10min_living_off": still["end_to_end_s"] * 10 / still["speech_minutes"],
        # Each run with the layers against the run without them beside it (the same load), the median
        # of those ratios: the speech engine's own time varies by a tenth from run to run.
        "living_layers_cost": statistics.median(_pair_costs(default_runs, still_runs, "end_to_end_s")),
        "living_layers_cost_cpu": statistics.median(
            _pair_costs(default_runs, still_runs, "end_to_end_cpu_s")
        ),
        # eSpeak NG's synthesis and alignment do the same work with the layers or without, and vary by a tenth
        # from run to run: the cost with each run's own engine time set aside.
        "living_layers_cost_beside_speech": statistics.median(
            _pair_costs_beside_speech(default_runs, still_runs)
        ),
        "keyframe_speedup": keyframe["keyframe_speedup"],
        "shape_keys_build_s": build["shape_keys_build_s"],
        "transfer_build_s": build["transfer_build_s"],
        "playback_fps": playback["playback_fps"],
        "peak_rss_mb": max(default["peak_rss_mb"], dense["peak_rss_mb"]),
        "end_to_end_default_head": default,
        "end_to_end_default_head_living_off": still,
        "end_to_end_dense_head": dense,
        "keyframes": keyframe,
        "build": build,
        "playback": playback,
    }
    if not args.no_render:
        render = _median_of(
            [_in_fresh_process("render", "--render-frames", str(args.render_frames)) for _ in range(runs)]
        )
        result["render_s_per_frame"] = render["render_s_per_frame"]
    print(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
