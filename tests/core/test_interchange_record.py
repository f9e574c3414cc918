"""The animation record Generate keeps beside the keys: read back as written, old ones read, damage told."""

import dataclasses
import json

import numpy as np
import pytest

from turkish_lipsync.core.base.model import HeadAndEyes, Hesitation
from turkish_lipsync.core.interchange.animation_record import (
    AnimationRecord,
    RecordError,
    record_from_json,
    record_to_json,
)
from turkish_lipsync.core.motion import weight_tracks
from turkish_lipsync.core.motion.living import LivingOptions, living_tracks
from turkish_lipsync.core.speech.timing import table_timeline
from turkish_lipsync.core.text.utterance import build_utterance


@pytest.fixture(scope="module")
def record():
    timeline = table_timeline(build_utterance("<SENT><HAPPY>Merhaba</HAPPY>, benim adım Erdem.</SENT>"))
    timeline = dataclasses.replace(timeline, hesitations=(Hesitation(0.8, 1.3, "e", "e"),))  # an "eee"
    tracks = living_tracks(weight_tracks(timeline, 60.0), timeline, LivingOptions(seed=3))
    return AnimationRecord(
        text="Merhaba, benim adım Erdem.",
        timeline=timeline,
        fps=60.0,
        frame_start=1,
        frame_count=tracks.frame_count,
        settings={"timing": "table"},
        key_fingerprint="abc",
        warnings=("a warning",),
        head_and_eyes=tracks.head_and_eyes,
    )


def test_the_record_reads_back_as_written(record):
    back = record_from_json(record_to_json(record), "the test")
    assert back.timeline == record.timeline and back.text == record.text and back.warnings == record.warnings
    for part in ("head", "left_eye", "right_eye"):
        written, read = getattr(record.head_and_eyes, part), getattr(back.head_and_eyes, part)
        assert read.shape == written.shape and read.dtype == np.float64
        assert np.abs(read - written).max() < 1e-5 * max(1.0, np.abs(written).max())
        assert np.abs(written).max() > 0.5  # the take moves: the comparison is not of zeros


def test_a_version_1_record_is_still_read(record):
    stored = json.loads(record_to_json(record))
    stored["version"] = 1
    del stored["timeline"]["hesitations"]  # written before hesitations were kept
    stored["head_and_eyes"] = {
        part: np.round(getattr(record.head_and_eyes, part), 5).tolist()
        for part in ("head", "left_eye", "right_eye")
    }
    back = record_from_json(json.dumps(stored), "the test")
    assert np.allclose(back.head_and_eyes.head, record.head_and_eyes.head, atol=1e-5)
    assert back.timeline.hesitations == () and back.timeline.phones == record.timeline.phones


@pytest.mark.parametrize(
    "damage",
    [
        lambda stored: stored["head_and_eyes"]["head"].update(float32="not base64!"),
        lambda stored: stored["head_and_eyes"]["head"].update(shape=[7, 3]),
        lambda stored: stored["head_and_eyes"].pop("left_eye"),
        lambda stored: stored.update(version=99),
    ],
)
def test_a_damaged_record_is_refused_with_what_to_do(record, damage):
    stored = json.loads(record_to_json(record))
    damage(stored)
    with pytest.raises(RecordError, match="press Generate Animation again"):
        record_from_json(json.dumps(stored), "the action 'TR_x'")


def test_rotations_are_stored_compactly(record):
    """Ten minutes at 60 fps must not make a record of megabytes of decimal numbers."""
    frames = 36_000
    moving = HeadAndEyes(
        head=np.random.default_rng(0).normal(0, 3, (frames, 3)),
        left_eye=np.random.default_rng(1).normal(0, 8, (frames, 3)),
        right_eye=np.random.default_rng(2).normal(0, 8, (frames, 3)),
    )
    size = len(record_to_json(dataclasses.replace(record, head_and_eyes=moving)).encode("utf-8"))
    packed = frames * 9 * 4 * 4 / 3  # float32 in base64
    assert size < packed + len(record_to_json(record)) + 1000
