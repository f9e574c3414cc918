"""Turkish text normalisation: casing, numbers, abbreviations, foreign letters, pauses and source links."""

from __future__ import annotations

import pytest

from turkish_lipsync.core.base.errors import TextError
from turkish_lipsync.core.base.model import Pause, SpokenWord
from turkish_lipsync.core.text.jsml import parse_jsml, pause_seconds
from turkish_lipsync.core.text.normalize import TURKISH_LETTERS, normalize, turkish_lower, turkish_upper


def spoken(source: str) -> str:
    """The normalised text: words joined by spaces, pauses as '|'."""
    return " ".join("|" if isinstance(item, Pause) else item.text for item in normalize(parse_jsml(source)))


def words(source: str) -> list[SpokenWord]:
    return [item for item in normalize(parse_jsml(source)) if isinstance(item, SpokenWord)]


def test_thesis_example_sentence() -> None:
    source = "Merhaba, benim adım Erdem Akagündüz."
    items = normalize(parse_jsml(source))
    assert spoken(source) == "merhaba | benim adım erdem akagündüz |"
    comma, stop = (item for item in items if isinstance(item, Pause))
    assert (comma.kind, comma.seconds, comma.offset) == ("comma", pause_seconds()["punctuation"]["comma"], 7)
    assert (stop.kind, stop.offset) == ("sentence", len(source) - 1)
    for word in words(source):
        assert "".join(turkish_lower(source[offset]) for offset in word.offsets) == word.text


def test_thesis_jsml_sample_keeps_emotions_and_pauses_once() -> None:
    source = (
        "<SENT>Animasyon programımız, <SAD>hüzün</SAD> <HAPPY>sevinç</HAPPY> <ANGER>sinir</ANGER> gibi "
        "duyguları aynı cümle içinde simüle edebilmektedir.</SENT>"
    )
    items = normalize(parse_jsml(source))
    assert [(word.text, word.style.emotion) for word in items if isinstance(word, SpokenWord)][:5] == [
        ("animasyon", None),
        ("programımız", None),
        ("hüzün", "sad"),
        ("sevinç", "happy"),
        ("sinir", "angry"),
    ]
    # The final '.' and </SENT> make one pause, not two.
    assert isinstance(items[-1], Pause) and not isinstance(items[-2], Pause)


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("IĞDIR ISPARTA ılık", "ığdır ısparta ılık"),
        ("İzmir İSTANBUL", "izmir istanbul"),
        ("I\u0307stanbul", "istanbul"),  # decomposed İ
        ("i\u0307stanbul", "istanbul"),  # what Python's "İ".lower() gives
        ("S\u0327ener", "şener"),  # decomposed ş
        ("kâğıt hâlâ îmâ Kûr", "kağıt hala ima kur"),
        ("Ankara'ya Türkiye’nin İstanbul'dan", "ankaraya türkiyenin istanbuldan"),
    ],
)
def test_turkish_casing_and_marks(source: str, expected: str) -> None:
    assert spoken(source) == expected


def test_every_letter_links_to_its_source_letter() -> None:
    source = "Kâğıt I\u0307stanbul'da İZMİR"
    result = words(source)
    assert [word.text for word in result] == ["kağıt", "istanbulda", "izmir"]
    assert result[0].offsets == (0, 1, 2, 3, 4)
    assert result[1].offsets[0] == 6  # the I of I + U+0307
    assert result[1].offsets[1] == 8  # the s after the combining dot
    assert source[result[1].offsets[-2]] == "d"  # the apostrophe is skipped
    assert result[2].offsets == tuple(range(len(source) - 5, len(source)))


