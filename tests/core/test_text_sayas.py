"""JSML SAYAS: a user overrides how any text is read, and the reading stays where the text was written."""

from __future__ import annotations

import pytest

from turkish_lipsync.core.base.errors import MarkupError
from turkish_lipsync.core.base.model import SpokenWord
from turkish_lipsync.core.text.jsml import parse_jsml
from turkish_lipsync.core.text.normalize import normalize


def words(source: str) -> list[SpokenWord]:
    return [item for item in normalize(parse_jsml(source)) if isinstance(item, SpokenWord)]


def test_sub_replaces_the_reading_and_points_into_the_written_text() -> None:
    source = 'Bilet <SAYAS SUB="on beş mart">15/03</SAYAS> tarihli.'
    result = words(source)
    assert [word.text for word in result] == ["bilet", "on", "beş", "mart", "tarihli"]
    written = range(source.index("15/03"), source.index("15/03") + len("15/03"))
    for word in result[1:4]:
        assert all(offset in written for offset in word.offsets)
    assert result[1].offsets[0] == written[0] and result[3].offsets[-1] == written[-1]


def test_sub_keeps_the_emotion_around_it() -> None:
    result = words('<HAPPY><SAYAS SUB="ahmet bey">A.B.</SAYAS></HAPPY> geldi')
    assert [(word.text, word.style.emotion) for word in result] == [
        ("ahmet", "happy"),
        ("bey", "happy"),
        ("geldi", None),
    ]


def test_without_sub_the_text_is_read_as_usual() -> None:
    assert [word.text for word in words('<SAYAS CLASS="date">15.03.2026</SAYAS>')] == [
        "on",
        "beş",
        "mart",
        "iki",
        "bin",
        "yirmi",
        "altı",
    ]


def test_literal_and_digits_spell_the_text() -> None:
    source = 'Kod <SAYAS CLASS="literal">AB12</SAYAS>, yıl <SAYAS CLASS="digits">2024</SAYAS>'
    assert [word.text for word in words(source)] == [
        "kod",
        "a",
        "be",
        "bir",
        "iki",
        "yıl",
        "iki",
        "sıfır",
        "iki",
        "dört",
    ]


@pytest.mark.parametrize(
    ("source", "message"),
    [
        ('<SAYAS SUB="">x</SAYAS>', "says nothing"),
        ('<SAYAS SUB="bir"><HAPPY>1</HAPPY></SAYAS>', "inside a <SAYAS>"),
        ('<SAYAS LANG="tr">x</SAYAS>', "has no attribute"),
    ],
)
def test_mistakes_are_refused_with_a_line_and_column(source: str, message: str) -> None:
    with pytest.raises(MarkupError, match=message):
        parse_jsml(source)
