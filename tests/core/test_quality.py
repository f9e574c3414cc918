"""The quality report: its measures on hand-made tracks, and thesis mode against the default."""

from __future__ import annotations

import json

import numpy as np
import pytest

from turkish_lipsync.core.base.model import Phone, Timeline, Track, WeightTracks
from turkish_lipsync.core.motion.frames import shape_runs, shown_shapes
from turkish_lipsync.core.motion.quality import (
    REPORT_KEYS,
    compare_modes,
    format_quality,
    quality_report,
)
from turkish_lipsync.core.speech.timing import table_timeline
from turkish_lipsync.core.text.utterance import build_utterance


def test_a_frame_shows_the_viseme_holding_half_its_weight_and_runs_group_them():
    weights = np.array(
        [
            [1.0, 0.0, 0.0],
            [0.6, 0.4, 0.0],
            [0.4, 0.35, 0.25],
            [0.2, 0.8, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
        ]
    )
    labels = shown_shapes(weights)
    assert labels.tolist() == [0, 0, -1, 1, 1, 0]
    assert shape_runs(labels) == [(0, 0, 2), (1, 3, 2), (0, 5, 1)]


def _tracks(fps: float, columns: dict[str, list[float]]) -> WeightTracks:
    frame_count = len(next(iter(columns.values())))
    frames = np.arange(frame_count, dtype=np.float64)
    tracks = tuple(
        Track(name, frames, np.asarray(values, dtype=np.float64)) for name, values in columns.items()
    )
    return WeightTracks(fps=fps, frame_count=frame_count, interpolation="LINEAR", tracks=tracks)


def test_the_measures_catch_a_flash_a_missed_closure_and_an_overfull_frame():
    # "ama" at 10 fps: a from 0.1 s, m at 0.3 s, a at 0.4 s; the m only reaches 0.7 and two shapes overlap.
    phones = (
        Phone(0.1, 0.3, 0, "a", "a", 0, "a"),
        Phone(0.3, 0.4, 1, "m", "ma", 0, "ma"),
        Phone(0.4, 0.6, 2, "a", "ma", 0, "a"),
    )
    timeline = Timeline(phones, (), (), (), 0.7, "table")
    tracks = _tracks(
        10,
        {
            "TR_viseme_neutral": [1, 0, 0, 0, 0, 0, 0, 1],
            "TR_viseme_a": [0, 1, 1, 0.3, 0.9, 1, 1, 0],
            "TR_viseme_ma": [0, 0, 0, 0.7, 0.3, 0, 0, 0],
        },
    )
    report = quality_report(timeline, tracks)
    assert report["bilabial_closure_share"] == 0.0
    assert report["max_weight_sum"] == pytest.approx(1.2)
    assert report["min_hold_frames"] == 1  # the neutral frame at the end
    assert report["max_frame_jump"] == pytest.approx(1.0)
    # The m rises through half at frame 2.5 (50 ms early); the second a from 0.3 to 0.9 passes half
    # at frame 3 1/3, 66.7 ms before its start at 0.4 s.
    assert report["onset_error_ms_max"] == pytest.approx(66.7)
    assert report["onset_reference"] == "timeline"


@pytest.mark.parametrize("emotion", ("HAPPY", "ANGRY", "DISGUSTED"))
def test_thesis_mode_trades_closures_for_the_emotion_and_the_default_does_not(emotion):
    text = f"<{emotion}>Pembe bulutlar mavi gökyüzünde yavaşça süzülüyordu.</{emotion}>"
    report = compare_modes(table_timeline(build_utterance(text)), 25)
    assert set(report) == {"thesis", "default"}
    for mode in report.values():
        assert set(REPORT_KEYS) <= set(mode)
    assert report["thesis"]["bilabial_closure_share"] < 1.0
    assert report["default"]["bilabial_closure_share"] == 1.0
    assert report["default"]["min_hold_frames"] >= 2
    json.dumps(report)  # the command line prints it as JSON


def test_without_emotion_the_default_is_smoother_than_the_thesis():
    timeline = table_timeline(
        build_utterance('<PROS RATE="150%">Mehmet bey bu sabah vapura binip geçti.</PROS>')
    )
    report = compare_modes(timeline, 24)
    thesis, default = report["thesis"], report["default"]
    assert default["changes_per_second"] < thesis["changes_per_second"]
    assert default["min_hold_frames"] >= 2 > thesis["min_hold_frames"]  # the thesis flashes single frames
    assert default["bilabial_closure_share"] >= thesis["bilabial_closure_share"]
    assert default["max_weight_sum"] <= 1.0 + 1e-9


def test_onsets_are_measured_against_the_engine_when_it_ran():
    from turkish_lipsync.core.speech import synthesize_timeline

    timeline = synthesize_timeline(build_utterance("Babam bana mavi bir kalem aldı."), "phone").timeline
    report = compare_modes(timeline, 30)
    for mode in report.values():
        assert mode["onset_reference"] == "engine"
        assert mode["onset_error_ms_max"] is not None and mode["onset_error_ms_max"] < 200


def test_the_text_format_lists_every_measure_for_both_modes():
    report = compare_modes(table_timeline(build_utterance("Bir fincan kahve lütfen.")), 30)
    text = format_quality(report)
    lines = text.splitlines()
    assert "thesis" in lines[1] and "default" in lines[1]
    assert len(lines) == 2 + 9
    assert all(len(line.split()) >= 3 for line in lines[2:])