def test_turkish_lower_and_upper() -> None:
    assert turkish_lower("IIİi DİYARBAKIR") == "ııii diyarbakır"
    assert turkish_upper("ıiIİ diyarbakır") == "IİIİ DİYARBAKIR"


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("2024", "iki bin yirmi dört"),
        ("0", "sıfır"),
        ("1", "bir"),
        ("100 1000 1001", "yüz bin bin bir"),
        ("111", "yüz on bir"),
        ("2000000", "iki milyon"),
        ("1.000.000", "bir milyon"),
        ("1234567890", "bir milyar iki yüz otuz dört milyon beş yüz altmış yedi bin sekiz yüz doksan"),
        ("1000000000000000", "bir katrilyon"),
        ("007", "sıfır sıfır yedi"),
        ("3,5", "üç virgül beş"),
        ("3.5", "üç virgül beş"),  # a decimal point is said "virgül", as Turkish says decimals
        ("3,05", "üç virgül sıfır beş"),
        ("1.250,75", "bin iki yüz elli virgül yetmiş beş"),
        ("%25", "yüzde yirmi beş"),
        ("25%", "yüzde yirmi beş"),
        ("-5 derece", "eksi beş derece"),
        ("Hava −3", "hava eksi üç"),
        ("3. sınıf", "üçüncü sınıf"),
        ("4. kat 1. sıra 6. gün 9. ay 10. yıl 20. yüzyıl", None),
        ("Sonuç 3.", "sonuç üç |"),
        ("Sıra 3. Sonra", "sıra üç | sonra"),
        ("3. Ekim", "üçüncü ekim"),
        # A number opening a sentence before any word is an ordinal (a sentence is rarely just "1.").
        ("1. Dünya Savaşı", "birinci dünya savaşı"),
        ("Bitti. 2. Madde", "bitti | ikinci madde"),
        ("2024'te 1990'larda", "iki bin yirmi dörtte bin dokuz yüz doksanlarda"),
        ("saat 14:30", "saat on dört otuz"),
        ("25.12.2023", "yirmi beş aralık iki bin yirmi üç"),
        ("192.168.1.1", "yüz doksan iki nokta yüz altmış sekiz nokta bir nokta bir"),
        ("1/2", "yarım"),
        ("$5 ve 10€", "beş dolar ve on avro"),
        ("5 km 3 kg 10 cm 2 m", "beş kilometre üç kilogram on santimetre iki metre"),
        ("5km'den", "beş kilometreden"),
    ],
)
def test_numbers(source: str, expected: str | None) -> None:
    if expected is None:
        assert (
            spoken(source) == "dördüncü kat birinci sıra altıncı gün dokuzuncu ay onuncu yıl yirminci yüzyıl"
        )
    else:
        assert spoken(source) == expected


def test_huge_number_is_read_digit_by_digit() -> None:
    result = spoken("9" * 60)
    assert result == " ".join(["dokuz"] * 60)


def test_number_words_point_into_their_digits() -> None:
    source = "Yıl 2024, oran %25."
    for word in words(source)[1:]:
        if word.text in ("oran",):
            continue
        assert all(source[offset] in "0123456789%" for offset in word.offsets), word
    two_thousand = words(source)[1:4]  # iki bin yirmi dört: iki, bin at the first 2, yirmi at the 2nd 2
    assert [word.text for word in two_thousand] == ["iki", "bin", "yirmi"]
    assert two_thousand[0].offsets[0] == 4
    assert two_thousand[2].offsets[0] == 6
    assert words(source)[4].offsets[0] == 7  # dört at the 4
    assert words(source)[6].offsets[0] == source.index("%")  # yüzde at the percent sign


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("Dr. Ahmet geldi", "doktor ahmet geldi"),
        ("Prof. Dr. Ayşe", "profesör doktor ayşe"),
        ("elma, armut vb. meyveler", "elma | armut ve benzeri meyveler"),
        ("kalem, silgi vs. Sonra", "kalem | silgi vesaire | sonra"),
        ("T.C. Merkez Bankası", "te ce merkez bankası"),
        ("bkz. sayfa", "bakınız sayfa"),
        ("örn. elma", "örneğin elma"),
        ("No. 5", "numara beş"),
        ("St. Petersburg", "sent petersburg"),
        ("TBMM", "te be me me"),
        ("ABD ve TBMM'de", "a be de ve te be me mede"),
        ("THY ile AKP", "te ha ye ile a ka pe"),
        ("NATO ve ODTÜ", "nato ve odtü"),
        ("Merhaba dünya", "merhaba dünya"),
        ("B planı", "be planı"),
        ("DİKKAT BU ALAN TEHLİKELİ OLABİLİR", "dikkat bu alan tehlikeli olabilir"),
        ("İYİ GÜNLER", "iyi günler"),
        ("MEB ve YÖK, DNA ile AVM", "meb ve yök | de ne a ile a ve me"),
        ("AB'ye", "a beye"),
    ],
)
def test_abbreviations_and_acronyms(source: str, expected: str) -> None:
    assert spoken(source) == expected


