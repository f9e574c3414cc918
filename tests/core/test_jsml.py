"""JSML parsing: the thesis's emotion tags, standard JSML elements, source offsets and clear errors."""

from __future__ import annotations

import pytest

from turkish_lipsync.core.base.errors import MarkupError
from turkish_lipsync.core.base.model import Pause, Style, TextRun
from turkish_lipsync.core.text.jsml import parse_jsml, pause_seconds

THESIS_SAMPLE = (
    "<SENT>Animasyon programımız, <SAD>hüzün</SAD>\n"
    "<HAPPY>sevinç</HAPPY> <ANGER>sinir</ANGER> gibi duyguları aynı cümle\n"
    "içinde simüle edebilmektedir.</SENT>"
)


def runs(items) -> list[TextRun]:
    return [item for item in items if isinstance(item, TextRun)]


def test_plain_text_is_one_run_with_every_offset() -> None:
    source = "Merhaba, benim adım Erdem Akagündüz."
    (run,) = parse_jsml(source)
    assert run.text == source
    assert run.offsets == tuple(range(len(source)))
    assert run.style == Style()


def test_thesis_sample_of_5_2_5() -> None:
    items = parse_jsml(THESIS_SAMPLE)
    spoken = [(run.text.strip(), run.style.emotion) for run in runs(items)]
    assert spoken == [
        ("Animasyon programımız,", None),
        ("hüzün", "sad"),
        ("sevinç", "happy"),
        ("sinir", "angry"),
        ("gibi duyguları aynı cümle\niçinde simüle edebilmektedir.", None),
    ]
    assert isinstance(items[-1], Pause) and items[-1].kind == "sentence"
    assert items[-1].seconds == pause_seconds()["punctuation"]["sentence"]
    for run in runs(items):
        assert all(THESIS_SAMPLE[offset] == char for char, offset in zip(run.text, run.offsets, strict=True))


def test_appendix_c_sample() -> None:
    items = parse_jsml("<SENT><SURPRISED>merhaba</SURPRISED>, benim adım erdem</SENT>")
    assert [(run.text, run.style.emotion) for run in runs(items)] == [
        ("merhaba", "surprised"),
        (", benim adım erdem", None),
    ]


@pytest.mark.parametrize(
    ("tag", "emotion"),
    [
        ("ANGRY", "angry"),
        ("anger", "angry"),
        ("Afraid", "afraid"),
        ("FEAR", "afraid"),
        ("sad", "sad"),
        ("SADNESS", "sad"),
        ("happy", "happy"),
        ("HAPPINESS", "happy"),
        ("surprised", "surprised"),
        ("SURPRISE", "surprised"),
        ("disgusted", "disgusted"),
        ("Disgust", "disgusted"),
    ],
)
def test_emotion_tags_and_variant_spellings(tag: str, emotion: str) -> None:
    (run,) = parse_jsml(f"<{tag}>kızgınım</{tag.upper()}>")
    assert run.style.emotion == emotion
    assert run.style.emotion_weight == 1.0


def test_nested_emotions_inner_wins_and_outer_returns() -> None:
    items = parse_jsml("<HAPPY weight='0.4'>çok <SAD>üzgün</SAD> ama mutlu</HAPPY>")
    assert [(run.text, run.style.emotion, run.style.emotion_weight) for run in runs(items)] == [
        ("çok ", "happy", 0.4),
        ("üzgün", "sad", 1.0),
        (" ama mutlu", "happy", 0.4),
    ]


@pytest.mark.parametrize(("value", "weight"), [("0.5", 0.5), ("0", 0.0), ("1", 1.0), ("75%", 0.75)])
def test_emotion_weight(value: str, weight: float) -> None:
    (run,) = parse_jsml(f'<ANGRY WEIGHT="{value}">hayır</ANGRY>')
    assert run.style.emotion_weight == pytest.approx(weight)


