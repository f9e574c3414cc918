"""Scripts with speakers: JSML's VOICE elements and the screenplay form, read into the same lines."""

from __future__ import annotations

import pytest

from turkish_lipsync.core.base.errors import MarkupError
from turkish_lipsync.core.base.model import TextRun
from turkish_lipsync.core.text.script import CAMERA, display_name, read_script, speaker_key


def spoken(line) -> str:
    return "".join(item.text for item in line.items if isinstance(item, TextRun)).strip()


def test_voice_elements_are_lines_with_their_speakers_addressees_and_tags() -> None:
    script = read_script(
        '<VOICE NAME="Ayşe" GENDER="female" TO="Ali"><HAPPY>Merhaba</HAPPY> Ali!</VOICE>\n'
        '<BREAK TIME="1.5s"/>\n'
        '<VOICE NAME="ALİ" GENDER="male" OVERLAP="200ms">Selam Ayşe.</VOICE>\n'
        '<VOICE NAME="ayşe" TO="camera">Görüyor musunuz?</VOICE>'
    )
    assert [line.speaker for line in script.lines] == ["ayşe", "ali", "ayşe"]
    assert [(s.name, s.gender) for s in script.speakers] == [("Ayşe", "female"), ("ALİ", "male")]
    first, second, third = script.lines
    assert first.addressee == "ali" and third.addressee == CAMERA
    assert first.items[0].style.emotion == "happy"  # a line keeps every tag it has
    assert (
        second.pause_before == pytest.approx(1.5) and second.overlaps and second.overlap == pytest.approx(0.2)
    )
    assert script.addressees() == ("ali", "ayşe", CAMERA)  # unnamed: the last other speaker


def test_turkish_capitals_fold_to_one_speaker() -> None:
    assert speaker_key("İLKNUR") == speaker_key("İlknur") == "ilknur"
    assert speaker_key("IŞIL") == speaker_key("Işıl") == "ışıl"
    assert display_name("ŞÜKRÜ  ÇAĞLAR") == "Şükrü Çağlar"
    script = read_script("IŞIL: Günaydın.\nİLKNUR: Günaydın Işıl.\nIşıl: Nasılsın?")
    assert [line.speaker for line in script.lines] == ["ışıl", "ilknur", "ışıl"]
    assert [speaker.name for speaker in script.speakers] == ["Işıl", "İlknur"]


def test_screenplay_cues_notes_continuations_and_directions() -> None:
    script = read_script(
        "AYŞE (to ALİ, female): Merhaba Ali,\n"
        "nasılsın?\n"
        "(gülümser)\n"
        "ALİ (overlapping): İyiyim.\n"
        '<BREAK TIME="800ms"/>\n'
        "AYŞE (to camera): <SAD>Ben</SAD> değilim.\n"
    )
    first, second, third = script.lines
    assert spoken(first) == "Merhaba Ali,\nnasılsın?"  # the direction is not spoken
    assert first.addressee == "ali" and script.speaker("ayşe").gender == "female"
    assert second.overlaps and third.pause_before == pytest.approx(0.8)
    assert third.addressee == CAMERA and third.items[0].style.emotion == "sad"
    # Offsets point into the whole script.
    assert script.source[third.items[0].offsets[0]] == "B"


def test_plain_text_with_a_colon_is_still_one_speaker() -> None:
    assert read_script("Not: yarın okullar tatil.") is None
    assert read_script("Saat 10:30'da buluşalım.") is None
    assert read_script("<SENT>Merhaba</SENT>") is None
    assert read_script("AYŞE: Merhaba.") is not None  # one cue, but a name in capitals
    assert read_script("Ayşe: Merhaba.\nAli: Selam.") is not None  # two cues


def test_text_outside_voices_is_refused_where_it_is() -> None:
    with pytest.raises(MarkupError) as error:
        read_script('<VOICE NAME="Ayşe">Merhaba.</VOICE>\n  Kim bu?')
    assert (error.value.line, error.value.column) == (2, 3)
    assert "outside any <VOICE>" in str(error.value)


@pytest.mark.parametrize(
    ("source", "where", "says"),
    [
        ('<VOICE NAME="A"><VOICE NAME="B">x</VOICE></VOICE>', (1, 17), "inside another <VOICE>"),
        ('<VOICE GENDER="female">x</VOICE>', (1, 1), "needs the speaker's name"),
        ('<VOICE NAME="A" GENDER="robot">x</VOICE>', (1, 17), "GENDER='robot'"),
        ('<VOICE NAME="A" TO="Zeynep">Merhaba.</VOICE>', (1, 1), "who never speaks"),
        ("AYŞE: Merhaba.\nALİ (whispering): Selam.", (2, 6), "(whispering)"),
        ("AYŞE: Merhaba <HAPY>Ali</HAPY>.", (1, 15), "unknown tag <HAPY>"),
        (
            '<VOICE NAME="A" GENDER="female">x</VOICE><VOICE NAME="a" GENDER="male">y</VOICE>',
            (1, 42),
            "keeps",
        ),
    ],
)
def test_errors_say_what_and_where(source: str, where: tuple[int, int], says: str) -> None:
    with pytest.raises(MarkupError) as error:
        read_script(source)
    assert (error.value.line, error.value.column) == where
    assert says in str(error.value)


def test_first_line_addresses_the_next_speaker_and_a_monologue_the_camera() -> None:
    script = read_script("AYŞE: Merhaba.\nALİ: Selam.\nCAN: Ben de buradayım.")
    assert script.addressees() == ("ali", "ayşe", "ali")
    assert read_script("AYŞE: Merhaba.").addressees() == (CAMERA,)