def test_acronym_letter_names_point_at_their_letters() -> None:
    source = "TBMM'de"
    result = words(source)
    assert [word.text for word in result] == ["te", "be", "me", "mede"]
    assert [word.offsets[0] for word in result] == [0, 1, 2, 3]
    assert result[-1].offsets == (3, 3, 5, 6)


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("Qatar", "katar"),
        ("Wagner", "vagner"),
        ("Xerox", "kseroks"),
        ("Café Noël", "cafe noel"),
        ("Mädchen", "medchen"),
        ("Straße", "strasse"),
        ("Øresund", "öresund"),
        ("Łódź", "lodz"),
    ],
)
def test_letters_outside_the_turkish_alphabet(source: str, expected: str) -> None:
    assert spoken(source) == expected


def test_punctuation_becomes_pauses() -> None:
    """Each mark pauses as a reader does: a breath at a comma, longer at a clause, a stop at a sentence end,
    the longest at a paragraph; "..." followed by a blank line is one pause, not two."""
    items = normalize(parse_jsml("Bir, iki; üç: dört. Beş? Altı! Yedi...\n\nSekiz — dokuz"))
    pauses = [(item.kind, item.seconds) for item in items if isinstance(item, Pause)]
    kinds = [kind for kind, _ in pauses]
    assert kinds == [
        "comma",
        "clause",
        "clause",
        "sentence",
        "question",
        "exclamation",
        "paragraph",
        "clause",
    ]
    seconds = dict(pauses)
    assert 0.1 <= seconds["comma"] < seconds["clause"] < seconds["sentence"] < seconds["paragraph"] <= 1.5
    assert seconds["question"] == seconds["exclamation"] == seconds["sentence"]
    words = [item.text for item in items if isinstance(item, SpokenWord)]
    assert words == ["bir", "iki", "üç", "dört", "beş", "altı", "yedi", "sekiz", "dokuz"]


def test_hyphens_split_words_without_a_pause() -> None:
    assert (
        spoken("Kuzey-Güney hattı, 2023-2024")
        == "kuzey güney hattı | iki bin yirmi üç ile iki bin yirmi dört"
    )


def test_emoji_and_symbols_are_dropped() -> None:
    assert spoken("Merhaba 😀👍🏽 dünya ✓ ★ © (tamam) «evet»") == "merhaba dünya tamam evet"
    assert spoken("Ali &amp; Veli") == "ali ve veli"


def test_other_scripts_are_dropped_not_crashed() -> None:
    assert spoken("Merhaba Привет 你好 dünya") == "merhaba dünya"


@pytest.mark.parametrize("source", ["", "   \n ", "😀🎉", "<SENT></SENT>", "...!?", "<BREAK/>", "Привет"])
def test_nothing_to_speak(source: str) -> None:
    with pytest.raises(TextError, match="nothing to speak"):
        normalize(parse_jsml(source))


def test_only_turkish_letters_remain() -> None:
    source = "Çağrı'nın №5 café'si — 3½ kg ÆØÅ, q̃ ŵ x̂ ʻokina ǅ ﬁ ① ²³ Ⅻ ‰ «İĞÜŞÖÇ»"
    for word in words(source):
        assert word.text and set(word.text) <= TURKISH_LETTERS, word
        assert len(word.offsets) == len(word.text)
        assert all(0 <= offset < len(source) for offset in word.offsets)


def test_one_megabyte_of_text() -> None:
    sentence = "Merhaba, benim adım Erdem Akagündüz; 2024 yılında %25 daha hızlı konuştum! "
    source = sentence * (1_000_000 // len(sentence) + 1)
    items = normalize(parse_jsml(source))
    per_sentence = len(words(sentence))
    assert sum(isinstance(item, SpokenWord) for item in items) == per_sentence * source.count("Merhaba")
    last = [item for item in items if isinstance(item, SpokenWord)][-1]
    assert last.text == "konuştum" and source[last.offsets[0]] == "k"
