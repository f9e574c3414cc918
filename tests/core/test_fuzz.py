"""Random and hostile inputs: a right result or one clear error, never a traceback, a hang or a changed input.

Seeded (reproducible), sized to run in CI in a few seconds per kind: random JSML (tags valid, invalid,
crossing, entities, other scripts, control characters, numbers and signs), random cue files of every format
(valid and broken), and the command line on random files.
"""

import contextlib
import hashlib
import io
import math
import signal

import numpy as np
import pytest

from turkish_lipsync.core.base.errors import LipSyncError
from turkish_lipsync.core.cli import main
from turkish_lipsync.core.pipeline import LipSyncOptions, lip_sync
from turkish_lipsync.core.speech.cue_timing import timeline_from_cues
from turkish_lipsync.core.speech.cues import cue_formats, read_cue_file
from turkish_lipsync.core.text.utterance import build_utterance

CASES = 150
HANG_SECONDS = 60  # a watchdog, not a speed measurement: a case that takes this long is stuck

WORDS = ["merhaba", "benim", "adım", "Erdem", "İstanbul", "ığdır", "şöyle", "çünkü", "Ağaç", "TBMM", "Prof."]
PIECES = [
    "<SENT>", "</SENT>", "<PARA>", "</PARA>", "<HAPPY>", "</HAPPY>", "<SAD WEIGHT='0.5'>", "</SAD>",
    "<EMP>", "</EMP>", "<BREAK/>", "<BREAK SIZE='large'/>", "<PROS RATE='2'>", "</PROS>", "<SAYAS SUB='on'>",
    "</SAYAS>", "<ANGRY", "</>", "<!DOCTYPE x [<!ENTITY a 'b'>]>", "&a;", "&amp;", "&#x130;", "<<", ">",
    "%-3", "-%12,5", "3.5", "1/2", "2.499,90 TL", "09:00'da", "XIX.", "1:25.000", "€4,99", "°C", "km/sa",
    "Привет", "مرحبا", "😀👍🏽", "\u0307", "\u200b", "\x00", "\x07", "\t", "\n\n", "...", "?", "!", "—", "'",
    '"', "ali@ornek.com.tr", "www.örnek.com", "0 (212) 555 12 34", "٣", "½", "ǅ", "ﬁ", " ",
]  # fmt: skip


@contextlib.contextmanager
def watchdog(seconds: int = HANG_SECONDS):
    def stuck(_signum, _frame):
        raise TimeoutError(f"a case ran longer than {seconds} s: it hangs")

    previous = signal.signal(signal.SIGALRM, stuck)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def random_jsml(rng: np.random.Generator) -> str:
    parts = []
    for _ in range(int(rng.integers(1, 25))):
        if rng.random() < 0.55:
            parts.append(str(rng.choice(WORDS)))
        else:
            parts.append(str(rng.choice(PIECES)))
        parts.append(" " if rng.random() < 0.7 else "")
    return "".join(parts)


def _check_timeline(timeline) -> None:
    starts = np.array([p.start for p in timeline.phones])
    ends = np.array([p.end for p in timeline.phones])
    assert np.all(np.isfinite(starts)) and np.all(starts >= 0) and np.all(ends >= starts - 1e-9)
    assert np.all(np.diff(starts) >= -1e-9)
    assert math.isfinite(timeline.duration) and ends.max(initial=0) <= timeline.duration + 1e-6


@pytest.mark.parametrize("seed", range(4))
def test_random_jsml_speaks_or_says_what_is_wrong(seed):
    rng = np.random.default_rng(seed)
    for _ in range(CASES):
        source = random_jsml(rng)
        with watchdog():
            try:
                result = lip_sync(source, LipSyncOptions(timing="table"))
            except LipSyncError as error:
                assert str(error) and "\n" not in str(error).strip(), source
                continue
        _check_timeline(result.timeline)
        assert result.tracks.frame_count >= 1


def test_random_jsml_through_the_speech_engine():
    rng = np.random.default_rng(7)
    for _ in range(25):
        source = random_jsml(rng)
        with watchdog():
            try:
                result = lip_sync(source, LipSyncOptions(timing="phone"))
            except LipSyncError:
                continue
        _check_timeline(result.timeline)
        assert result.synthesis is not None and result.synthesis.duration > 0


def _random_cue_text(rng: np.random.Generator, name: str, fps: float) -> str:
    """A cue file of the format, written from a real timeline and then damaged, or random noise."""
    roll = rng.random()
    if roll < 0.15:
        return bytes(rng.integers(0, 256, int(rng.integers(0, 400)), dtype=np.uint8)).decode("latin-1")
    utterance = build_utterance(" ".join(rng.choice(WORDS[:8], size=int(rng.integers(1, 6)))))
    from turkish_lipsync.core.speech.timing import table_timeline

    text = cue_formats()[name].write(table_timeline(utterance), fps)[0]
    if roll < 0.5:
        return text
    lines = text.splitlines()
    for _ in range(int(rng.integers(1, 4))):
        if not lines:
            break
        i = int(rng.integers(0, len(lines)))
        damage = rng.choice(["drop", "swap", "number", "shape", "duplicate"])
        if damage == "drop":
            del lines[i]
        elif damage == "swap" and len(lines) > 1:
            j = int(rng.integers(0, len(lines)))
            lines[i], lines[j] = lines[j], lines[i]
        elif damage == "number":
            lines[i] = lines[i].replace("0", str(rng.choice(["-1", "nan", "1e9", "inf", "x", "٣"])), 1)
        elif damage == "shape":
            lines[i] = lines[i] + str(rng.choice(["Q", "", " A B", "😀"]))
        else:
            lines.insert(i, lines[i])
    return "\n".join(lines)


