"""Rhubarb Lip Sync's JSON: metadata (sound file, duration) and mouthCues (start, end, value).

Read by the Rhubarb importers of game engines (Godot, Unity) and web players (three.js, Pixi).
"""

from __future__ import annotations

import json
from pathlib import Path

from .common import CueFileError, MouthCue, RhubarbResult, check_cue_count, register


@register
class RhubarbJson(RhubarbResult):
    name = "rhubarb-json"
    order = 2
    suffixes = (".json",)
    label = "Rhubarb JSON"
    description = "Mouth cues A-H and X as JSON (Godot, Unity, Spine, web players)"

    def parse(self, path: Path, text: str) -> tuple[list[tuple[str, object, object, object]], object, str]:
        try:
            document = json.loads(text)
        except json.JSONDecodeError as error:
            raise CueFileError(f"{path}: line {error.lineno}: not valid JSON ({error.msg})") from None
        entries = document.get("mouthCues") if isinstance(document, dict) else None
        if not isinstance(entries, list):
            raise CueFileError(f"{path}: no 'mouthCues' list: is this a Rhubarb JSON file?")
        check_cue_count(path, len(entries))
        records = []
        for index, entry in enumerate(entries):
            if not isinstance(entry, dict):
                raise CueFileError(f"{path}: mouthCues[{index}] must be an object with start, end and value")
            records.append((f"mouthCues[{index}]", entry.get("start"), entry.get("end"), entry.get("value")))
        metadata = document.get("metadata") if isinstance(document.get("metadata"), dict) else {}
        return records, metadata.get("duration"), str(metadata.get("soundFile", ""))

    def document(self, cues: tuple[MouthCue, ...], duration: float, sound_file: str) -> str:
        document = {
            "metadata": {"soundFile": sound_file, "duration": round(duration, 3)},
            "mouthCues": [
                {"start": round(cue.start, 3), "end": round(cue.end, 3), "value": cue.shape} for cue in cues
            ],
        }
        return json.dumps(document, indent=2) + "\n"
