"""ARKit weights per frame as Live Link Face CSV: the layout, the weights the keys stand for, a read-back."""

import numpy as np
import pytest

from turkish_lipsync.core.faces.arkit_names import ARKIT_UNITS
from turkish_lipsync.core.interchange import export_text
from turkish_lipsync.core.interchange.arkit_csv import (
    HEADER,
    LIVE_LINK_UNITS,
    arkit_weights,
    frame_of_timecode,
    read_arkit_csv,
    timecode,
)
from turkish_lipsync.core.motion import weight_tracks
from turkish_lipsync.core.motion.frames import shown_frame_count
from turkish_lipsync.core.speech import synthesize_timeline
from turkish_lipsync.core.text.utterance import build_utterance

FPS = 30.0


@pytest.fixture(scope="module")
def animation():
    timeline = synthesize_timeline(
        build_utterance("<HAPPY>Mehmet bey bu sabah vapura binip geçti.</HAPPY>")
    ).timeline
    return timeline, weight_tracks(timeline, FPS)


def test_header_is_live_link_faces():
    assert sorted(LIVE_LINK_UNITS) == sorted(ARKIT_UNITS) and len(LIVE_LINK_UNITS) == 52
    assert HEADER[:4] == ("Timecode", "BlendShapeCount", "EyeBlinkLeft", "EyeLookDownLeft")
    assert HEADER[2 + 52 - 1] == "TongueOut" and HEADER[-9:-6] == ("HeadYaw", "HeadPitch", "HeadRoll")
    assert len(HEADER) == 2 + 61


@pytest.mark.parametrize("fps", [24.0, 25.0, 29.97, 60.0])
def test_timecodes_count_frames(fps):
    for frame in (0, 1, 29, 30, 1799, 1800, 107_999, 108_000):
        assert frame_of_timecode(timecode(frame, fps), fps) == frame
    assert timecode(round(fps) * 3661 + 5, fps) == "01:01:01:05.000"


def test_csv_reads_back_frame_by_frame(animation, tmp_path):
    timeline, tracks = animation
    path = tmp_path / "speech.csv"
    path.write_text(export_text("arkit-csv", timeline, tracks)[0], encoding="utf-8")
    frames, weights = read_arkit_csv(path, FPS)
    expected, _ = arkit_weights(tracks)
    # one row per frame that shows the speech, as many as a scene and its video have: not every frame the
    # motion was computed over (one past the last sound)
    shown = shown_frame_count(timeline.duration, FPS)
    assert tracks.frame_count > shown
    np.testing.assert_array_equal(frames, np.arange(shown))
    np.testing.assert_allclose(weights, expected[:shown], atol=5e-7)
    assert ((weights >= 0) & (weights <= 1)).all()
    rows = path.read_text(encoding="utf-8").splitlines()
    assert rows[1].split(",")[1] == "61"


def test_weights_show_what_the_keys_do(animation):
    timeline, tracks = animation
    weights, clipped = arkit_weights(tracks)
    column = {unit: LIVE_LINK_UNITS.index(unit) for unit in ("jawOpen", "mouthClose", "mouthSmileLeft")}
    # the open a of "sabah" opens the jaw more than the closed m of "Mehmet"
    a_phone = next(p for p in timeline.phones if p.viseme == "a")
    m_phone = timeline.phones[0]
    a_frame = round((a_phone.start + a_phone.end) / 2 * FPS)
    m_frame = round((m_phone.start + m_phone.end) / 2 * FPS)
    assert weights[a_frame, column["jawOpen"]] > weights[m_frame, column["jawOpen"]] + 0.1
    assert weights[m_frame, column["mouthClose"]] > 0.05
    # the whole sentence is happy: the smile is on somewhere in every word
    assert weights[:, column["mouthSmileLeft"]].max() > 0.3
    assert all(count > 0 for count in clipped.values())


def test_clipped_units_are_reported(animation):
    timeline, tracks = animation
    _, warnings = export_text("arkit-csv", timeline, tracks)
    _, clipped = arkit_weights(tracks)
    if clipped:
        assert len(warnings) == 1 and all(unit in warnings[0] for unit in clipped)
    else:
        assert warnings == ()
