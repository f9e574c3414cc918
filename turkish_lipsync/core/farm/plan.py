"""The frames of an episode's scenes, known before any scene is built: a job's chunks are fixed when it is
made, so each scene's speech is timed here as its build will time it (no Blender: the core alone).

The build checks that the scene it made has these frames (tasks.build_scene): a scene whose inputs
changed after the job was made fails its build and says to make the job again.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..base.errors import LipSyncError, MarkupError
from ..base.files import read_user_text
from ..batch.arguments import parse_arguments
from ..batch.command import lip_sync_options, scene_sources, speaker_choices
from ..motion.frames import shown_frame_count
from ..pipeline import lip_sync
from ..scene import cast_for, scene_speech
from .manifest import Episode, EpisodeError, Scene


def blender_fps(fps: float) -> float:
    """The frame rate a scene shows after render.py set it (blender/batch.py: set_frame_rate): a whole rate
    over a base Blender keeps in 32 bits (29.97 is 30 / 1.001), so the frames counted here are the frames the
    build counts."""
    whole = round(fps)
    if abs(whole - fps) < 1e-6:
        return float(whole)
    return whole / float(np.float32(whole / fps))


def scene_frames(scene: Scene, fps: float) -> tuple[int, int]:
    """(first, last) frame of the scene once built: its speech's length at the scene's frame rate."""
    try:
        arguments = parse_arguments([*scene.arguments, "--no-render"])
    except SystemExit:  # render.py's parser printed what it refused
        raise EpisodeError(
            [f"{scene.where}: scene {scene.name}'s settings are refused by render.py"]
        ) from None
    source = read_user_text(scene.file, "scene's script")
    options = dataclasses.replace(lip_sync_options(arguments), fps=blender_fps(fps))
    if scene.script is not None:
        cast = cast_for(scene.script, speaker_choices(arguments), options.emotion_strength)
        duration = scene_speech(scene.script, cast, options, scene_sources(arguments)).duration
    else:
        duration = lip_sync(source, options).timeline.duration
    return 1, shown_frame_count(duration, options.fps)


def plan_episode(episode: Episode) -> dict[str, tuple[int, int]]:
    """Every scene's frames; EpisodeError lists each scene that cannot be spoken, with its file."""
    frames, problems = {}, []
    for scene in episode.scenes:
        try:
            frames[scene.name] = scene_frames(scene, episode.render.fps)
        except MarkupError as error:
            problems.append(f"{scene.file}:{error.line}:{error.column}: {error.message}")
        except EpisodeError as error:
            problems += error.problems
        except LipSyncError as error:
            problems.append(f"{scene.file}: {error}")
    if problems:
        raise EpisodeError(problems)
    return frames
