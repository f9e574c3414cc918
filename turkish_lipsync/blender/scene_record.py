"""What the last conversation Generate made in a scene: its characters' heads and names, its strips.

Kept on the scene as JSON (names only, safe across undo), so that Generate again replaces exactly what it
made, Render frames every character and the exports write one file per character.
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import bpy

SCENE_PROPERTY = "turkish_lipsync_conversation"


@dataclass(frozen=True)
class ConversationRecord:
    heads: dict[str, str]  # speaker's key -> head object's name
    names: dict[str, str]  # speaker's key -> the name the script gives them
    strips: tuple[str, ...] = ()  # our sound strips
    fps: float = 25.0
    duration: float = 0.0  # seconds of the scene

    def head_objects(self) -> list[bpy.types.Object]:
        """The characters' heads that are still in the file, in the cast's order."""
        return [bpy.data.objects[name] for name in self.heads.values() if name in bpy.data.objects]


def conversation_record(scene: bpy.types.Scene) -> ConversationRecord | None:
    stored = scene.get(SCENE_PROPERTY)
    if not stored:
        return None
    try:
        data = json.loads(str(stored))
        return ConversationRecord(
            heads=dict(data["heads"]),
            names=dict(data["names"]),
            strips=tuple(data.get("strips", ())),
            fps=float(data.get("fps", 25.0)),
            duration=float(data.get("duration", 0.0)),
        )
    except (ValueError, KeyError, TypeError):
        return None  # a damaged record: the scene is treated as having none


def keep_conversation_record(scene: bpy.types.Scene, record: ConversationRecord) -> None:
    scene[SCENE_PROPERTY] = json.dumps(
        {
            "heads": record.heads,
            "names": record.names,
            "strips": list(record.strips),
            "fps": record.fps,
            "duration": record.duration,
        },
        ensure_ascii=False,
    )


def forget_conversation_record(scene: bpy.types.Scene) -> None:
    scene.pop(SCENE_PROPERTY, None)
