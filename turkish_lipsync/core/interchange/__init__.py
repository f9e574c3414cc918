"""Interchange with the tools around Blender: exports of a generated animation, and timing files read back.

Exports (no Blender needed): Rhubarb mouth cues (TSV, JSON, XML), Moho switch data (.dat), a Papagayo project
(.pgo) and the 52 ARKit weights per frame as Live Link Face CSV. Imports: Rhubarb TSV/JSON/XML, Papagayo .pgo
and Moho .dat as the timing source of our Turkish visemes (cue_timing.py).
"""

from __future__ import annotations

from pathlib import Path

from ..errors import LipSyncError
from ..model import Timeline, WeightTracks
from ..pipeline import Choice
from .arkit_csv import arkit_weights, live_link_csv, read_arkit_csv
from .cue_timing import CUE_SUFFIXES, CUE_TIMING, CueSource, read_cue_source, timeline_from_cues
from .cues import CueFileError, MouthCue, cues_as_json, cues_as_tsv, cues_as_xml, mouth_cues
from .papagayo import moho_switch_dat, read_pgo, timeline_as_pgo

# Export format -> the file suffix it is written with.
EXPORT_FORMATS: dict[str, str] = {
    "rhubarb-tsv": ".tsv",
    "rhubarb-json": ".json",
    "rhubarb-xml": ".xml",
    "moho-dat": ".dat",
    "papagayo-pgo": ".pgo",
    "arkit-csv": ".csv",
}
# The formats for the panel and --help: what each one is and who reads it.
EXPORT_CHOICES: tuple[Choice, ...] = (
    Choice("rhubarb-tsv", "Rhubarb TSV", "Mouth cues A-H and X with their start times (Rhubarb Lip Sync)"),
    Choice("rhubarb-json", "Rhubarb JSON", "Mouth cues A-H and X as JSON (Godot, Unity, Spine, web players)"),
    Choice("rhubarb-xml", "Rhubarb XML", "Mouth cues A-H and X as XML (Rhubarb Lip Sync's XML output)"),
    Choice("moho-dat", "Moho Switch Data", "Preston Blair mouths per frame for Moho and OpenToonz (.dat)"),
    Choice("papagayo-pgo", "Papagayo Project", "Words and mouths per frame for Papagayo-NG (.pgo)"),
    Choice("arkit-csv", "ARKit CSV", "52 ARKit weights per frame, Live Link Face layout (Unreal, MetaHuman)"),
)


def export_text(
    export_format: str,
    timeline: Timeline,
    fps: float,
    *,
    tracks: WeightTracks | None = None,
    sound_file: str = "",
    text: str = "",
) -> tuple[str, tuple[str, ...]]:
    """The file contents of one export format, and warnings for what the format could not hold."""
    if export_format not in EXPORT_FORMATS:
        raise LipSyncError(
            f"unknown export format {export_format!r}; choose one of: {', '.join(EXPORT_FORMATS)}"
        )
    if export_format == "arkit-csv":
        if tracks is None:
            raise LipSyncError(
                "the ARKit CSV needs the weight tracks of the animation, not only its timeline"
            )
        weights, clipped = arkit_weights(tracks)
        warnings = ()
        if clipped:
            units = ", ".join(f"{unit} ({count})" for unit, count in sorted(clipped.items()))
            warnings = (
                "ARKit weights lie in 0..1, so the CSV clips the frames where our keys drive a unit outside "
                f"that range (negative for lip corners drawn in, above 1 in strong emotions): {units}.",
            )
        return live_link_csv(weights, tracks.fps), warnings
    if export_format == "papagayo-pgo":
        warnings = ()
        if abs(fps - round(fps)) > 1e-6:
            warnings = (
                f"Papagayo counts whole frame rates: the project says {round(fps)} fps for the scene's "
                f"{fps:g}, so it plays {abs(round(fps) / fps - 1):.1%} off in Papagayo itself.",
            )
        return timeline_as_pgo(timeline, fps, sound_file, text), warnings
    cues = mouth_cues(timeline)
    if export_format == "rhubarb-tsv":
        return cues_as_tsv(cues), ()
    if export_format == "rhubarb-json":
        return cues_as_json(cues, timeline.duration, sound_file), ()
    if export_format == "rhubarb-xml":
        return cues_as_xml(cues, timeline.duration, sound_file), ()
    return moho_switch_dat(cues, fps), ()


def write_export(path: Path | str, contents: str) -> Path:
    """Write an export beside nothing else: the folder is created, errors say where."""
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(contents, encoding="utf-8")
    except OSError as error:
        raise LipSyncError(
            f"cannot write the export {path}: {error.strerror}; choose a writable place"
        ) from None
    return path


__all__ = [
    "CUE_SUFFIXES",
    "CUE_TIMING",
    "EXPORT_CHOICES",
    "EXPORT_FORMATS",
    "CueFileError",
    "CueSource",
    "MouthCue",
    "arkit_weights",
    "export_text",
    "live_link_csv",
    "mouth_cues",
    "read_arkit_csv",
    "read_cue_source",
    "read_pgo",
    "timeline_from_cues",
    "write_export",
]
