"""The steps of an episode's scene as a farm runs them (farm/steps.toml): build, render a chunk, join.

Each can be run again: a step whose output is there, made from the same inputs, says so and does nothing
(a build from the same files, a chunk from the same .blend with the same settings); what a step writes
appears only whole (the .blend and each chunk are written under another name and renamed once checked), so a
task killed midway leaves nothing a later step could take for done. The Blender work runs in a process of
its own: the given Blender (`blender -b -P ...`), else this Python with its bpy module.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path

from ..base.errors import LipSyncError
from . import CHECKOUT
from .manifest import Episode, Scene, read_episode

RENDER_SCRIPT = CHECKOUT / "scripts" / "render.py"
CHUNK_NAME = re.compile(r"^frames-(\d+)-(\d+)\.mp4$")
BUILD_RECORD = "build.json"


class TaskError(LipSyncError):
    """A step of a scene that failed; the message names the scene (and the frames) and what to do."""


def chunk_name(first: int, last: int) -> str:
    return f"frames-{first:04d}-{last:04d}.mp4"


def file_digest(path: Path) -> str:
    digest = hashlib.sha256()
    with Path(path).open("rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def write_json(path: Path, data: dict) -> None:
    """Written whole or not at all (a reader never sees half a record)."""
    partial = path.with_name(f".{path.name}.partial")
    partial.write_text(json.dumps(data, ensure_ascii=False, indent=1), encoding="utf-8")
    os.replace(partial, path)


def read_json(path: Path) -> dict | None:
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


# ---------------------------------------------------------------- one Blender process


def blender_command(blender: str, script: Path, arguments: list[str]) -> list[str]:
    """The script run in Blender (`BLENDER -b -P SCRIPT -- ARGS`), or with this Python's bpy module."""
    if not blender:
        return [sys.executable, str(script), *arguments]
    found = shutil.which(blender) or (blender if Path(blender).is_file() else None)
    if found is None:
        raise TaskError(f"no Blender at {blender!r}: give the path of a Blender executable, or none for bpy")
    return [found, "-b", "--python-exit-code", "1", "-P", str(script), "--", *arguments]


def run_blender(command: list[str], what: str) -> None:
    """Run it, its output passing through; render.py's one error line becomes this task's error."""
    error_line = None
    process = subprocess.Popen(command, stderr=subprocess.PIPE, text=True, encoding="utf-8", errors="replace")
    try:
        for line in process.stderr:
            if line.startswith("render.py: error: "):
                error_line = line.split(": error: ", 1)[1].strip()
            else:
                sys.stderr.write(line)
        code = process.wait()
    finally:
        if process.poll() is None:  # this task was stopped: its Blender stops with it
            process.kill()
            process.wait()
    if code < 0:
        name = signal.Signals(-code).name
        raise TaskError(f"{what}: its Blender process was killed ({name}) before it finished; run it again")
    if code:
        raise TaskError(f"{what}: {error_line or f'Blender exited with code {code} (its output is above)'}")


def video_frames(path: Path) -> int:
    import av

    with av.open(os.fspath(path)) as container:
        stream = container.streams.video[0]
        return stream.frames or sum(1 for packet in container.demux(stream) if packet.dts is not None)


def _holds_frames(chunk: Path, count: int) -> bool:
    """The chunk is there and readable with all its frames (not cut short by a full disk, say)."""
    import av

    try:
        return chunk.is_file() and video_frames(chunk) == count
    except (OSError, IndexError, av.error.FFmpegError):
        return False


# ---------------------------------------------------------------- build


def build_inputs(episode: Episode, scene: Scene, frames: tuple[int, int]) -> str:
    """What the build is made from, as one digest: the scene's settings (paths relative to the episode),
    every file they name and the extension's version; the same digest on every machine."""
    from ..base.data import read_toml_file

    folder = str(episode.folder)
    version = read_toml_file(CHECKOUT / "blender_manifest.toml").get("version", "")
    described = {
        "arguments": [argument.replace(folder, "{episode}") for argument in scene.arguments],
        "files": {str(path).replace(folder, "{episode}"): file_digest(path) for path in scene.inputs},
        "frames": list(frames),
        "version": version,
    }
    return hashlib.sha256(json.dumps(described, sort_keys=True).encode()).hexdigest()