def test_break_sizes_and_times() -> None:
    sizes = pause_seconds()["break_size"]
    items = parse_jsml(
        'a<BREAK MSECS="300"/>b<BREAK SIZE="large"/>c<break size=small>d<BREAK/>e<BREAK TIME="1.5s"/>'
        'f<BREAK TIME="250ms"></BREAK>g'
    )
    pauses = [(item.seconds, item.kind) for item in items if isinstance(item, Pause)]
    assert pauses == [
        (0.3, "break"),
        (sizes["large"], "break"),
        (sizes["small"], "break"),
        (sizes["medium"], "break"),
        (1.5, "break"),
        (0.25, "break"),
    ]
    assert [run.text for run in runs(items)] == list("abcdefg")
    assert items[1].offset == 1  # the pause points at its '<'


def test_sentence_and_paragraph_pauses() -> None:
    items = parse_jsml("<PARA><SENT>Bir.</SENT><SENT>İki</SENT></PARA>")
    kinds = [item.kind for item in items if isinstance(item, Pause)]
    assert kinds == ["sentence", "sentence", "paragraph"]


@pytest.mark.parametrize(
    ("attributes", "rate", "pitch", "volume"),
    [
        ('RATE="350"', 2.0, 1.0, 1.0),
        ('RATE="+20%"', 1.2, 1.0, 1.0),
        ('RATE="-10%"', 0.9, 1.0, 1.0),
        ('RATE="fast"', 1.25, 1.0, 1.0),
        ('RATE="xslow"', 0.6, 1.0, 1.0),
        ('RATE="default"', 1.0, 1.0, 1.0),
        ('PITCH="+50%" VOL="0.5"', 1.0, 1.5, 0.5),
        ('PITCH="high" VOL="loud"', 1.0, 1.15, 1.3),
        ('PITCH="240"', 1.0, 2.0, 1.0),
    ],
)
def test_prosody(attributes: str, rate: float, pitch: float, volume: float) -> None:
    (run,) = parse_jsml(f"<PROS {attributes}>yavaş</PROS>")
    assert (run.style.rate, run.style.pitch, run.style.volume) == pytest.approx((rate, pitch, volume))


def test_relative_prosody_is_relative_to_the_enclosing_element() -> None:
    items = parse_jsml('<PROS RATE="fast">a <PROS RATE="+20%">b</PROS></PROS>')
    assert [run.style.rate for run in runs(items)] == pytest.approx([1.25, 1.5])


def test_emphasis() -> None:
    items = parse_jsml('<EMP>çok</EMP> <EMP LEVEL="reduced">az</EMP> güzel')
    assert [(run.text, run.style.emphasis) for run in runs(items)] == [
        ("çok", True),
        ("az", False),
        (" güzel", False),
    ]


def test_entities_map_to_the_index_of_their_ampersand() -> None:
    source = "Ali &amp; Veli &lt;3 &#305;&#x15F;&quot;"
    (run,) = parse_jsml(source)
    assert run.text == 'Ali & Veli <3 ış"'
    assert run.offsets[4] == source.index("&amp;")
    assert run.offsets[run.text.index("ı")] == source.index("&#305;")
    assert run.offsets[run.text.index("ş")] == source.index("&#x15F;")


def test_comments_declaration_and_root_element_are_accepted() -> None:
    items = parse_jsml('<?xml version="1.0"?><!-- bir not --><JSML><SENT>Merhaba</SENT></JSML>')
    assert [run.text for run in runs(items)] == ["Merhaba"]


def test_empty_text_parses_to_nothing() -> None:
    assert parse_jsml("") == ()
    assert parse_jsml("<SENT> </SENT>") == (Pause(pause_seconds()["punctuation"]["sentence"], 7, "sentence"),)


