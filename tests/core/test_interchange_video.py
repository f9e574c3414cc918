"""Joining video chunks with the speech: frames copied, not re-encoded; the audio once over the whole."""

import numpy as np
import pytest

from turkish_lipsync.core.interchange.video import VideoError, join_videos

av = pytest.importorskip("av")
soundfile = pytest.importorskip("soundfile")
from tests.render_runs import decoded_media  # noqa: E402

FPS = 25
SIZE = 32


def _picture(index: int) -> np.ndarray:
    """A frame that differs from every other: a moving bar on a gradient."""
    y, x = np.mgrid[0:SIZE, 0:SIZE]
    image = np.stack([(x * 8) % 256, (y * 8) % 256, np.full_like(x, index * 9 % 256)], axis=-1)
    image[:, index % SIZE] = 255
    return image.astype(np.uint8)


def _encode(path, frames, *, size=SIZE):
    with av.open(str(path), "w", format="mp4") as out:
        stream = out.add_stream("libx264", rate=FPS, options={"qp": "0", "bf": "0", "threads": "1"})
        stream.width = stream.height = size
        stream.pix_fmt = "yuv420p"
        for index in frames:
            picture = _picture(index) if size == SIZE else np.zeros((size, size, 3), np.uint8)
            for packet in stream.encode(av.VideoFrame.from_ndarray(picture, format="rgb24")):
                out.mux(packet)
        for packet in stream.encode(None):
            out.mux(packet)


@pytest.fixture()
def speech(tmp_path):
    seconds = 30 / FPS
    t = np.arange(int(seconds * 16000)) / 16000
    path = tmp_path / "speech.wav"
    soundfile.write(
        path, (0.3 * np.sin(2 * np.pi * 220 * t) * np.minimum(1, t * 4)).astype(np.float32), 16000
    )
    return path


def test_three_chunks_join_into_the_same_frames_and_samples_as_one(tmp_path, speech):
    _encode(tmp_path / "whole.mp4", range(30))
    chunks = []
    for number, frames in enumerate((range(0, 11), range(11, 20), range(20, 30))):
        chunks.append(tmp_path / f"chunk{number}.mp4")
        _encode(chunks[-1], frames)
    one = join_videos([tmp_path / "whole.mp4"], tmp_path / "one.mp4", speech)
    three = join_videos(chunks, tmp_path / "three.mp4", speech)
    assert one.frame_count == three.frame_count == 30 and three.chunk_frames == (11, 9, 10)
    frames_one, audio_one = decoded_media(one.path)
    frames_three, audio_three = decoded_media(three.path)
    assert len(frames_one) == len(frames_three) == 30
    for a, b in zip(frames_one, frames_three, strict=True):
        np.testing.assert_array_equal(a, b)
    assert not np.array_equal(frames_three[10], frames_three[11])
    np.testing.assert_array_equal(audio_one, audio_three)
    # the audio is the speech, as long as the video
    with av.open(str(three.path)) as container:
        video, audio = container.streams.video[0], container.streams.audio[0]
        assert (
            abs(float(audio.duration * audio.time_base) - float(video.duration * video.time_base)) < 1 / FPS
        )
    assert abs(audio_three.shape[1] / 48000 - 30 / FPS) < 0.05
    spectrum = np.abs(np.fft.rfft(audio_three[0]))
    assert abs(np.argmax(spectrum) * 48000 / audio_three.shape[1] - 220) < 5  # the speech's 220 Hz tone


def test_the_video_is_copied_not_re_encoded(tmp_path):
    chunks = [tmp_path / "a.mp4", tmp_path / "b.mp4"]
    _encode(chunks[0], range(0, 5))
    _encode(chunks[1], range(5, 12))
    joined = join_videos(chunks, tmp_path / "joined.mp4")

    def packets(path):
        with av.open(str(path)) as container:
            return [bytes(p) for p in container.demux(container.streams.video[0]) if p.size]

    assert packets(joined.path) == packets(chunks[0]) + packets(chunks[1])


def test_chunks_of_another_size_are_refused(tmp_path):
    _encode(tmp_path / "a.mp4", range(3))
    _encode(tmp_path / "b.mp4", range(3), size=48)
    with pytest.raises(VideoError, match="encoded differently"):
        join_videos([tmp_path / "a.mp4", tmp_path / "b.mp4"], tmp_path / "out.mp4")
    assert not (tmp_path / "out.mp4").exists() and not (tmp_path / "out.joining.mp4").exists()


def test_a_missing_chunk_is_named(tmp_path):
    with pytest.raises(VideoError, match="missing.mp4"):
        join_videos([tmp_path / "missing.mp4"], tmp_path / "out.mp4")


def test_chunks_that_do_not_cover_the_speech_are_refused(tmp_path, speech):
    """The speech lasts 30 frames; a join of chunks 1-10 and 21-30 (the middle one missing) would cut it."""
    _encode(tmp_path / "a.mp4", range(10))
    _encode(tmp_path / "c.mp4", range(20, 30))
    with pytest.raises(VideoError, match=r"chunks hold 20 frames .* lasts 1.20 s: a chunk .* is missing"):
        join_videos([tmp_path / "a.mp4", tmp_path / "c.mp4"], tmp_path / "out.mp4", speech)
    assert not (tmp_path / "out.mp4").exists()