def _built_already(record: dict | None, inputs: str, blend: Path, speech: Path) -> bool:
    if not record or record.get("inputs") != inputs or not blend.is_file():
        return False
    speech_kept = record.get("speech") is None or (
        speech.is_file() and file_digest(speech) == record["speech"]
    )
    return speech_kept and file_digest(blend) == record.get("blend")


def build_scene(
    folder: Path, name: str, frames: tuple[int, int], blend: Path, speech: Path, blender: str
) -> None:
    """The scene built from the episode's files and saved to `blend`, its speech copied to `speech`."""
    episode = read_episode([folder], only=name)
    scene = episode.scene(name)
    inputs = build_inputs(episode, scene, frames)
    record_path = blend.parent / BUILD_RECORD
    if _built_already(read_json(record_path), inputs, blend, speech):
        print(f"{name}: built already from these files ({blend}); skipped", flush=True)
        return
    started = time.perf_counter()
    blend.parent.mkdir(parents=True, exist_ok=True)
    for stale in (record_path, blend, speech):  # a build of other files: what the last one made is stale
        stale.unlink(missing_ok=True)
    building = blend.with_name(f"{blend.stem}.building.blend")
    result_path = blend.with_name(f".{blend.stem}.building.json")
    try:
        arguments = [*scene.arguments, "--no-render", "--save-blend", str(building)]
        arguments += ["--audio-folder", str(blend.parent / "audio"), "--built-json", str(result_path)]
        run_blender(blender_command(blender, RENDER_SCRIPT, arguments), name)
        result = read_json(result_path) or {}
        built = tuple(result.get("frames", ()))
        if len(built) != 2:
            raise TaskError(f"{name}: the build saved no scene (Blender's output is above); build it again")
        if built != frames:
            raise TaskError(
                f"{name}: the scene was built with frames {built[0]}-{built[1]} but the job was made for "
                f"{frames[0]}-{frames[1]}: its files changed since; make the job again (episode.py job)"
            )
        speech_digest = None
        if result.get("speech"):
            partial = speech.with_name(f".{speech.name}.partial")
            shutil.copyfile(result["speech"], partial)
            os.replace(partial, speech)
            speech_digest = file_digest(speech)
        os.replace(building, blend)
    finally:
        building.unlink(missing_ok=True)
        result_path.unlink(missing_ok=True)
    write_json(
        record_path,
        {"inputs": inputs, "frames": list(frames), "blend": file_digest(blend), "speech": speech_digest},
    )
    seconds = time.perf_counter() - started
    print(f"{name}: built frames {frames[0]}-{frames[1]} in {seconds:.1f} s: {blend}, {speech}", flush=True)


# ---------------------------------------------------------------- render a chunk


@dataclass(frozen=True)
class ChunkStamp:
    """What a chunk was rendered from: the .blend's digest and the render settings."""

    blend: str
    engine: str
    samples: int
    frames: tuple[int, int]

    @classmethod
    def read(cls, path: Path) -> ChunkStamp | None:
        data = read_json(path)
        try:
            return cls(data["blend"], data["engine"], int(data["samples"]), tuple(data["frames"]))
        except (KeyError, TypeError, ValueError):
            return None


def render_chunk(
    blend: Path, frames: tuple[int, int], chunks: Path, engine: str, samples: int, blender: str
) -> None:
    """Frames of the scene's .blend rendered by one Blender process into chunks/frames-FIRST-LAST.mp4."""
    first, last = frames
    what = f"{blend.stem} frames {first}-{last}"
    if not blend.is_file():
        raise TaskError(f"{what}: no scene {blend}; run the scene's build first")
    chunk = chunks / chunk_name(first, last)
    stamp_path = chunk.with_suffix(".json")
    wanted = ChunkStamp(file_digest(blend), engine.upper(), samples, frames)
    if ChunkStamp.read(stamp_path) == wanted and _holds_frames(chunk, last - first + 1):
        print(f"{what}: rendered already from this .blend ({chunk}); skipped", flush=True)
        return
    chunks.mkdir(parents=True, exist_ok=True)
    stamp_path.unlink(missing_ok=True)
    partial = chunks / f".{chunk.stem}.partial.mp4"
    started = time.perf_counter()
    try:
        partial.unlink(missing_ok=True)
        arguments = ["--head", str(blend), "--frames", f"{first}-{last}", "--engine", engine]
        arguments += ["--samples", str(samples), "--out", str(partial)]
        run_blender(blender_command(blender, RENDER_SCRIPT, arguments), what)
        count = video_frames(partial)
        if count != last - first + 1:
            raise TaskError(f"{what}: Blender wrote {count} frames, not {last - first + 1}; render it again")
        os.replace(partial, chunk)
    finally:
        partial.unlink(missing_ok=True)
    write_json(stamp_path, asdict(wanted) | {"frames": list(frames)})
    print(f"{what}: rendered in {time.perf_counter() - started:.1f} s to {chunk}", flush=True)


