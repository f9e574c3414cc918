"""What Generate keeps with an animation, so that exports describe the animation the head has.

Blender holds only the keys; the timeline (which letter is spoken when, as which viseme) is not in them. The
record is written beside the keys when they are made: the text, the timeline, the frame rate and first frame,
the settings that made it, a fingerprint of the keys as written, the head's and eyes' rotations. An export
reads it back instead of speaking the text again (which would follow today's settings, and eSpeak's timing
varies by milliseconds from run to run), and the fingerprint tells when the keys were edited by hand since.
"""

from __future__ import annotations

import base64
import binascii
import json
from dataclasses import dataclass, field

import numpy as np

from ..base.errors import LipSyncError
from ..base.model import EmotionSpan, HeadAndEyes, Hesitation, Phone, Timeline, WordSpan

RECORD_VERSION = 2  # 2: the rotations as packed float32 (version 1 wrote them as lists of numbers)
_HEAD_AND_EYES = ("head", "left_eye", "right_eye")


class RecordError(LipSyncError):
    """A stored animation record that cannot be read."""


@dataclass(frozen=True, eq=False)
class AnimationRecord:
    text: str  # the source Generate spoke (JSML or plain)
    timeline: Timeline
    fps: float
    frame_start: int  # the scene frame the utterance starts on
    frame_count: int  # frames the weight tracks cover
    settings: dict = field(default_factory=dict)  # timing, motion, rate, ... as Generate had them
    key_fingerprint: str = ""  # of the keyed curves as Generate wrote them
    warnings: tuple[str, ...] = ()
    head_and_eyes: HeadAndEyes | None = None  # the living layers' rotations Generate keyed


def timeline_to_dict(timeline: Timeline) -> dict:
    return {
        "phones": [
            [p.start, p.end, p.letter_index, p.letter, p.syllable, p.word_index, p.viseme]
            for p in timeline.phones
        ],
        "words": [[w.start, w.end, w.index, w.text] for w in timeline.words],
        "emotions": [[e.start, e.end, e.emotion, e.weight] for e in timeline.emotions],
        "emphases": [list(span) for span in timeline.emphases],
        "duration": timeline.duration,
        "timing": timeline.timing,
        "engine_onsets": list(timeline.engine_onsets),
        "hesitations": [[h.start, h.end, h.sound, h.viseme] for h in timeline.hesitations],
    }


def timeline_from_dict(data: dict) -> Timeline:
    return Timeline(
        phones=tuple(Phone(*entry) for entry in data["phones"]),
        words=tuple(WordSpan(*entry) for entry in data["words"]),
        emotions=tuple(EmotionSpan(*entry) for entry in data["emotions"]),
        emphases=tuple(tuple(span) for span in data["emphases"]),
        duration=float(data["duration"]),
        timing=str(data["timing"]),
        engine_onsets=tuple(data.get("engine_onsets", ())),
        hesitations=tuple(Hesitation(*entry) for entry in data.get("hesitations", ())),
    )


def record_to_json(record: AnimationRecord) -> str:
    return json.dumps(
        {
            "version": RECORD_VERSION,
            "text": record.text,
            "timeline": timeline_to_dict(record.timeline),
            "fps": record.fps,
            "frame_start": record.frame_start,
            "frame_count": record.frame_count,
            "settings": record.settings,
            "key_fingerprint": record.key_fingerprint,
            "warnings": list(record.warnings),
            "head_and_eyes": None
            if record.head_and_eyes is None
            else {part: _packed(getattr(record.head_and_eyes, part)) for part in _HEAD_AND_EYES},
        },
        ensure_ascii=False,
        separators=(",", ":"),
    )


def record_from_json(text: str, where: str) -> AnimationRecord:
    """The record stored at `where` (named in errors); another version's record is refused with what to do."""
    try:
        data = json.loads(text)
        version = data.get("version")
        if version not in (1, RECORD_VERSION):
            raise RecordError(
                f"{where} holds an animation record of version {version!r}; this version reads "
                f"{RECORD_VERSION}: press Generate Animation again, then export"
            )
        return AnimationRecord(
            text=str(data["text"]),
            timeline=timeline_from_dict(data["timeline"]),
            fps=float(data["fps"]),
            frame_start=int(data["frame_start"]),
            frame_count=int(data["frame_count"]),
            settings=dict(data.get("settings", {})),
            key_fingerprint=str(data.get("key_fingerprint", "")),
            warnings=tuple(data.get("warnings", ())),
            head_and_eyes=None
            if data.get("head_and_eyes") is None
            else HeadAndEyes(**{part: _unpacked(data["head_and_eyes"][part]) for part in _HEAD_AND_EYES}),
        )
    except (json.JSONDecodeError, KeyError, TypeError, ValueError, AttributeError, binascii.Error) as error:
        raise RecordError(
            f"{where} holds a damaged animation record ({error}): press Generate Animation again, then export"
        ) from None


def _packed(angles: np.ndarray) -> dict:
    """(frames, k) degrees as little-endian float32 in base64: a minute at 60 fps in 60 kB, written in a
    millisecond (as JSON numbers they took a fifth of a second for ten minutes)."""
    angles = np.asarray(angles, "<f4")
    return {"shape": list(angles.shape), "float32": base64.b64encode(angles.tobytes()).decode("ascii")}


def _unpacked(stored) -> np.ndarray:
    """The angles _packed wrote, or a version 1 record's list of rows."""
    if isinstance(stored, list):
        return np.array(stored, np.float64)
    values = np.frombuffer(base64.b64decode(stored["float32"], validate=True), "<f4")
    return values.reshape([int(size) for size in stored["shape"]]).astype(np.float64)
