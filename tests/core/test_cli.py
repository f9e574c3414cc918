import json
import subprocess
import sys
from pathlib import Path

from tests.core.test_speech_recording import OTHER_TEXT
from tests.core.test_speech_recording_person import quiet_room, said_aloud, take_of, written

ROOT = Path(__file__).resolve().parents[2]


def run(*args, check=True):
    result = subprocess.run(
        [sys.executable, "-m", "turkish_lipsync", *args],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
    )
    if check:
        assert result.returncode == 0, result.stderr
    return result


def test_syllables_one_word_a_line():
    output = run("syllables", "merhaba", "tren", "strateji", "İSTANBUL").stdout.split()
    assert output == ["mer-ha-ba", "tren", "stra-te-ji", "is-tan-bul"]


def test_timeline_json_with_table_timing(tmp_path):
    source = tmp_path / "sample.jsml"
    source.write_text("<SENT><SURPRISED>merhaba</SURPRISED>, benim adım erdem</SENT>", encoding="utf-8")
    data = json.loads(run("timeline", str(source), "--timing", "table", "--format", "json").stdout)
    assert [p["letter"] for p in data["phones"]][:7] == list("merhaba")
    assert data["phones"][0]["viseme"] == "me" and data["phones"][0]["syllable"] == "mer"
    assert [w["text"] for w in data["words"]] == ["merhaba", "benim", "adım", "erdem"]
    assert data["emotions"][0]["emotion"] == "surprised"
    starts = [p["start"] for p in data["phones"]]
    assert starts == sorted(starts)


def test_timeline_tsv_lists_phones_words_and_emotions():
    lines = run("timeline", "--text", "<HAPPY>iyi günler</HAPPY>", "--timing", "table").stdout.splitlines()
    kinds = [line.split("\t")[0] for line in lines[2:]]
    assert kinds.count("phone") == 9 and kinds.count("word") == 2 and kinds.count("emotion") == 1


def test_errors_are_one_clear_line_and_a_non_zero_exit(tmp_path):
    result = run("timeline", "--text", "<SENT>merhaba", "--timing", "table", check=False)
    assert result.returncode != 0
    assert "Traceback" not in result.stderr
    assert result.stderr.startswith("error: ") and "line 1" in result.stderr
    missing = run("timeline", str(tmp_path / "none.jsml"), "--timing", "table", check=False)
    assert missing.returncode != 0 and "no such file" in missing.stderr


SCENE = "AYŞE (to ALİ): Merhaba Ali.\nALİ: Selam Ayşe, nasılsın?\n"


def test_timeline_of_a_script_prints_its_lines_and_each_speakers_timeline(tmp_path):
    source = tmp_path / "scene.txt"
    source.write_text(SCENE, encoding="utf-8")
    data = json.loads(run("timeline", str(source), "--timing", "table", "--format", "json").stdout)
    assert [(line["speaker"], line["addressee"]) for line in data["lines"]] == [
        ("Ayşe", "Ali"),
        ("Ali", "Ayşe"),
    ]
    assert data["lines"][0]["end"] < data["lines"][1]["start"]
    assert {w["text"] for w in data["speakers"]["Ali"]["words"]} == {"selam", "ayşe", "nasılsın"}
    tsv = run("timeline", str(source), "--timing", "table").stdout
    assert tsv.startswith("# scene\tlines 2\tspeakers 2") and "# speaker Ali\tvoice" in tsv


def test_export_of_a_script_writes_a_voice_or_a_file_per_character(tmp_path):
    source = tmp_path / "scene.txt"
    source.write_text(SCENE, encoding="utf-8")
    pgo = run("export", str(source), "--timing", "table", "--format", "papagayo-pgo").stdout.splitlines()
    assert pgo[4] == "2" and pgo[5] == "\tAyşe"
    run(
        "export",
        str(source),
        "--timing",
        "table",
        "--format",
        "rhubarb-tsv",
        "--out",
        str(tmp_path / "c.tsv"),
    )
    assert (tmp_path / "c_Ayşe.tsv").is_file() and (tmp_path / "c_Ali.tsv").is_file()


def test_a_hesitation_said_aloud_is_listed_with_the_recordings_timeline(tmp_path):
    """An "eee" a person says between two words of their take: the timeline lists it, with its shape."""
    audio = written(quiet_room(said_aloud(take_of(OTHER_TEXT), "eeeeee")), tmp_path / "take.wav")
    data = json.loads(run("timeline", "--text", OTHER_TEXT, "--audio", str(audio), "--format", "json").stdout)
    assert data["hesitations"] and {h["sound"] for h in data["hesitations"]} == {"e"}
    assert all(h["viseme"] == "e" and h["end"] - h["start"] > 0.3 for h in data["hesitations"])
    lines = run("timeline", "--text", OTHER_TEXT, "--audio", str(audio)).stdout.splitlines()
    assert [line.split("\t")[3] for line in lines if line.startswith("hesitation\t")] == ["e"] * len(
        data["hesitations"]
    )