@pytest.mark.parametrize("name", list(cue_formats()))
def test_random_cue_files_time_the_text_or_are_refused_in_one_line(tmp_path, name):
    rng = np.random.default_rng(sum(map(ord, name)))
    suffix = cue_formats()[name].suffixes[0]
    utterance = build_utterance("Merhaba, benim adım Erdem.")
    for number in range(CASES):
        path = tmp_path / f"cues{number}{suffix}"
        path.write_text(_random_cue_text(rng, name, 25.0), encoding="utf-8", errors="surrogatepass")
        with watchdog():
            try:
                timeline, _ = timeline_from_cues(utterance, read_cue_file(path, 25.0))
            except LipSyncError as error:
                assert str(error).startswith(str(path)) or "cue" in str(error) or "text" in str(error), error
                continue
        _check_timeline(timeline)


def test_the_command_line_on_random_files_never_changes_them(tmp_path):
    rng = np.random.default_rng(11)
    for number in range(20):
        script = tmp_path / f"script{number}.jsml"
        script.write_text(random_jsml(rng), encoding="utf-8")
        cues = tmp_path / f"cues{number}.tsv"
        cues.write_text(_random_cue_text(rng, "rhubarb-tsv", 25.0), encoding="utf-8")
        before = {path: hashlib.sha256(path.read_bytes()).digest() for path in (script, cues)}
        arguments = [
            ["timeline", str(script), "--timing", "table", "--format", "json"],
            ["export", str(script), "--cues", str(cues), "--format", "moho-dat", "--out", str(cues)],
            ["export", str(script), "--timing", "table", "--format", "arkit-csv"],
            ["timeline", "--cues", str(cues), "--text", "merhaba benim"],
        ][number % 4]
        out, err = io.StringIO(), io.StringIO()
        with watchdog(), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            status = main(arguments)
        assert status in (0, 2), (arguments, err.getvalue())
        errors = [line for line in err.getvalue().splitlines() if line.startswith("error:")]
        assert (status == 2) == bool(errors) and len(errors) <= 1, err.getvalue()
        assert {path: hashlib.sha256(path.read_bytes()).digest() for path in (script, cues)} == before


def _random_mesh(rng: np.random.Generator, kind: int) -> tuple[np.ndarray, np.ndarray]:
    """A mesh within the budget (3,000 vertices, 4,000 triangles): random, degenerate, or a real head
    damaged (flattened, scattered, duplicated)."""
    from turkish_lipsync.core.faces.reference import load_reference_head

    if kind == 0:  # random triangles among random points (a head of nothing: the 13 GB case)
        count = int(rng.integers(4, 3000))
        return rng.normal(size=(count, 3)), rng.integers(0, count, size=(int(rng.integers(1, 4000)), 3))
    if kind == 1:  # everything on one plane, or one point
        count = int(rng.integers(4, 500))
        points = rng.normal(size=(count, 3)) * np.array([1.0, 0.0, 1.0]) * rng.choice([1.0, 0.0])
        return points, rng.integers(0, count, size=(count, 3))
    head = load_reference_head()
    keep = np.sort(rng.choice(len(head.vertices), size=min(3000, len(head.vertices)), replace=False))
    remap = np.full(len(head.vertices), -1)
    remap[keep] = np.arange(keep.size)
    triangles = remap[head.triangles()]
    triangles = triangles[(triangles >= 0).all(axis=1)][:4000]
    vertices = head.vertices[keep] * rng.uniform(1e-3, 1e3)
    if kind == 3:
        vertices = vertices + rng.normal(scale=0.02, size=vertices.shape) * np.abs(vertices).max()
    if kind == 4:
        vertices = vertices[:, [0, 2, 1]] * np.array([1.0, -1.0, 1.0])  # another up axis
    return vertices, triangles


def test_random_meshes_give_landmarks_or_one_clear_error():
    from turkish_lipsync.core.faces.landmarks import find_landmarks

    rng = np.random.default_rng(23)
    for kind in (0, 0, 1, 2, 3, 4):  # each kind of mesh; about 8 s each, the search tries every view
        vertices, triangles = _random_mesh(rng, kind)
        with watchdog(120):
            try:
                found = find_landmarks(vertices, triangles)
            except LipSyncError as error:
                assert str(error) and "\n" not in str(error).strip()
                continue
        points = np.array(list(found.values()))
        assert np.isfinite(points).all()
