"""Recordings as they arrive, in Blender: Blender's own FFmpeg (aud) reads MP4, M4A, MOV, MKV and WebM for
the core once the add-on registers, with their timing and length kept; the panel's recording fields browse
only what can be read; the panel, a conversation and render.py follow an encoded take as its WAV.

The PyPI bpy 4.2 module has no audio at all: there PyAV reads them (what a real Blender 4.2 does with aud
is what 4.5 and 5.0 do here).
"""

import re
import subprocess
import sys

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
pytest.importorskip("av")  # the takes are encoded with PyAV

from lab.kit.encoded_takes import (  # noqa: E402
    ENCODINGS,
    TAKE_TEXT,
    encode,
    lag_seconds,
    write_takes,
)
from tests.core.test_speech_decoders import AAC_FRAME, ONSET_TOLERANCE, WAV_RATE, onset_differences  # noqa: E402
from tests.core.test_speech_recording import write_pcm_wav  # noqa: E402
from tests.render_runs import RENDER_SCRIPT, run_render  # noqa: E402
from turkish_lipsync import blender  # noqa: E402
from turkish_lipsync.blender import compat, heads, pipeline, recording_browser, sequencer, shapekeys  # noqa: E402
from turkish_lipsync.blender.audio_decoding import BlenderAudioDecoder  # noqa: E402
from turkish_lipsync.core.pipeline import LipSyncOptions  # noqa: E402
from turkish_lipsync.core.scene import cast_for, converse, scene_speech  # noqa: E402
from turkish_lipsync.core.scene.speech import SceneSources  # noqa: E402
from turkish_lipsync.core.speech.audio import decode_audio  # noqa: E402
from turkish_lipsync.core.speech.decoders import DECODERS, sniff_format  # noqa: E402
from turkish_lipsync.core.text.script import read_script  # noqa: E402

pytestmark = pytest.mark.usefixtures("registered_extension")

FPS = 25
needs_blenders_ffmpeg = pytest.mark.skipif(
    not compat.HAS_FFMPEG_AUDIO, reason="the PyPI bpy 4.2 module is built without audio"
)


@pytest.fixture(scope="module")
def takes(tmp_path_factory):
    """The take as a 44.1 kHz stereo WAV and in every encoding, in a folder with Turkish letters."""
    return write_takes(tmp_path_factory.mktemp("kayıtlar-çğış"))


def test_blenders_ffmpeg_reads_for_the_core_where_blender_has_it(takes):
    names = list(DECODERS.entries())
    if compat.HAS_FFMPEG_AUDIO:
        assert names.index("soundfile") < names.index("blender") < names.index("pyav")
        assert {decode_audio(takes[name]).decoder for name in ("m4a", "mp4", "mov", "mkv", "webm")} == {
            "blender"
        }
    else:
        assert "blender" not in names and decode_audio(takes["m4a"]).decoder == "pyav"
    assert decode_audio(takes["mp3"]).decoder == "soundfile"
    blender.unregister()
    try:
        assert "blender" not in DECODERS.entries()  # the core keeps its own decoders
    finally:
        blender.register()


@needs_blenders_ffmpeg
@pytest.mark.parametrize("name", sorted(ENCODINGS))
def test_blenders_decoder_keeps_the_timing_and_length(takes, name):
    reference = decode_audio(takes["wav"])
    samples, rate = BlenderAudioDecoder().decode(takes[name], sniff_format(takes[name]))
    codec, encoded_rate, _, _ = ENCODINGS[name]
    assert rate == (48000 if codec == "libopus" else encoded_rate) and samples.dtype == np.float32
    # An AAC encoder's priming is not heard as sound, in MP4's edit list as in Matroska's codec delay.
    assert abs(lag_seconds(samples, rate, reference.samples)) <= 1 / WAV_RATE
    extra = samples.size / rate - reference.samples.size / WAV_RATE
    assert abs(extra) <= (AAC_FRAME / rate if name == "mkv" else 0.001), extra
    assert 0.3 < np.abs(samples).max() <= 1.0  # the channels' mean, not Audaspace's sum