# ---------------------------------------------------------------- join


def tiling(chunks: dict[tuple[int, int], Path], frames: tuple[int, int]) -> list[Path] | None:
    """Chunks that cover the frames once each, in order (the longest first where several start alike)."""
    starts: dict[int, list[tuple[int, int]]] = {}
    for span in sorted(chunks, key=lambda span: -span[1]):
        starts.setdefault(span[0], []).append(span)

    def cover(frame: int) -> list[Path] | None:
        if frame == frames[1] + 1:
            return []
        for span in starts.get(frame, ()):
            if span[1] <= frames[1] and (rest := cover(span[1] + 1)) is not None:
                return [chunks[span], *rest]
        return None

    return cover(frames[0])


def uncovered(spans, frames: tuple[int, int]) -> str:
    """The frames no chunk holds, as ranges ("5-8, 12")."""
    held = {frame for first, last in spans for frame in range(first, last + 1)}
    missing = [frame for frame in range(frames[0], frames[1] + 1) if frame not in held]
    runs: list[list[int]] = []
    for frame in missing:
        if runs and frame == runs[-1][1] + 1:
            runs[-1][1] = frame
        else:
            runs.append([frame, frame])
    return ", ".join(f"{a}-{b}" if a != b else f"{a}" for a, b in runs)


def rendered_chunks(blend: Path, chunks: Path, engine: str, samples: int) -> tuple[dict, int]:
    """The chunks rendered from this .blend with these settings, by frames; and how many others lie there."""
    digest = file_digest(blend)
    found, others = {}, 0
    for path in sorted(chunks.glob("frames-*.mp4")) if chunks.is_dir() else ():
        match = CHUNK_NAME.match(path.name)
        if not match:
            continue
        span = int(match.group(1)), int(match.group(2))
        if ChunkStamp.read(path.with_suffix(".json")) == ChunkStamp(digest, engine.upper(), samples, span):
            found[span] = path
        else:
            others += 1
    return found, others


def join_scene(
    blend: Path,
    frames: tuple[int, int],
    chunks: Path,
    engine: str,
    samples: int,
    speech: Path | None,
    out: Path,
) -> None:
    """The scene's chunks joined in frame order with its speech into one MP4 (core/interchange/video.py)."""
    from ..interchange.video import join_videos

    what = blend.stem
    if not blend.is_file():
        raise TaskError(f"{what}: no scene {blend}; run the scene's build first")
    found, others = rendered_chunks(blend, chunks, engine, samples)
    ordered = tiling(found, frames)
    if ordered is None:
        missing, span = uncovered(found, frames), f"{frames[0]}-{frames[1]}"
        if not missing:
            raise TaskError(
                f"{what}: the chunks of frames {span} overlap without following each other: render the "
                "scene's chunks again with one chunk size"
            )
        raise TaskError(
            f"{what}: frames {missing} of {span} are not rendered from this .blend with {engine.upper()} and "
            f"{samples} samples: render them (the render step's tasks of those frames), then join again"
        )
    if others:
        print(
            f"{what}: left aside {others} chunks rendered from another .blend or with other settings",
            flush=True,
        )
    audio = speech if speech is not None and speech.is_file() else None
    if audio is None:
        built = read_json(blend.parent / BUILD_RECORD)
        if speech is not None and not (built and built.get("speech") is None):
            raise TaskError(f"{what}: no speech {speech}: build the scene again")
        print(f"{what}: warning: the scene has no speech: its video is silent", file=sys.stderr, flush=True)
    joined = join_videos(ordered, out, audio)
    seconds = f"{joined.frame_count} frames, {joined.seconds:.2f} s"
    print(f"{what}: joined {len(ordered)} chunks, {seconds}, to {out}", flush=True)
