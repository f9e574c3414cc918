"""The speech WAV as one TR_speech strip; the frame range follows the speech."""

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
soundfile = pytest.importorskip("soundfile")

from turkish_lipsync.blender import compat, sequencer  # noqa: E402
from turkish_lipsync.core.base.errors import AudioError  # noqa: E402
from turkish_lipsync.core.motion.frames import shown_frame_count  # noqa: E402
from turkish_lipsync.core.speech.base import Synthesis  # noqa: E402

needs_audio = pytest.mark.skipif(
    not compat.HAS_AUDIO, reason="this bpy build has no Audaspace: sound strips cannot exist (PyPI bpy 4.2)"
)


@pytest.fixture(autouse=True)
def empty_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    yield


def _wav(path, seconds: float, rate: int = 22050):
    samples = (0.2 * np.sin(2 * np.pi * 220 * np.arange(int(seconds * rate)) / rate)).astype(np.float32)
    soundfile.write(str(path), samples, rate)
    return path


def test_frame_range_covers_the_speech_at_a_fractional_rate(tmp_path):
    scene = bpy.context.scene
    scene.render.fps, scene.render.fps_base = 30, 1.001
    scene.frame_start, scene.frame_end = sequencer.BLENDER_DEFAULT_RANGE
    wav = _wav(tmp_path / "speech.wav", 1.5)
    sequencer.place_speech_strip(scene, wav, 5, 1.5)
    # 1.5 s * 29.97 fps = 44.96, the nearest whole count is 45 frames: 5..49.
    frame_count = shown_frame_count(1.5, sequencer.scene_fps(scene))
    assert frame_count == 45
    assert sequencer.fit_frame_range(scene, 5, frame_count) == ()
    assert (scene.frame_start, scene.frame_end) == (5, 49)
    assert sequencer.speech_wav_of(scene) == wav


def test_a_frame_range_of_the_users_own_is_kept_or_extended_with_a_warning():
    scene = bpy.context.scene
    scene.pop(sequencer.FRAME_RANGE_PROPERTY, None)
    scene.frame_start, scene.frame_end = 10, 500  # a shot of the user's, the speech inside it
    assert sequencer.fit_frame_range(scene, 10, 16) == ()
    assert (scene.frame_start, scene.frame_end) == (10, 500)
    scene.pop(sequencer.FRAME_RANGE_PROPERTY, None)
    scene.frame_start, scene.frame_end = 10, 20  # too short for the speech
    (warning,) = sequencer.fit_frame_range(scene, 10, 16)
    assert (scene.frame_start, scene.frame_end) == (10, 25) and "frames 10-20 did not hold" in warning
    # a range Generate set is Generate's to change again, silently
    assert sequencer.fit_frame_range(scene, 10, 8) == ()
    assert (scene.frame_start, scene.frame_end) == (10, 17)


def test_missing_wav_is_an_error_that_changes_nothing(tmp_path):
    scene = bpy.context.scene
    scene.frame_end = 77
    with pytest.raises(AudioError, match="does not exist"):
        sequencer.place_speech_strip(scene, tmp_path / "nothing.wav", 1, 2.0)
    assert scene.frame_end == 77
    strips = compat.sequencer_strips(scene, create=False)
    assert strips is None or len(strips) == 0


@needs_audio
def test_regenerating_replaces_the_strip_and_keeps_other_strips(tmp_path):
    scene = bpy.context.scene
    scene.render.fps, scene.render.fps_base = 25, 1.0
    music = _wav(tmp_path / "music.wav", 4.0)
    strips = compat.sequencer_strips(scene)
    strips.new_sound("Music", str(music), 1, 1)

    first = _wav(tmp_path / "first.wav", 2.0)
    second = _wav(tmp_path / "second.wav", 1.0)
    sequencer.place_speech_strip(scene, first, 1, 2.0)
    sequencer.place_speech_strip(scene, second, 11, 1.0)

    strips = compat.sequencer_strips(scene)
    speech = [s for s in strips if s.name.startswith(sequencer.SPEECH_STRIP_NAME)]
    assert len(speech) == 1
    assert speech[0].frame_start == 11
    assert speech[0].frame_final_duration == 25
    assert speech[0].channel != strips["Music"].channel
    assert sequencer.speech_wav_of(scene) == second
    assert "Music" in strips


def _synthesis(seconds: float, frequency: float = 200.0):
    rate = 22050
    t = np.arange(int(seconds * rate)) / rate
    samples = (8000 * np.sin(2 * np.pi * frequency * t)).astype(np.int16)
    return Synthesis(samples, rate, (), (), "test")


def test_wav_goes_next_to_the_saved_blend_or_to_the_chosen_folder(tmp_path):
    speech = _synthesis(0.5)
    unsaved = sequencer.write_speech_wav("TR_merhaba benim adım erdem", speech)
    assert unsaved.is_file() and unsaved.name.startswith("TR_merhaba_benim_adım_erdem-")

    blend = tmp_path / "scene.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    assert sequencer.write_speech_wav("TR_a", speech).parent == tmp_path / sequencer.SPEECH_FOLDER_NAME
    chosen = tmp_path / "chosen"
    assert sequencer.write_speech_wav("TR_a", speech, str(chosen)).parent == chosen


def test_two_speeches_of_one_name_never_share_a_wav_and_a_foreign_wav_is_kept(tmp_path):
    """Two scenes saved in one folder speak the same text at two rates: two WAVs, each scene's its own.
    A file of ours by name but not written by us (a user's) is left as it was."""
    first = sequencer.write_speech_wav("TR_merhaba", _synthesis(1.0), str(tmp_path))
    second = sequencer.write_speech_wav("TR_merhaba", _synthesis(1.4), str(tmp_path))
    assert first != second and first.is_file() and second.is_file()
    assert sequencer.write_speech_wav("TR_merhaba", _synthesis(1.0), str(tmp_path)) == first  # reused
    first.write_bytes(b"not ours")  # the user puts a file of their own under that name
    third = sequencer.write_speech_wav("TR_merhaba", _synthesis(1.0), str(tmp_path))
    assert third != first and first.read_bytes() == b"not ours"
    assert soundfile.read(str(third))[0].size == 22050
