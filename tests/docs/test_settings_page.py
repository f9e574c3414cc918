"""The manual's page of the settings of hearing a recording names every setting with its shipped value."""

import dataclasses
import re
from pathlib import Path

import pytest

from turkish_lipsync.core.speech.aligner_settings import AlignerSettings
from turkish_lipsync.core.speech.recognition.settings import RecogniserSettings
from turkish_lipsync.core.speech.speech_detector import DetectorSettings

PAGE = Path(__file__).resolve().parents[2] / "docs" / "developer" / "aligner-settings.md"


def table_rows(text: str) -> dict[str, float | str]:
    """Each setting of a table row (the backquoted names of its first cell, in order) -> the value in
    the same place of its value cell (a number, or a backquoted text)."""
    rows = {}
    for line in text.splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if line.startswith("|") and len(cells) >= 3:
            names = re.findall(r"`(\w+)`", cells[0])
            values = [
                quoted if number == "" else float(number.replace(",", "").replace("−", "-"))
                for quoted, number in re.findall(r"`([^`]*)`|(−?\d[\d,]*\.?\d*)", cells[1])
            ]
            rows.update(zip(names, values, strict=False))
    return rows


@pytest.mark.parametrize("settings", [AlignerSettings, RecogniserSettings, DetectorSettings])
def test_every_setting_is_on_the_page_with_its_value(settings):
    rows = table_rows(PAGE.read_text(encoding="utf-8"))
    for field in dataclasses.fields(settings):
        assert field.name in rows, f"{settings.__name__}.{field.name} is not on {PAGE.name} with a value"
        assert rows[field.name] == field.default, (
            f"{field.name}: page {rows[field.name]}, code {field.default}"
        )


def test_the_reader_finds_rows_and_their_values():
    rows = table_rows(
        "| setting | value | why |\n|---|---|---|\n| `a`, `b` | 1.0, 3,000 s | 2 |\n| `c` | −8.0 | |"
    )
    assert rows == {"a": 1.0, "b": 3000.0, "c": -8.0}
