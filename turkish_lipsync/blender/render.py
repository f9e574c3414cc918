"""Scene set-up for a talking-head render: camera and three-point lights on the face, engine, MP4 output."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import bpy
import numpy as np
from mathutils import Vector

from ..core.base.errors import LipSyncError
from ..core.base.model import EMOTION_KEY_PREFIX, VISEME_KEY_PREFIX
from ..core.interchange.video import join_videos
from . import compat, mesh
from .owned_keys import owned_keys

ENGINES = ("EEVEE", "CYCLES", "WORKBENCH")
CAMERA_NAME = "TR_camera"
LIGHT_NAMES = ("TR_key_light", "TR_fill_light", "TR_rim_light")
WORLD_NAME = "TR_world"
CAMERA_LENS_MM = 70.0
# Margins around the moving part of the face (brows to chin), as fractions of its height: room above for
# the top of the head, below for the start of the neck, at the sides for the ears.
FACE_MARGIN_ABOVE = 0.27
FACE_MARGIN_BELOW = 0.06
FACE_MARGIN_SIDES = 0.1
GROUP_MARGIN = 0.15  # room around a group of heads, as a share of their height
PROBE_ENVIRONMENT_VARIABLE = "TURKISH_LIPSYNC_PROBE_OPENGL"


class RenderError(LipSyncError):
    """A render that cannot be set up or written."""


# ---------------------------------------------------------------- engine choice


def _probe_opengl_in_subprocess(timeout_seconds: float = 180.0) -> bool:
    """Render one tiny EEVEE frame in a child process: a missing EGL driver aborts the child, not us."""
    engine = compat.engine_id("EEVEE")
    code = (
        "import bpy, sys\n"
        "scene = bpy.context.scene\n"
        f"scene.render.engine = {engine!r}\n"
        "scene.render.resolution_x = scene.render.resolution_y = 8\n"
        "bpy.ops.render.render()\n"
        "sys.exit(0)\n"
    )
    if (
        bpy.app.binary_path
        and not bpy.app.binary_path.endswith(("python", "python3"))
        and os.path.isfile(bpy.app.binary_path)
    ):
        command = [bpy.app.binary_path, "-b", "--factory-startup", "--python-expr", code]
    else:
        command = [sys.executable, "-c", code]
    try:
        result = subprocess.run(command, capture_output=True, timeout=timeout_seconds, check=False)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return result.returncode == 0


def opengl_available(probe: bool | None = None) -> bool:
    """Whether EEVEE can render here.

    With a user interface there is always a GL context. In background mode there may be none (and Mesa's
    software EGL takes a minute to compile EEVEE's shaders), so assume none unless probing is asked for,
    by the argument or by setting TURKISH_LIPSYNC_PROBE_OPENGL=1.
    """
    if not bpy.app.background:
        return True
    if probe is None:
        probe = os.environ.get(PROBE_ENVIRONMENT_VARIABLE, "") not in ("", "0")
    return _probe_opengl_in_subprocess() if probe else False


def choose_engine(requested: str, probe: bool | None = None) -> str:
    """EEVEE, CYCLES or WORKBENCH; 'AUTO' picks EEVEE where an OpenGL context exists, Cycles otherwise."""
    requested = requested.upper()
    if requested == "AUTO":
        return "EEVEE" if opengl_available(probe) else "CYCLES"
    if requested not in ENGINES:
        raise RenderError(f"Unknown render engine {requested!r}; use auto, EEVEE, CYCLES or WORKBENCH.")
    return requested


def cycles_has_denoiser() -> bool:
    try:
        import _cycles  # Blender's own module, present wherever Cycles is

        return bool(getattr(_cycles, "with_openimagedenoise", False))
    except ImportError:
        return False


def configure_engine(scene: bpy.types.Scene, engine: str, samples: int | None = None) -> None:
    """Select the engine with settings fit for a face close-up on a CPU."""
    scene.render.engine = compat.engine_id(engine)
    if engine == "CYCLES":
        cycles = scene.cycles
        cycles.device = "CPU"
        cycles.samples = samples or 16
        cycles.use_adaptive_sampling = True
        cycles.max_bounces = 4
        # Keep the scene between frames: only the shape keys change, the BVH and shaders need no rebuild.
        scene.render.use_persistent_data = True
        # OpenImageDenoise triples the time of a 16-sample frame on two cores; at these sample counts
        # the skin is clean enough without it, so it is only used when many samples are asked for anyway.
        denoise = cycles_has_denoiser() and (samples or 16) >= 64
        cycles.use_denoising = denoise
        if denoise:
            cycles.denoiser = "OPENIMAGEDENOISE"
    elif engine == "EEVEE":
        scene.eevee.taa_render_samples = samples or 16
    else:
        shading = scene.display.shading
        shading.light = "STUDIO"
        shading.color_type = "MATERIAL"
        scene.display.render_aa = "8" if samples is None or samples >= 8 else "OFF"


# ---------------------------------------------------------------- undoing a set-up


_VALUE_TYPES = {"BOOLEAN", "INT", "FLOAT", "STRING", "ENUM"}


def _values_of(struct) -> dict[str, object]:
    """The writable plain values of an RNA struct (arrays as tuples)."""
    values = {}
    for prop in struct.bl_rna.properties:
        if prop.is_readonly or prop.type not in _VALUE_TYPES or prop.identifier == "rna_type":
            continue
        value = getattr(struct, prop.identifier)
        values[prop.identifier] = tuple(value) if getattr(prop, "is_array", False) else value
    return values


def _set_values(struct, values: dict[str, object]) -> None:
    for name, value in values.items():
        if getattr(struct, name) == value:
            continue
        try:
            setattr(struct, name, value)
        except (AttributeError, TypeError, ValueError):
            pass  # values another setting now rules out (an enum item of another engine)


def _render_structs(scene: bpy.types.Scene) -> dict[str, object]:
    structs = {
        "render": scene.render,
        "image_settings": scene.render.image_settings,
        "ffmpeg": scene.render.ffmpeg,
        "eevee": scene.eevee,
        "display": scene.display,
        "shading": scene.display.shading,
    }
    if hasattr(scene, "cycles"):
        structs["cycles"] = scene.cycles
    return structs


@dataclass(frozen=True, eq=False)
class SceneSettings:
    """What preparing a render changes in a scene, to put back when the render is cancelled."""

    values: dict[str, dict[str, object]]
    camera: str | None
    world: str | None
    objects: frozenset[str]

    @classmethod
    def of(cls, scene: bpy.types.Scene) -> SceneSettings:
        return cls(
            values={name: _values_of(struct) for name, struct in _render_structs(scene).items()},
            camera=scene.camera.name if scene.camera else None,
            world=scene.world.name if scene.world else None,
            objects=frozenset(obj.name for obj in bpy.data.objects),
        )

    def restore(self, scene: bpy.types.Scene) -> None:
        # Image settings first: the output format decides which other values are allowed.
        structs = _render_structs(scene)
        for name in ("image_settings", *structs):
            _set_values(structs[name], self.values.get(name, {}))
        scene.camera = bpy.data.objects.get(self.camera) if self.camera else None
        scene.world = bpy.data.worlds.get(self.world) if self.world else None
        for name in (*LIGHT_NAMES, CAMERA_NAME):
            obj = bpy.data.objects.get(name)
            if obj is not None and name not in self.objects:
                data = obj.data
                bpy.data.objects.remove(obj, do_unlink=True)
                if data is not None and data.users == 0:
                    (bpy.data.cameras if name == CAMERA_NAME else bpy.data.lights).remove(data)
        world = bpy.data.worlds.get(WORLD_NAME)
        if world is not None and world.users == 0 and self.world != WORLD_NAME:
            bpy.data.worlds.remove(world)


# ---------------------------------------------------------------- output


def configure_output(
    scene: bpy.types.Scene, out_path: str | os.PathLike, resolution: tuple[int, int] | None = None
) -> None:
    """MP4 with H.264 video and AAC audio (H.264 needs even frame sizes)."""
    render = scene.render
    if resolution is not None:
        width, height = resolution
        render.resolution_x = max(2, int(width) // 2 * 2)
        render.resolution_y = max(2, int(height) // 2 * 2)
    render.resolution_percentage = 100
    compat.set_video_output(render.image_settings)
    ffmpeg = render.ffmpeg
    ffmpeg.format = "MPEG4"
    ffmpeg.codec = "H264"
    ffmpeg.constant_rate_factor = "MEDIUM"
    ffmpeg.ffmpeg_preset = "GOOD"
    ffmpeg.gopsize = max(1, round(render.fps / render.fps_base))
    ffmpeg.audio_codec = "AAC"
    ffmpeg.audio_channels = "MONO"
    ffmpeg.audio_mixrate = 48000
    ffmpeg.audio_bitrate = 128
    render.use_file_extension = False
    render.filepath = os.fspath(Path(out_path).resolve())


def mux_audio(video_path: Path, wav_path: Path) -> None:
    """Add the speech as AAC to a silent MP4 (for Blender builds without audio: the bpy module 4.2): the
    video is copied, as a farm's chunks are joined."""
    silent = video_path.with_name(video_path.stem + ".silent" + video_path.suffix)
    os.replace(video_path, silent)
    try:
        join_videos([silent], video_path, wav_path, whole_speech=False)  # the range rendered, its sound
    except Exception:
        os.replace(silent, video_path)
        raise
    silent.unlink()


# ---------------------------------------------------------------- camera and lights


def face_points(objects) -> np.ndarray:
    """World points of the face: the vertices our viseme and emotion keys move, else the whole mesh."""
    moving_points = []
    all_points = []
    for obj in objects:
        if obj is None or obj.type != "MESH" or not len(obj.data.vertices):
            continue
        count = len(obj.data.vertices)
        rest = mesh.read_coordinates(obj.data.vertices, count)
        all_points.append(mesh.to_world(obj, rest))
        key = obj.data.shape_keys
        if key is None:
            continue
        names = [
            name
            for ours, name in owned_keys(obj).items()
            if ours.startswith((VISEME_KEY_PREFIX, EMOTION_KEY_PREFIX))
        ]
        if not names:
            continue
        shapes = np.empty((len(names), count * 3), np.float32)
        for row, name in zip(shapes, names, strict=True):
            key.key_blocks[name].points.foreach_get("co", row)
        moves = np.square(shapes.reshape(len(names), count, 3) - rest).sum(axis=2)  # squared, per key
        # Recipes smear tiny motion over the whole head; the face is where a key really moves (a tenth of
        # its largest displacement).
        moved = (moves > np.maximum(1e-12, 0.01 * moves.max(axis=1, initial=0.0))[:, None]).any(axis=0)
        if moved.any():
            moving_points.append(mesh.to_world(obj, rest[moved]))
    points = moving_points or all_points
    if not points:
        raise RenderError("No head mesh to frame: choose a head object with vertices in the Lip Sync panel.")
    return np.concatenate(points)


def whole_points(objects) -> np.ndarray:
    """World points of every vertex of the objects (the heads of a group, whole)."""
    points = [
        mesh.to_world(obj, mesh.read_coordinates(obj.data.vertices, len(obj.data.vertices)))
        for obj in objects
        if obj is not None and obj.type == "MESH" and len(obj.data.vertices)
    ]
    if not points:
        raise RenderError("No head mesh to frame: the conversation's heads have no vertices.")
    return np.concatenate(points)


def face_bounds(objects) -> tuple[np.ndarray, np.ndarray]:
    """World-space box of the face (face_points)."""
    stacked = face_points(objects)
    return stacked.min(axis=0), stacked.max(axis=0)


def _look_at(obj: bpy.types.Object, target: Vector) -> None:
    obj.rotation_euler = (target - obj.location).to_track_quat("-Z", "Y").to_euler()


def _link(scene: bpy.types.Scene, obj: bpy.types.Object) -> None:
    if obj.name not in scene.collection.objects:
        scene.collection.objects.link(obj)


def _ensure_object(scene: bpy.types.Scene, name: str, data) -> bpy.types.Object:
    obj = bpy.data.objects.get(name)
    if obj is None:
        obj = bpy.data.objects.new(name, data)
    _link(scene, obj)
    return obj


# The frame of a face looking along -Y with Z up: columns are the character's left, up and forward.
FACING_MINUS_Y = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


def camera_placement(
    scene: bpy.types.Scene, head_objects, facing: np.ndarray | None = None, group: bool = False
) -> tuple[Vector, float, float, float]:
    """(centre of the framed head, camera distance, sensor width, framed size) of the camera frame_face
    adds, in front of the face. facing: the head's frame (columns: its left, up and forward in world axes);
    a face looking along -Y where it is not given. group: several heads (a conversation), framed whole
    with a little room around them, since each turns toward the others."""
    facing = FACING_MINUS_Y if facing is None else np.asarray(facing, np.float64)
    if group:
        local = whole_points(head_objects) @ facing
        low, high = local.min(axis=0), local.max(axis=0)
        room = GROUP_MARGIN * float(high[1] - low[1])
        low, high = low - np.array([room, room, 0.0]), high + np.array([room, room, 0.0])
    else:
        local = face_points(head_objects) @ facing  # across, up, forward
        low, high = local.min(axis=0), local.max(axis=0)
        face_height = float(high[1] - low[1])
        # The whole head from its crown to the top of the neck.
        low = low - face_height * np.array([FACE_MARGIN_SIDES, FACE_MARGIN_BELOW, 0.0])
        high = high + face_height * np.array([FACE_MARGIN_SIDES, FACE_MARGIN_ABOVE, 0.0])
    width, height, depth = (high - low).tolist()
    centre = Vector((facing @ ((low + high) / 2)).tolist())
    aspect = (
        scene.render.resolution_x
        * scene.render.pixel_aspect_x
        / max(1.0, scene.render.resolution_y * scene.render.pixel_aspect_y)
    )
    sensor = 36.0
    half_wide = math.atan(sensor / 2 / CAMERA_LENS_MM)  # across the longer side of the frame
    half_horizontal = half_wide if aspect >= 1 else math.atan(math.tan(half_wide) * aspect)
    half_vertical = math.atan(math.tan(half_wide) / aspect) if aspect >= 1 else half_wide
    distance = max(width / 2 / math.tan(half_horizontal), height / 2 / math.tan(half_vertical)) + depth / 2
    return centre, max(distance, 1e-3), sensor, max(width, height)


def frame_face(
    scene: bpy.types.Scene, head_objects, facing: np.ndarray | None = None, group: bool = False
) -> dict[str, bool]:
    """Add a camera and three-point lights in front of the face where the scene has none; re-aim ours.

    facing and group as for camera_placement (a VRM avatar looks along +Y, others along X). The user's own
    camera and lights are never moved. Returns which were added or re-aimed.
    """
    facing = FACING_MINUS_Y if facing is None else np.asarray(facing, np.float64)
    centre, distance, sensor, size = camera_placement(scene, head_objects, facing, group)
    done = {"camera": False, "lights": False}

    camera = scene.camera
    if camera is None or camera.name == CAMERA_NAME:
        camera_data = bpy.data.cameras.get(CAMERA_NAME) or bpy.data.cameras.new(CAMERA_NAME)
        camera = _ensure_object(scene, CAMERA_NAME, camera_data)
        camera.data.lens = CAMERA_LENS_MM
        camera.data.sensor_width = sensor
        camera.data.sensor_fit = "AUTO"
        camera.data.clip_start = distance / 100
        camera.data.clip_end = distance * 100
        camera.location = centre + Vector((facing[:, 2] * distance).tolist())
        _look_at(camera, centre)
        scene.camera = camera
        done["camera"] = True

    has_user_lights = any(o.type == "LIGHT" and o.name not in LIGHT_NAMES for o in scene.objects)
    if not has_user_lights:
        # (name, direction from the face as the character's left, up and forward, power relative to the key)
        placement = (
            (LIGHT_NAMES[0], (-0.7, 0.6, 1.0), 1.0),
            (LIGHT_NAMES[1], (0.9, 0.1, 0.8), 0.35),
            (LIGHT_NAMES[2], (0.4, 0.8, -1.0), 0.8),
        )
        for name, local, power in placement:
            direction = Vector((facing @ np.array(local)).tolist())
            light_data = bpy.data.lights.get(name) or bpy.data.lights.new(name, type="AREA")
            light_data.size = size * 1.2
            # Area light power falls with the square of the distance: scale it with the framing.
            light_data.energy = 15.0 * power * distance**2
            light = _ensure_object(scene, name, light_data)
            light.location = centre + direction.normalized() * distance * 1.1
            _look_at(light, centre)
        done["lights"] = True

    if scene.world is None:
        world = bpy.data.worlds.get(WORLD_NAME) or bpy.data.worlds.new(WORLD_NAME)
        world.color = (0.05, 0.05, 0.06)
        scene.world = world
    return done
