"""Farm rendering: a saved scene rendered in three chunks and joined gives the frames and samples of one."""

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
av = pytest.importorskip("av")
from tests.render_runs import decoded_media, run_render  # noqa: E402

CHUNKS = ((1, 3), (4, 6), (7, None))  # None: the scene's last frame


def _rendered(*arguments: str):
    result = run_render(*arguments)
    assert result.returncode == 0, result.stderr[-2000:]
    return result


@pytest.fixture(scope="module")
def renders(tmp_path_factory):
    folder = tmp_path_factory.mktemp("farm")
    blend = folder / "scene.blend"
    _rendered(
        "--text",
        "Ama baba",
        "--no-render",
        "--save-blend",
        str(blend),
        "--resolution",
        "32x32",
        "--fps",
        "25",
    )
    wav = next((folder / "lipsync_audio").glob("*.wav"))
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    last = bpy.context.scene.frame_end
    common = ("--head", str(blend), "--engine", "cycles", "--samples", "1")
    _rendered(*common, "--frames", f"1-{last}", "--out", str(folder / "whole.mp4"))
    chunks = []
    for first, end in CHUNKS:
        chunks.append(folder / f"chunk-{first}.mp4")
        _rendered(*common, "--frames", f"{first}-{end or last}", "--out", str(chunks[-1]))
    # the join needs no Blender: it runs as a plain script
    _rendered("--join", str(folder / "whole.mp4"), "--audio", str(wav), "--out", str(folder / "one.mp4"))
    joined = _rendered("--join", *map(str, chunks), "--audio", str(wav), "--out", str(folder / "three.mp4"))
    return folder, last, chunks, joined.stdout


def test_three_chunks_and_a_join_give_the_frames_and_samples_of_one_render(renders):
    folder, last, _, _ = renders
    frames_one, audio_one = decoded_media(folder / "one.mp4")
    frames_three, audio_three = decoded_media(folder / "three.mp4")
    assert len(frames_one) == len(frames_three) == last
    for frame, (whole, joined) in enumerate(zip(frames_one, frames_three, strict=True), start=1):
        np.testing.assert_array_equal(whole, joined, err_msg=f"frame {frame}")
    # the mouth moves: the frames are not all the same picture
    assert any(not np.array_equal(frames_one[0], frame) for frame in frames_one[1:])
    np.testing.assert_array_equal(audio_one, audio_three)
    assert np.abs(audio_three).max() > 0.05  # the speech, not silence


def test_chunks_are_silent_lossless_and_the_join_lasts_as_long_as_the_scene(renders):
    folder, last, chunks, stdout = renders
    for chunk in chunks:
        with av.open(str(chunk)) as container:
            assert not container.streams.audio and len(container.streams.video) == 1
    with av.open(str(folder / "three.mp4")) as container:
        video, audio = container.streams.video[0], container.streams.audio[0]
        assert (video.codec_context.name, audio.codec_context.name) == ("h264", "aac")
        assert abs(float(video.duration * video.time_base) - last / 25) < 1e-3
    assert f"(3, 3, {last - 6} frames)" in stdout


def test_a_range_outside_the_scene_is_refused(renders):
    folder, last, _, _ = renders
    scene = str(folder / "scene.blend")
    result = run_render(
        "--head", scene, "--engine", "cycles", "--frames", f"{last}-{last + 5}", "--out", folder / "bad.mp4"
    )
    assert result.returncode == 1 and "not inside the scene's frames" in result.stderr
    assert not (folder / "bad.mp4").exists()


def test_a_chunk_can_be_a_folder_of_png_frames(renders):
    folder, _, _, _ = renders
    scene = str(folder / "scene.blend")
    _rendered(
        "--head",
        scene,
        "--engine",
        "cycles",
        "--samples",
        "1",
        "--frames",
        "2-3",
        "--out",
        str(folder / "frames"),
    )
    assert sorted(path.name for path in (folder / "frames").iterdir()) == ["000002.png", "000003.png"]
