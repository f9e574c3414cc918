"""Rhubarb Lip Sync's XML: <rhubarbResult> with metadata and <mouthCue start end>SHAPE</mouthCue>."""

from __future__ import annotations

import xml.etree.ElementTree as ElementTree
from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

from .common import CueFileError, MouthCue, RhubarbResult, check_cue_count, register


@register
class RhubarbXml(RhubarbResult):
    name = "rhubarb-xml"
    order = 3
    suffixes = (".xml",)
    label = "Rhubarb XML"
    description = "Mouth cues A-H and X as XML (Rhubarb Lip Sync's XML output)"

    def parse(self, path: Path, text: str) -> tuple[list[tuple[str, object, object, object]], object, str]:
        """Documents with a DTD or entities are refused (Rhubarb never writes them)."""
        if "<!DOCTYPE" in text or "<!ENTITY" in text:
            raise CueFileError(f"{path}: XML with a DTD or entities is not read; Rhubarb never writes them")
        check_cue_count(path, text.count("<mouthCue "))
        try:
            root = ElementTree.fromstring(text)
        except ElementTree.ParseError as error:
            line, column = error.position
            raise CueFileError(f"{path}: line {line}, column {column}: not valid XML") from None
        records = [
            (f"mouthCue {index + 1}", element.get("start"), element.get("end"), (element.text or "").strip())
            for index, element in enumerate(root.iter("mouthCue"))
        ]
        return records, root.findtext("metadata/duration") or None, root.findtext("metadata/soundFile") or ""

    def document(self, cues: tuple[MouthCue, ...], duration: float, sound_file: str) -> str:
        lines = [
            '<?xml version="1.0" encoding="utf-8"?>',
            "<rhubarbResult>",
            "  <metadata>",
            f"    <soundFile>{escape(sound_file)}</soundFile>",
            f"    <duration>{duration:.3f}</duration>",
            "  </metadata>",
            "  <mouthCues>",
        ]
        lines += [
            f"    <mouthCue start={quoteattr(f'{cue.start:.3f}')} end={quoteattr(f'{cue.end:.3f}')}>"
            f"{cue.shape}</mouthCue>"
            for cue in cues
        ]
        lines += ["  </mouthCues>", "</rhubarbResult>"]
        return "\n".join(lines) + "\n"