def test_the_panel_follows_an_mp4_and_an_mp3_as_it_follows_the_wav(takes, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.render.fps = FPS
    head = heads.create_reference_head(bpy.context)["head"]
    shapekeys.build_shape_keys(head)
    settings = bpy.context.scene.turkish_lipsync
    settings.head, settings.audio_folder = head, str(tmp_path)
    text = bpy.data.texts.new("speech")
    text.write(TAKE_TEXT)
    settings.source_kind, settings.text = "TEXT", text
    keyed, sounds, frame_ends = {}, {}, {}
    for name in ("wav", "mp4", "mp3", "wav again"):
        settings.recording = str(takes[name.removesuffix(" again")])
        assert bpy.ops.turkish_lipsync.generate() == {"FINISHED"}
        keyed[name] = pipeline.animation_record(head).timeline  # what the keys were made from
        sounds[name] = decode_audio(sequencer.speech_wav_of(bpy.context.scene))
        frame_ends[name] = bpy.context.scene.frame_end
    # Within 10 ms of the WAV's onsets, beyond what the WAV moves aligned again (eSpeak NG's rendition
    # shifts a little from one synthesis to the next: tests/core/test_speech_decoders.py).
    for name in ("mp4", "mp3"):
        for kind in ("phones", "words"):
            spread = onset_differences(keyed["wav again"], keyed["wav"], kind)
            differences = onset_differences(keyed[name], keyed["wav"], kind)
            assert np.all(differences <= ONSET_TOLERANCE + spread + 1e-6), (name, kind, differences.max())
    # The sound placed in the sequencer is the recording at its own rate, as long as the WAV's (to 1 ms).
    for name, sound in sounds.items():
        assert sound.rate == (WAV_RATE if name.startswith("wav") else ENCODINGS[name][1])
        assert abs(sound.samples.size / sound.rate - sounds["wav"].samples.size / WAV_RATE) <= 0.001
        assert frame_ends[name] == frame_ends["wav"]
    if compat.HAS_AUDIO:
        assert [s.name for s in compat.sequencer_strips(bpy.context.scene)] == [sequencer.SPEECH_STRIP_NAME]


def test_a_video_without_sound_is_refused_and_changes_nothing(tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    head = heads.create_reference_head(bpy.context)["head"]
    shapekeys.build_shape_keys(head)
    settings = bpy.context.scene.turkish_lipsync
    settings.head = head
    text = bpy.data.texts.new("speech")
    text.write("Merhaba.")
    settings.source_kind, settings.text = "TEXT", text
    silent = encode(tmp_path / "resim.mp4", np.zeros((1, 0), np.float32), 48000, "aac", "libx264", False)
    settings.recording = str(silent)
    actions = len(bpy.data.actions)
    with pytest.raises(RuntimeError, match=r"resim\.mp4"):
        bpy.ops.turkish_lipsync.generate()
    assert len(bpy.data.actions) == actions and sequencer.speech_wav_of(bpy.context.scene) is None


def test_the_recording_browser_shows_only_what_can_be_read_and_fills_the_field(takes, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    shown = set(recording_browser.FILTER_GLOB.split(";"))
    read = ("wav", "flac", "ogg", "mp3", "m4a", "aac", "mp4", "mov", "mkv", "webm")
    assert {f"*.{suffix}" for suffix in read} <= shown
    assert "*.blend" not in shown and "*.txt" not in shown
    settings = bpy.context.scene.turkish_lipsync
    chosen = str(takes["m4a"])
    assert bpy.ops.turkish_lipsync.choose_recording("EXEC_DEFAULT", filepath=chosen) == {"FINISHED"}
    assert settings.recording == chosen  # an unsaved file: the path stays absolute
    bpy.ops.wm.save_as_mainfile(filepath=str(takes["m4a"].parent / "sahne.blend"))
    assert bpy.ops.turkish_lipsync.choose_recording("EXEC_DEFAULT", filepath=chosen) == {"FINISHED"}
    assert settings.recording == "//take.m4a"
    assert bpy.ops.turkish_lipsync.choose_recording("EXEC_DEFAULT", filepath=chosen, target="SPEAKER") == {
        "CANCELLED"
    }  # no speaker in the cast yet: nothing to fill
    settings.cast.add().name = "Ayşe"
    bpy.ops.turkish_lipsync.choose_recording("EXEC_DEFAULT", filepath=str(takes["mp4"]), target="SPEAKER")
    assert settings.cast[0].recording == "//take.mp4" and settings.recording == "//take.m4a"


def test_a_conversation_follows_its_speakers_m4a_tracks_as_their_wavs(tmp_path):
    script = read_script("AYŞE (to ALİ): Merhaba Ali, nasılsın?\nALİ: İyiyim, sağ ol. Sen nasılsın?")
    truth = converse(script, cast_for(script), LipSyncOptions(fps=FPS)).speech
    lines = {}
    for kind in ("wav", "m4a"):
        tracks = {}
        for role in truth.cast.roles:
            voice = truth.voice_of(role.key)
            samples = (voice.samples.astype(np.float32) / 32768)[None, :]
            path = tmp_path / f"{role.key}.{kind}"
            if kind == "wav":
                tracks[role.key] = write_pcm_wav(path, samples[0], voice.sample_rate)
            else:
                tracks[role.key] = encode(path, samples, voice.sample_rate, "aac")
        sources = SceneSources(speaker_recordings=tracks)
        lines[kind] = scene_speech(script, truth.cast, LipSyncOptions(fps=FPS), sources).lines
    # Each speaker's turns are aligned on their own stretch of the track, so a phone at a near tie of two
    # analysis frames (10 ms) can take the other one; eSpeak NG's rendition itself moves by up to ~10 ms
    # with what it spoke before in the process (tests/blender/test_pipeline.py): two frames in all.
    for wav, m4a in zip(lines["wav"], lines["m4a"], strict=True):
        starts = np.array([p.start for p in m4a.timeline.phones]) - [p.start for p in wav.timeline.phones]
        assert np.abs(starts).max() <= 2 * ONSET_TOLERANCE + 1e-6 and np.median(np.abs(starts)) <= 1e-3


def _run_render_without_pyav(*arguments) -> subprocess.CompletedProcess:
    """render.py in a process where PyAV cannot be imported: what a user's own Blender has."""
    runner = (
        "import runpy, sys; sys.modules['av'] = None; "
        f"sys.argv = [{str(RENDER_SCRIPT)!r}, *sys.argv[1:]]; "
        "runpy.run_path(sys.argv[0], run_name='__main__')"
    )
    return subprocess.run(
        [sys.executable, "-c", runner, *map(str, arguments)],
        capture_output=True, text=True, timeout=600, check=False,
    )  # fmt: skip


def test_render_script_reads_an_m4a_as_its_wav(takes, tmp_path):
    """Where Blender has its FFmpeg, PyAV is hidden from the script: Blender's own decoder reads the take."""
    run = _run_render_without_pyav if compat.HAS_FFMPEG_AUDIO else run_render
    generated = {}
    for name in ("wav", "m4a"):
        result = run("--text", TAKE_TEXT, "--audio", takes[name], "--no-render", "--fps", FPS,
                     "--save-blend", tmp_path / f"{name}.blend")  # fmt: skip
        assert result.returncode == 0, result.stderr
        assert "Traceback" not in result.stderr
        generated[name] = next(line for line in result.stdout.splitlines() if line.startswith("Generated"))
    # "Generated N phones, S s, frames A-B at F fps; audio: ...": the same phones and frames, the same
    # seconds to the printed hundredth.
    numbers = {name: re.findall(r"[\d.]+", line.partition("; audio:")[0]) for name, line in generated.items()}
    assert numbers["m4a"][0] == numbers["wav"][0] and numbers["m4a"][2:] == numbers["wav"][2:]
    assert float(numbers["m4a"][1]) == pytest.approx(float(numbers["wav"][1]), abs=0.011)
