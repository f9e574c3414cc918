"""Where a scene's speech comes from: each line spoken in its speaker's voice (or aligned to its own
recording), one recording of the whole scene, one recording per speaker, or a Papagayo project with a voice
per speaker. Each is one module here with a `SceneSource` registered in `SCENE_SOURCES`, as a single text's
timing sources are in core/speech/sources; `speak_scene` (scene/speech.py) asks them which one a request
is for."""

from __future__ import annotations

from .base import SCENE_SOURCES, SceneRequest, SceneSource, scene_source_for

__all__ = ["SCENE_SOURCES", "SceneRequest", "SceneSource", "scene_source_for"]
