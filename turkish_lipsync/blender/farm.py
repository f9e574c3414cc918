"""Farm rendering: one frame range of the saved .blend as a chunk that the join copies without re-encoding.

A render manager (Flamenco: farm/flamenco/turkish_lipsync.js) gives each worker a frame range; every worker
renders its range of the same .blend with the same settings, and one task joins the chunks with the speech
(core/interchange/video.py). The chunks are lossless H.264 without B-frames and without sound: the frames
are then the frames a single render gives, their timestamps follow on from chunk to chunk, and the speech
is encoded once over the whole length instead of once per chunk (which would add the AAC encoder's padding
at every seam).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import bpy

from . import compat, pipeline, render

VIDEO_SUFFIXES = (".mp4", ".mkv")
IMAGE_NUMBER = "######"  # Blender's frame-number placeholder: frame 7 of a sequence is 000007.png


@dataclass(frozen=True)
class ChunkResult:
    path: Path  # the video, or the folder of numbered PNG frames
    engine: str
    first_frame: int
    last_frame: int
    seconds: float


def is_video_chunk(path: Path | str) -> bool:
    return Path(path).suffix.lower() in VIDEO_SUFFIXES


def configure_chunk_video(scene: bpy.types.Scene) -> None:
    """Lossless H.264 with no B-frames and no audio (see the module docstring for why)."""
    ffmpeg = scene.render.ffmpeg
    if Path(scene.render.filepath).suffix.lower() == ".mkv":
        ffmpeg.format = "MKV"
    ffmpeg.constant_rate_factor = "LOSSLESS"
    ffmpeg.use_max_b_frames = True
    ffmpeg.max_b_frames = 0
    ffmpeg.audio_codec = "NONE"


def render_chunk(
    context: bpy.types.Context,
    head: bpy.types.Object | None,
    out_path: str,
    first_frame: int,
    last_frame: int,
    *,
    engine: str,
    samples: int | None = None,
    resolution: tuple[int, int] | None = None,
    progress: pipeline.Progress | None = None,
) -> ChunkResult:
    """Render frames first_frame..last_frame of the open scene to a video chunk (.mp4, .mkv) or, for any
    other path, to a folder of PNG frames named by frame number. The scene is framed, lit and set up as
    a whole render would be; the scene's frame range is put back afterwards."""
    scene = context.scene
    if not scene.frame_start <= first_frame <= last_frame <= scene.frame_end:
        raise render.RenderError(
            f"Frames {first_frame}-{last_frame} are not inside the scene's frames {scene.frame_start}-"
            f"{scene.frame_end}; give a range within them (the render manager splits the scene's range)."
        )
    if engine.upper() == "AUTO":
        raise render.RenderError(
            "Chunks need a fixed engine (CYCLES, EEVEE or WORKBENCH): 'auto' could choose differently on "
            "different workers, and the joined video would change engine mid-way."
        )
    out = Path(bpy.path.abspath(out_path))
    video = is_video_chunk(out)
    prepared = pipeline.prepare_render(
        context,
        head,
        str(out if video else out / "chunk.mp4"),
        engine=engine,
        samples=samples,
        resolution=resolution,
    )
    if video:
        configure_chunk_video(scene)
    else:
        out.mkdir(parents=True, exist_ok=True)
        compat.set_image_output(scene.render.image_settings, "PNG")
        scene.render.use_file_extension = True
        scene.render.filepath = str(out / IMAGE_NUMBER)
    saved_range = (scene.frame_start, scene.frame_end)
    started = time.perf_counter()
    if progress is not None:
        progress(0.05, f"Rendering frames {first_frame}-{last_frame} to {out}")
    try:
        scene.frame_start, scene.frame_end = first_frame, last_frame
        bpy.ops.render.render(animation=True, scene=scene.name)
    finally:
        scene.frame_start, scene.frame_end = saved_range
    written = out.is_file() if video else len(list(out.glob("*.png"))) >= last_frame - first_frame + 1
    if not written:
        raise render.RenderError(f"Blender did not write {out}; see the console for the render error.")
    return ChunkResult(out, prepared.engine, first_frame, last_frame, time.perf_counter() - started)