@pytest.mark.parametrize(
    ("source", "line", "column", "message"),
    [
        ("<SENT>Merhaba", 1, 1, "never closed"),
        ("Bir\n  <SAD>iki", 2, 3, "never closed"),
        ("<SAD><HAPPY>a</SAD></HAPPY>", 1, 14, "crosses <HAPPY>"),
        ("metin\n<FOO>x</FOO>", 2, 1, "unknown tag <FOO>"),
        ("<SENT>x</SENT></SENT>", 1, 15, "closes nothing"),
        ('<BREAK MSECS="abc"/>', 1, 8, "MSECS"),
        ('<BREAK SIZE="huge"/>', 1, 8, "SIZE"),
        ('<BREAK TIME="3 hours"/>', 1, 8, "TIME"),
        ('<ANGRY WEIGHT="2">x</ANGRY>', 1, 8, "WEIGHT"),
        ('<ANGRY WEIGHT="much">x</ANGRY>', 1, 8, "WEIGHT"),
        ('<PROS RATE="warp">x</PROS>', 1, 7, "RATE"),
        ('<PROS VOL="-200%">x</PROS>', 1, 7, "VOL"),
        ('<EMP LEVEL="max">x</EMP>', 1, 6, "LEVEL"),
        ('<SAD COLOR="blue">x</SAD>', 1, 6, "no attribute COLOR"),
        ("<SAD WEIGHT>x</SAD>", 1, 6, "has no value"),
        ("3 < 4", 1, 3, "&lt;"),
        ("<SENT>Ali & Veli</SENT>", 1, 11, "&amp;"),
        ("&nbsp;", 1, 1, "unknown entity"),
        ("&#0;", 1, 1, "not a valid character"),
        ("<SENT", 1, 1, "not closed by '>'"),
        ("<!-- açık yorum", 1, 1, "comment"),
        ("<![CDATA[x]]>", 1, 1, "not supported"),
    ],
)
def test_malformed_markup_names_line_and_column(source: str, line: int, column: int, message: str) -> None:
    with pytest.raises(MarkupError) as caught:
        parse_jsml(source)
    error = caught.value
    assert (error.line, error.column) == (line, column), str(error)
    assert message in str(error)
    assert error.snippet and error.snippet in source
    assert f"line {line}, column {column}" in str(error)


def test_billion_laughs_is_refused_at_once() -> None:
    entities = "\n".join(
        f' <!ENTITY lol{n} "{("&lol" + str(n - 1) + ";") * 10 if n else "lol"}">' for n in range(10)
    )
    bomb = f'<?xml version="1.0"?>\n<!DOCTYPE lolz [\n{entities}\n]>\n<lolz>&lol9;</lolz>'
    with pytest.raises(MarkupError, match="DTDs and entity declarations are not allowed") as caught:
        parse_jsml(bomb)
    assert (caught.value.line, caught.value.column) == (2, 1)


def test_entity_declaration_alone_is_refused() -> None:
    with pytest.raises(MarkupError, match="DTDs and entity declarations are not allowed"):
        parse_jsml('Merhaba <!ENTITY x "y"> &x;')


def test_one_megabyte_of_markup_parses() -> None:
    sentence = "<SENT><HAPPY>Merhaba</HAPPY>, benim adım <EMP>Erdem</EMP> &amp; Ali.<BREAK/></SENT>\n"
    source = sentence * (1_000_000 // len(sentence) + 1)
    items = parse_jsml(source)
    assert len(source) > 1_000_000
    count = source.count("<SENT>")
    assert sum(isinstance(item, Pause) for item in items) == 2 * count
    assert sum(run.style.emotion == "happy" for run in runs(items)) == count
    last = runs(items)[-1]
    assert source[last.offsets[-1]] == last.text[-1]


def test_plain_text_may_use_a_bare_ampersand_but_markup_may_not():
    (run,) = [item for item in parse_jsml("Ali & Veli") if isinstance(item, TextRun)]
    assert run.text == "Ali & Veli"
    with pytest.raises(MarkupError, match="&amp;"):
        parse_jsml("<SENT>Ali & Veli</SENT>")
