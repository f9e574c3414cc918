"""`python -m turkish_lipsync normalize`: the spoken text of a script, without the engine or Blender."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def run(*arguments: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "turkish_lipsync", "normalize", *arguments],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
    )


def test_text_on_the_command_line() -> None:
    result = run("Toplantı", "09:00'da,", "bütçe 2.499,90 TL'ye çıktı.")
    assert result.returncode == 0, result.stderr
    assert (
        result.stdout == "toplantı dokuzda, bütçe iki bin dört yüz doksan dokuz lira doksan kuruşa çıktı.\n"
    )


def test_a_jsml_file(tmp_path: Path) -> None:
    script = tmp_path / "konuşma.jsml"
    script.write_text("<SENT>XIX. yüzyılda <HAPPY>Zeynep'e</HAPPY> ½ ekmek</SENT>\n\nSon.", encoding="utf-8")
    result = run("--file", str(script))
    assert result.returncode == 0, result.stderr
    assert result.stdout == "on dokuzuncu yüzyılda zeynebe yarım ekmek.\n\nson.\n"


def test_errors_say_what_is_wrong(tmp_path: Path) -> None:
    missing = run("--file", str(tmp_path / "yok.jsml"))
    assert missing.returncode == 2 and "no such file" in missing.stderr
    markup = run("<HAPPY>merhaba")
    assert markup.returncode == 2 and "never closed" in markup.stderr
