"""The speech WAV as one TR_speech strip; the frame range follows the speech."""

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
soundfile = pytest.importorskip("soundfile")

from turkish_lipsync.blender import compat, sequencer  # noqa: E402
from turkish_lipsync.core.base.errors import AudioError  # noqa: E402

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
    wav = _wav(tmp_path / "speech.wav", 1.5)
    sequencer.place_speech_strip(scene, wav, 5, 1.5)
    assert scene.frame_start == 5
    # 1.5 s * 29.97 fps = 44.96, the nearest whole count is 45 frames: 5..49.
    assert scene.frame_end == 49
    assert sequencer.speech_wav_of(scene) == wav


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
    assert (scene.frame_start, scene.frame_end) == (11, 35)


def test_wav_goes_next_to_the_saved_blend_or_to_the_chosen_folder(tmp_path):
    unsaved = sequencer.speech_wav_path("TR_merhaba benim adım erdem")
    assert unsaved.parent.is_dir()
    assert unsaved.name == "TR_merhaba_benim_adım_erdem.wav"

    blend = tmp_path / "scene.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    assert sequencer.speech_wav_path("TR_a").parent == tmp_path / sequencer.SPEECH_FOLDER_NAME
    chosen = tmp_path / "chosen"
    assert sequencer.speech_wav_path("TR_a", str(chosen)) == chosen / "TR_a.wav"
