"""The speech as a sound strip: WAV next to the .blend, one strip named TR_speech, frame range to fit."""

from __future__ import annotations

import os
import re
import tempfile
from pathlib import Path

import bpy

from ..core.base.errors import AudioError
from ..core.motion.frames import shown_frame_count
from ..core.speech.wav import speech_wav_in
from . import compat
from .scene_record import conversation_record

SPEECH_STRIP_NAME = "TR_speech"
SPEECH_FOLDER_NAME = "lipsync_audio"
# The speech WAV of the last generation, also where no sound strip can exist (bpy module without audio).
SPEECH_PATH_PROPERTY = "turkish_lipsync_speech_wav"


def scene_fps(scene: bpy.types.Scene) -> float:
    """The real frame rate, fractional rates included (29.97 is fps 30 / fps_base 1.001)."""
    return scene.render.fps / scene.render.fps_base


def _safe_file_stem(name: str) -> str:
    stem = re.sub(r"[^\w.-]+", "_", name, flags=re.UNICODE).strip("._")
    return stem[:60] or "speech"


def speech_folder(chosen_folder: str = "", package: str | None = None) -> Path:
    """Where the WAV goes: the chosen folder, else beside the saved .blend, else the user/temp folder."""
    if chosen_folder:
        folder = Path(bpy.path.abspath(chosen_folder))
    elif bpy.data.filepath:
        folder = Path(bpy.data.filepath).parent / SPEECH_FOLDER_NAME
    else:
        folder = None
        if package:
            try:
                folder = Path(bpy.utils.extension_path_user(package, path="speech", create=True))
            except (ValueError, AttributeError, RuntimeError):
                folder = None
        if folder is None:
            folder = Path(tempfile.gettempdir()) / "turkish_lipsync"
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise AudioError(
            f"Cannot create the speech folder {folder}: {error.strerror}. Choose a writable folder for the "
            "speech audio in the Lip Sync panel (or with --save-blend next to a writable place)."
        ) from error
    return folder


def write_speech_wav(name: str, synthesis, chosen_folder: str = "", package: str | None = None) -> Path:
    """The speech's WAV in the speech folder, named after the action and the sound (core/speech/wav.py)."""
    return speech_wav_in(speech_folder(chosen_folder, package), _safe_file_stem(name), synthesis)


def blend_relative(path: Path) -> str:
    """A path Blender stores relative to the .blend when it is saved (so the folder can move)."""
    if bpy.data.filepath:
        try:
            return bpy.path.relpath(str(path))
        except ValueError:  # another drive on Windows
            return str(path)
    return str(path)


def remove_speech_strip(scene: bpy.types.Scene) -> bool:
    strips = compat.sequencer_strips(scene, create=False)
    if strips is None:
        return False
    strip = strips.get(SPEECH_STRIP_NAME)
    if strip is None:
        return False
    strips.remove(strip)
    return True


def _free_channel(strips, start_frame: int, end_frame: int) -> int:
    """The lowest channel with nothing between start and end (other strips are never moved)."""
    for channel in range(1, 129):
        clash = any(
            s.channel == channel and s.frame_final_start < end_frame and s.frame_final_end > start_frame
            for s in strips
        )
        if not clash:
            return channel
    return 1


FRAME_RANGE_PROPERTY = "turkish_lipsync_frame_range"  # the range Generate set last: (start, end)
BLENDER_DEFAULT_RANGE = (1, 250)


def fit_frame_range(scene: bpy.types.Scene, start_frame: int, frame_count: int) -> tuple[str, ...]:
    """The scene's frames made to show the speech; a range of the user's own is kept where it holds it.

    A new scene (Blender's 1-250) or one whose range Generate set before gets exactly the speech's frames.
    A range the user chose stays as it is when the speech fits in it, and is extended when it does not
    (the returned warning says so)."""
    current = (scene.frame_start, scene.frame_end)
    wanted = (int(start_frame), int(start_frame) + frame_count - 1)
    ours = tuple(scene.get(FRAME_RANGE_PROPERTY, ())) == current or current == BLENDER_DEFAULT_RANGE
    warnings: tuple[str, ...] = ()
    if ours:
        scene.frame_start, scene.frame_end = wanted
    elif not (current[0] <= wanted[0] and wanted[1] <= current[1]):
        scene.frame_start, scene.frame_end = min(current[0], wanted[0]), max(current[1], wanted[1])
        warnings = (
            f"The scene's frames {current[0]}-{current[1]} did not hold the speech (frames {wanted[0]}-"
            f"{wanted[1]}): they are now {scene.frame_start}-{scene.frame_end}.",
        )
    scene[FRAME_RANGE_PROPERTY] = (scene.frame_start, scene.frame_end)
    return warnings


