"""An episode's folder and its episode.toml read into scenes: each scene's scripts/render.py arguments, and
every mistake found at once, each with its file and line."""

import wave
from pathlib import Path

import pytest

from turkish_lipsync.core.farm.manifest import EpisodeError, key_lines, known_variants, read_episode

CUBE = "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n"
CONVERSATION = "AYŞE: Merhaba Ali!\nALİ: Merhaba Ayşe.\n"


def _episode(folder: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    return folder


def _take(path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with wave.open(str(path), "wb") as take:
        take.setnchannels(1)
        take.setsampwidth(2)
        take.setframerate(16000)
        take.writeframes(b"\0\0" * 1600)


def _problems(folder: Path) -> list[str]:
    with pytest.raises(EpisodeError) as raised:
        read_episode([folder])
    return list(raised.value.problems)


def test_a_folder_without_a_manifest_is_its_scene_files_in_name_order_with_the_defaults(tmp_path):
    _episode(tmp_path, {"02-yol.jsml": "Ama baba.", "01-kafe.txt": CONVERSATION, "notlar.md": "not a scene"})
    episode = read_episode([tmp_path])
    assert [scene.name for scene in episode.scenes] == ["01-kafe", "02-yol"]
    assert episode.title == tmp_path.name and episode.manifest is None
    kafe, yol = episode.scenes
    assert kafe.script is not None and [s.name for s in kafe.script.speakers] == ["Ayşe", "Ali"]
    assert yol.script is None
    assert kafe.arguments == (
        "--jsml",
        str(tmp_path / "01-kafe.txt"),
        "--fps",
        "25",
        "--resolution",
        "960x540",
    )


def test_defaults_and_a_scenes_own_settings_become_its_render_arguments(tmp_path):
    _episode(
        tmp_path,
        {
            "01-kafe.txt": CONVERSATION,
            "02-yol.jsml": "Ama baba.",
            "heads/ayse.obj": CUBE,
            "heads/ali.obj": CUBE,
            "heads/yol.obj": CUBE,
            "episode.toml": """
[episode]
title = "Bölüm 1"
fps = 29.97
resolution = "64x36"
samples = 2
chunk_size = 10

[defaults]
timing = "word"
gaze = false
cast."Ayşe" = "heads/ayse.obj"
cast."Mehmet" = "default"   # the series' other characters: left out where they do not speak

[scene."01-kafe"]
cast."ALİ" = "heads/ali.obj"
voice = { "Ali" = "m7:0.9:1.05" }
audio = "takes/kafe.wav"

[scene."02-yol"]
head = "heads/yol.obj"
rate = 1.2
""",
        },
    )
    _take(tmp_path / "takes" / "kafe.wav")
    episode = read_episode([tmp_path / "episode.toml"])
    assert episode.title == "Bölüm 1" and episode.render.resolution == (64, 36)
    assert (episode.render.fps, episode.render.samples, episode.render.chunk_size) == (29.97, 2, 10)
    kafe, yol = episode.scenes
    assert kafe.arguments[6:] == (
        "--timing", "word", "--no-gaze",
        "--cast", f"Ayşe={tmp_path / 'heads/ayse.obj'}", "--cast", f"ALİ={tmp_path / 'heads/ali.obj'}",
        "--voice", "Ali=m7:0.9:1.05", "--audio", str(tmp_path / "takes/kafe.wav"),
    )  # fmt: skip
    assert set(kafe.inputs) == {
        tmp_path / p for p in ("01-kafe.txt", "heads/ayse.obj", "heads/ali.obj", "takes/kafe.wav")
    }
    assert yol.arguments[6:] == (
        "--timing",
        "word",
        "--no-gaze",
        "--head",
        str(tmp_path / "heads/yol.obj"),
        "--rate",
        "1.2",
    )
    assert kafe.where == f"{tmp_path / 'episode.toml'}:15" and yol.where == f"{tmp_path / 'episode.toml'}:20"


def test_every_mistake_is_listed_with_its_line(tmp_path):
    _episode(
        tmp_path,
        {
            "01-kafe.txt": CONVERSATION,
            "02-yol.jsml": "Ama baba.",
            "heads/a.obj": CUBE,
            "episode.toml": """[episode]
fps = 300
engine = "octane"
chunk_size = 500
frames = 3

[defaults]
timing = "phones"
cast."Ayşe" = "heads/missing.glb"
smile = 2

[scene."01-kafe"]
head = "heads/a.obj"
voice = { Ayse = "m9" }

[scene."02-yol"]
cast.Ali = "default"
rate = 9

[scene."03-yok"]
audio = "x.wav"
""",
        },
    )
    toml = tmp_path / "episode.toml"
    assert _problems(tmp_path) == [
        f"{toml}:2: fps must be a number from 1 to 240",
        f"{toml}:3: engine must be one of CYCLES, EEVEE, WORKBENCH",
        f"{toml}:4: chunk_size must be a number from 1 to 150",
        f"{toml}:5: frames is not a setting of [episode]; they are title, scenes, fps, resolution, engine, "
        "samples, chunk_size",
        f"{toml}:8: timing must be one of phone, word, table",
        f"{toml}:9: cast.Ayşe heads/missing.glb: no such file beside episode.toml",
        f"{toml}:10: smile is not a setting of a scene; the settings are audio, blink_amount, blinks, cast, "
        "cues, emotion_strength, expression, expression_amount, gaze, gaze_amount, head, head_amount, "
        "head_motion, interpolation, line_audio, mapping, motion, rate, seed, speaker_audio, "
        "speaker_emotion, timing, voice",
        f"{toml}:13: head does not fit scene 01-kafe: it is a script with speakers: give their heads with "
        "cast",
        f"{toml}:14: voice.Ayse must be one of "
        + ", ".join(known_variants())
        + ", female or male, optionally :PITCH:RATE",
        f"{toml}:14: voice.Ayse: Ayse does not speak in 01-kafe.txt; its speakers are Ayşe, Ali",
        f"{toml}:17: cast does not fit scene 02-yol: it is one head's text",
        f"{toml}:18: rate must be a number from 0.25 to 4",
        f'{toml}:20: [scene."03-yok"] names no scene of the episode; its scenes are 01-kafe, 02-yol',
    ]


def test_a_scripts_markup_error_names_its_line_and_column(tmp_path):
    _episode(tmp_path, {"01-kafe.txt": CONVERSATION, "02-yol.jsml": "<SENT>Ama\n<HAPPY>baba.</SENT>"})
    (problem,) = _problems(tmp_path)
    assert problem.startswith(f"{tmp_path / '02-yol.jsml'}:2:13: </SENT> crosses <HAPPY>")


def test_toml_that_does_not_parse_names_its_line_and_says_how_to_write_a_turkish_name(tmp_path):
    _episode(tmp_path, {"01-kafe.txt": CONVERSATION, "episode.toml": '[defaults]\ncast.Ayşe = "default"\n'})
    (problem,) = _problems(tmp_path)
    assert problem.startswith(f"{tmp_path / 'episode.toml'}:2:")
    assert 'a name with Turkish letters is written in quotes: "Ayşe"' in problem


def test_scenes_are_chosen_by_the_manifest_or_the_files_given(tmp_path):
    _episode(
        tmp_path,
        {
            "a.txt": CONVERSATION,
            "b.jsml": "Ama baba.",
            "c.jsml": "Baba.",
            "episode.toml": '[episode]\nscenes = ["c.jsml", "a.txt"]\n',
        },
    )
    assert [scene.name for scene in read_episode([tmp_path]).scenes] == ["c", "a"]
    assert [scene.name for scene in read_episode([tmp_path / "b.jsml"]).scenes] == ["b"]
    (tmp_path / "episode.toml").write_text('[episode]\nscenes = ["a.txt", "d.txt"]\n', encoding="utf-8")
    assert _problems(tmp_path) == [
        f"{tmp_path / 'episode.toml'}:2: scenes: d.txt: no such file beside episode.toml"
    ]


def test_one_scene_is_read_alone_whatever_another_scenes_file_holds(tmp_path):
    """A farm builds each scene from the episode's folder: another scene's broken file stops only its own."""
    _episode(tmp_path, {"01-kafe.txt": CONVERSATION, "02-yol.jsml": "<SENT>Ama baba."})
    (scene,) = read_episode([tmp_path], only="01-kafe").scenes
    assert scene.name == "01-kafe"
    with pytest.raises(EpisodeError, match="02-yol.jsml:1:1"):
        read_episode([tmp_path], only="02-yol")
    with pytest.raises(EpisodeError, match="no scene '03-yok'; its scenes are 01-kafe"):
        read_episode([tmp_path], only="03-yok")


def test_two_files_of_one_name_or_a_name_a_step_cannot_carry_are_refused(tmp_path):
    _episode(tmp_path, {"a.txt": CONVERSATION, "a.jsml": "Baba.", "b{1}.jsml": "Baba."})
    problems = _problems(tmp_path)
    assert any("a.jsml and a.txt are both scene a" in problem for problem in problems)
    assert any(
        "b{1}.jsml: a scene's name" in problem and "rename the file" in problem for problem in problems
    )


def test_key_lines_point_at_headers_assignments_and_inline_tables():
    text = '[episode]\ntitle = "x"\n\n[scene."01 kafe"]\n'
    text += 'cast = { "Ayşe" = "a.glb", Ali = "b" }\nvoice.Ali = "m7"\n'
    lines = key_lines(text)
    assert lines[("episode",)] == 1 and lines[("episode", "title")] == 2
    assert lines[("scene", "01 kafe")] == 4
    assert lines[("scene", "01 kafe", "cast", "Ayşe")] == lines[("scene", "01 kafe", "cast", "Ali")] == 5
    assert lines[("scene", "01 kafe", "voice", "Ali")] == 6


def test_the_example_episode_reads_as_two_scenes():
    episode = read_episode([Path(__file__).resolve().parents[2] / "examples" / "episode"])
    assert episode.title == "Kafede" and [scene.name for scene in episode.scenes] == ["01-kafe", "02-mektup"]
    kafe, mektup = episode.scenes
    assert "--voice" in kafe.arguments and "--voice" not in mektup.arguments  # only where Ali speaks
    assert mektup.arguments[-4:] == ("--rate", "0.9", "--expression-amount", "1.3")
