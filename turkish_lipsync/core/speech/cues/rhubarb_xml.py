"""Rhubarb Lip Sync's XML: <rhubarbResult> with metadata and <mouthCue start end>SHAPE</mouthCue>."""

from __future__ import annotations

import xml.etree.ElementTree as ElementTree
from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

from ...base.model import Timeline
from .common import (
    CueFileError,
    CueFormat,
    CueSource,
    check_cue_count,
    mouth_cues,
    read_text,
    register,
    source_from_records,
)


@register
class RhubarbXml(CueFormat):
    name = "rhubarb-xml"
    order = 3
    suffixes = (".xml",)
    label = "Rhubarb XML"
    description = "Mouth cues A-H and X as XML (Rhubarb Lip Sync's XML output)"

    def read(self, path: Path, fps: float) -> CueSource:
        """Documents with a DTD or entities are refused (Rhubarb never writes them)."""
        text = read_text(path)
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
        duration = root.findtext("metadata/duration") or None
        return source_from_records(path, records, duration, root.findtext("metadata/soundFile") or "")

    def write(self, timeline: Timeline, fps: float, *, sound_file: str = "", text: str = ""):
        lines = [
            '<?xml version="1.0" encoding="utf-8"?>',
            "<rhubarbResult>",
            "  <metadata>",
            f"    <soundFile>{escape(sound_file)}</soundFile>",
            f"    <duration>{timeline.duration:.3f}</duration>",
            "  </metadata>",
            "  <mouthCues>",
        ]
        lines += [
            f"    <mouthCue start={quoteattr(f'{cue.start:.3f}')} end={quoteattr(f'{cue.end:.3f}')}>"
            f"{cue.shape}</mouthCue>"
            for cue in mouth_cues(timeline)
        ]
        lines += ["  </mouthCues>", "</rhubarbResult>"]
        return "\n".join(lines) + "\n", ()