def place_speech_strip(
    scene: bpy.types.Scene,
    wav_path: Path,
    start_frame: int,
    duration_seconds: float,
) -> str | None:
    """Replace the TR_speech strip with wav_path at start_frame; returns the strip name.

    Returns None where this Blender has no audio support (the bpy module 4.2): the path is still recorded
    on the scene, and the renderer adds the sound to the video itself.
    """
    if not Path(wav_path).is_file():
        raise AudioError(f"The speech audio {wav_path} does not exist; generate the animation again.")
    frame_count = shown_frame_count(duration_seconds, scene_fps(scene))
    scene[SPEECH_PATH_PROPERTY] = blend_relative(Path(wav_path))
    if not compat.HAS_AUDIO:
        return None
    remove_speech_strip(scene)
    strips = compat.sequencer_strips(scene, create=True)
    channel = _free_channel(strips, start_frame, start_frame + frame_count)
    strip = strips.new_sound(SPEECH_STRIP_NAME, blend_relative(Path(wav_path)), channel, int(start_frame))
    strip.name = SPEECH_STRIP_NAME
    # Scrubbing and playback follow the audio, as animators expect for lip sync.
    scene.sync_mode = "AUDIO_SYNC"
    return strip.name


def place_scene_strips(
    scene: bpy.types.Scene, sounds: list[tuple[str, Path, int, int]], mix_path: Path | None
) -> tuple[str, ...]:
    """A conversation's sound strips (name, WAV, first frame, frames), each on the lowest channel free for
    it; the scene's mix recorded as its speech (what a render without audio support adds, what exports
    name). Returns the strips' names (none where this Blender has no audio)."""
    if mix_path is not None:
        scene[SPEECH_PATH_PROPERTY] = blend_relative(Path(mix_path))
    if not compat.HAS_AUDIO:
        return ()
    strips = compat.sequencer_strips(scene, create=True)
    names = []
    for name, wav, start_frame, frame_count in sounds:
        if not Path(wav).is_file():
            raise AudioError(f"The speech audio {wav} does not exist; generate the animation again.")
        channel = _free_channel(strips, int(start_frame), int(start_frame) + frame_count)
        strip = strips.new_sound(name, blend_relative(Path(wav)), channel, int(start_frame))
        names.append(strip.name)
    if names:
        scene.sync_mode = "AUDIO_SYNC"
    return tuple(names)


def remove_scene_strips(scene: bpy.types.Scene, names) -> int:
    """Remove a conversation's strips of ours, by the names Generate recorded (the user's stay)."""
    strips = compat.sequencer_strips(scene, create=False)
    if strips is None:
        return 0
    removed = 0
    for name in names:
        strip = strips.get(name)
        if strip is not None:
            strips.remove(strip)
            removed += 1
    return removed


def speech_strip(scene: bpy.types.Scene):
    strips = compat.sequencer_strips(scene, create=False)
    return strips.get(SPEECH_STRIP_NAME) if strips is not None else None


def speech_wav_of(scene: bpy.types.Scene) -> Path | None:
    """The speech WAV of the scene: the strip's sound, else the recorded path."""
    strip = speech_strip(scene)
    if strip is not None and strip.sound is not None:
        return Path(os.path.normpath(bpy.path.abspath(strip.sound.filepath)))
    recorded = scene.get(SPEECH_PATH_PROPERTY)
    return Path(os.path.normpath(bpy.path.abspath(recorded))) if recorded else None


def relate_speech_to(scene: bpy.types.Scene, blend_path: Path) -> None:
    """Store our speech path relative to where the .blend will be saved (so the folder can move)."""
    wav = speech_wav_of(scene)
    if wav is None:
        return
    try:
        relative = bpy.path.relpath(str(wav), start=str(Path(blend_path).resolve().parent))
    except ValueError:  # another drive on Windows
        return
    scene[SPEECH_PATH_PROPERTY] = relative
    strip = speech_strip(scene)
    if strip is not None and strip.sound is not None:
        strip.sound.filepath = relative
    record = conversation_record(scene)
    strips = compat.sequencer_strips(scene, create=False)
    for name in record.strips if record is not None and strips is not None else ():
        line = strips.get(name)
        if line is not None and line.sound is not None:
            try:
                line.sound.filepath = bpy.path.relpath(
                    os.path.normpath(bpy.path.abspath(line.sound.filepath)),
                    start=str(Path(blend_path).resolve().parent),
                )
            except ValueError:  # another drive on Windows
                continue
