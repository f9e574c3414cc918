"""Render set-up (camera, lights, engines, MP4 output) and a short Cycles render checked with PyAV."""

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
av = pytest.importorskip("av")
soundfile = pytest.importorskip("soundfile")

from mathutils import Vector  # noqa: E402

from turkish_lipsync.blender import compat, pipeline, render, sequencer  # noqa: E402


@pytest.fixture(autouse=True)
def empty_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps, scene.render.fps_base = 25, 1.0
    yield


def _face(name: str = "Face", z: float = 1.6) -> bpy.types.Object:
    """A small sphere facing -Y whose TR key moves only its front (the 'mouth')."""
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.1, location=(0.0, 0.0, z), segments=16, ring_count=8)
    face = bpy.context.active_object
    face.name = name
    face.shape_key_add(name="Basis")
    key = face.shape_key_add(name="TR_viseme_a")
    coordinates = np.array([tuple(v.co) for v in face.data.vertices])
    front = coordinates[:, 1] < -0.07
    coordinates[front, 2] -= 0.02
    key.points.foreach_set("co", coordinates.ravel())
    return face


def test_engine_identifiers_match_this_blender():
    scene = bpy.context.scene
    chosen = set()
    for engine in render.ENGINES:
        identifier = compat.engine_id(engine)
        scene.render.engine = identifier  # raises if this Blender has no such engine
        assert scene.render.engine == identifier and engine in identifier
        chosen.add(identifier)
    assert len(chosen) == len(render.ENGINES)


def test_auto_engine_is_cycles_in_background_without_probing():
    assert bpy.app.background
    assert render.choose_engine("auto", probe=False) == "CYCLES"
    assert render.choose_engine("workbench") == "WORKBENCH"
    with pytest.raises(render.RenderError, match="Unknown render engine"):
        render.choose_engine("povray")


def test_output_is_mp4_with_h264_and_aac(tmp_path):
    scene = bpy.context.scene
    render.configure_output(scene, tmp_path / "x.mp4", (321, 181))
    assert scene.render.image_settings.file_format == "FFMPEG"
    ffmpeg = scene.render.ffmpeg
    assert (ffmpeg.format, ffmpeg.codec, ffmpeg.audio_codec) == ("MPEG4", "H264", "AAC")
    assert (scene.render.resolution_x, scene.render.resolution_y) == (320, 180)  # H.264 needs even sizes


def test_camera_and_lights_frame_the_moving_part_of_the_face():
    face = _face()
    done = render.frame_face(bpy.context.scene, [face])
    assert done == {"camera": True, "lights": True}
    camera = bpy.context.scene.camera
    assert camera.name == render.CAMERA_NAME
    # In front of the face (-Y), level with the moving vertices, looking at them along +Y.
    low, high = render.face_bounds([face])
    assert camera.location.y < low[1]
    assert low[2] <= camera.location.z <= high[2]
    bpy.context.view_layer.update()
    forward = camera.matrix_world.to_quaternion() @ Vector((0, 0, -1))
    assert forward.y > 0.99
    lights = [o for o in bpy.context.scene.objects if o.type == "LIGHT"]
    assert sorted(o.name for o in lights) == sorted(render.LIGHT_NAMES)
    # Framing again re-aims ours and adds nothing.
    assert render.frame_face(bpy.context.scene, [face]) == {"camera": True, "lights": True}
    assert len([o for o in bpy.context.scene.objects if o.type in ("CAMERA", "LIGHT")]) == 4


def test_the_users_camera_and_lights_are_never_touched():
    face = _face()
    camera = bpy.data.objects.new("MyCamera", bpy.data.cameras.new("MyCamera"))
    camera.location = (5.0, -5.0, 2.0)
    bpy.context.scene.collection.objects.link(camera)
    bpy.context.scene.camera = camera
    sun = bpy.data.objects.new("MySun", bpy.data.lights.new("MySun", type="SUN"))
    bpy.context.scene.collection.objects.link(sun)
    assert render.frame_face(bpy.context.scene, [face]) == {"camera": False, "lights": False}
    assert tuple(camera.location) == (5.0, -5.0, 2.0)
    assert render.CAMERA_NAME not in bpy.data.objects
    assert not any(name in bpy.data.objects for name in render.LIGHT_NAMES)


def _stream_seconds(stream) -> float:
    return float(stream.duration * stream.time_base)


def test_short_cycles_render_has_video_and_audio_of_the_speech_length(tmp_path):
    scene = bpy.context.scene
    face = _face()
    speech_seconds = 0.44  # 11 frames at 25 fps
    rate = 22050
    t = np.arange(int(speech_seconds * rate)) / rate
    wav = tmp_path / "speech.wav"
    soundfile.write(str(wav), (0.3 * np.sin(2 * np.pi * 200 * t)).astype(np.float32), rate)
    sequencer.place_speech_strip(scene, wav, 1, speech_seconds)
    frame_count = round(speech_seconds * 25)
    scene.frame_start, scene.frame_end = 1, frame_count

    result = pipeline.render_video(
        bpy.context, face, str(tmp_path / "out.mp4"), engine="CYCLES", samples=1, resolution=(48, 32)
    )
    assert result.engine == "CYCLES" and result.frame_count == frame_count

    with av.open(str(tmp_path / "out.mp4")) as container:
        video = container.streams.video[0]
        audio = container.streams.audio[0]
        assert video.codec_context.name == "h264"
        assert audio.codec_context.name == "aac"
        assert (video.codec_context.width, video.codec_context.height) == (48, 32)
        frames = sum(1 for _ in container.decode(video=0))
        seconds = _stream_seconds(video), _stream_seconds(audio)  # read while the file is open (PyAV 18.1)
    one_frame = 1 / 25
    assert frames == frame_count
    assert abs(seconds[0] - speech_seconds) <= one_frame
    assert abs(seconds[1] - speech_seconds) <= one_frame


def test_a_still_goes_to_png_and_the_video_settings_stay(tmp_path):
    scene = bpy.context.scene
    face = _face()
    render.configure_output(scene, tmp_path / "video.mp4", (48, 32))
    still = str(tmp_path / "still.png")
    path = pipeline.render_still(bpy.context, face, still, frame=1, engine="CYCLES", samples=1)
    assert path.endswith("still.png")
    assert (tmp_path / "still.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert scene.render.image_settings.file_format == "FFMPEG"
    assert scene.render.filepath.endswith("video.mp4")


def test_a_head_looking_along_plus_y_is_filmed_from_the_front():
    """A VRM avatar looks along +Y after import: the camera goes in front of its face, not behind its head."""
    from turkish_lipsync.blender import heads, pipeline

    parts = heads.create_reference_head(bpy.context)
    head = parts["head"]
    for obj in parts.values():
        if obj.parent is None:
            obj.rotation_euler.z = math.pi  # the whole head turned to look along +Y
    bpy.context.view_layer.update()
    pipeline.frame_head(bpy.context.scene, head)
    camera = bpy.context.scene.camera
    low, high = render.face_bounds(pipeline.head_objects(head))
    assert camera.location.y > high[1]
    bpy.context.view_layer.update()
    forward = camera.matrix_world.to_quaternion() @ Vector((0, 0, -1))
    assert forward.y < -0.99
