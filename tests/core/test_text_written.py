"""Written forms read as a Turkish speaker reads them: dates, times, money, Roman numerals, fractions,
ranges, units, phone numbers, addresses, and the suffixes after them."""

from __future__ import annotations

import random

import pytest

from turkish_lipsync.core.base.errors import TextError
from turkish_lipsync.core.base.model import SpokenWord
from turkish_lipsync.core.text.jsml import parse_jsml
from turkish_lipsync.core.text.normalize import normalize, spoken_text, spoken_words
from turkish_lipsync.core.text.tables import TURKISH_LETTERS


def said(source: str) -> str:
    return " ".join(spoken_words(source))


def words(source: str) -> list[SpokenWord]:
    return [item for item in normalize(parse_jsml(source)) if isinstance(item, SpokenWord)]


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("15.03.2026", "on beş mart iki bin yirmi altı"),
        ("15/03/2026", "on beş mart iki bin yirmi altı"),
        ("2026-03-15", "on beş mart iki bin yirmi altı"),
        ("03-10-2026", "üç ekim iki bin yirmi altı"),
        ("29 Ekim 1923", "yirmi dokuz ekim bin dokuz yüz yirmi üç"),
        ("15.03.2026'da", "on beş mart iki bin yirmi altıda"),
        ("01.03.2026-05.03.2026", "bir mart iki bin yirmi altı ile beş mart iki bin yirmi altı"),
        ("31.13.2026", "otuz bir nokta on üç nokta iki bin yirmi altı"),  # no month 13: not a date
    ],
)
def test_dates(source: str, expected: str) -> None:
    assert said(source) == expected


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("09:30", "dokuz otuz"),
        ("09:00'da", "dokuzda"),
        ("14.30'da", "on dört otuzda"),
        ("saat 20.30", "saat yirmi otuz"),
        ("00:15", "sıfır sıfır on beş"),
        ("10:05", "on sıfır beş"),
        ("24:00'e kadar", "yirmi dörde kadar"),
        ("08:45'te", "sekiz kırk beşte"),
        ("10:00-12:00", "on ile on iki"),
        ("14:30-15:30 arası", "on dört otuz ile on beş otuz arası"),
        ("3.50 lira", "üç virgül elli lira"),  # a dot without a suffix or "saat" is a decimal
    ],
)
def test_times(source: str, expected: str) -> None:
    assert said(source) == expected


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("2.499,90 TL", "iki bin dört yüz doksan dokuz lira doksan kuruş"),
        ("1.250,50 ₺", "bin iki yüz elli lira elli kuruş"),
        ("100 TL'ye", "yüz liraya"),
        ("2.499,90 TL'ye", "iki bin dört yüz doksan dokuz lira doksan kuruşa"),
        ("$4.99", "dört dolar doksan dokuz sent"),
        ("€9,5", "dokuz avro elli sent"),
        ("£20", "yirmi sterlin"),
        ("0,75 TL", "yetmiş beş kuruş"),
        ("1,5 milyon TL", "bir virgül beş milyon lira"),
        ("1.000-2.000 TL", "bin ile iki bin lira"),
        ("45 €'ya", "kırk beş avroya"),
    ],
)
def test_money(source: str, expected: str) -> None:
    assert said(source) == expected


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("%18,5", "yüzde on sekiz virgül beş"),
        ("%10-20 indirim", "yüzde on ile yirmi indirim"),
        ("%1.250 arttı", "yüzde bin iki yüz elli arttı"),
        ("%52'si", "yüzde elli ikisi"),
        ("3.5 milyon", "üç virgül beş milyon"),
        ("3,14", "üç virgül on dört"),
        ("39,9334", "otuz dokuz virgül dokuz üç üç dört"),
        ("-12,5", "eksi on iki virgül beş"),
        ("1.2.3 sürümü", "bir nokta iki nokta üç sürümü"),
    ],
)
def test_percentages_and_decimals(source: str, expected: str) -> None:
    assert said(source) == expected


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("3. sınıf", "üçüncü sınıf"),
        ("12'nci madde", "on ikinci madde"),
        ("5'inci kat", "beşinci kat"),
        ("4'üncü", "dördüncü"),
        ("3-5. maddeler", "üçüncü ile beşinci maddeler"),
        ("XX. yüzyıl", "yirminci yüzyıl"),
        ("XIX. yüzyılda", "on dokuzuncu yüzyılda"),
        ("II. Abdülhamit", "ikinci abdülhamit"),
        ("IV. Murat", "dördüncü murat"),
        ("Sultan V. Mehmet", "sultan beşinci mehmet"),
        ("tahta III. Selim çıktı", "tahta üçüncü selim çıktı"),
        ("XXI yüzyıl", "yirmi birinci yüzyıl"),
        # Not numerals: an initial between names, words of capitals, a lone I, a numeral without a dot.
        ("Mehmet V. Delibaş", "mehmet ve delibaş"),
        ("VIP salon", "vıp salon"),
        ("Bu bir CD. Sonra", "bu bir ce de sonra"),
        ("GELDİ MI. Evet.", "geldi mı evet"),
        ("Bölüm IIII. kısım", "bölüm ıııı kısım"),
        ("Henry VIII geldi", "henry vııı geldi"),
    ],
)
def test_ordinals_and_roman_numerals(source: str, expected: str) -> None:
    assert said(source) == expected


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("1/2 kilo", "yarım kilo"),
        ("1/4 saat", "çeyrek saat"),
        ("3/4 oranında", "dörtte üç oranında"),
        ("2/3 çoğunluk", "üçte iki çoğunluk"),
        ("1/6", "altıda bir"),
        ("1/1000", "binde bir"),
        ("2 1/2 kilo", "iki buçuk kilo"),
        ("3 3/4 metre", "üç tam dörtte üç metre"),
        ("½ ekmek, 2½ saat", "yarım ekmek iki buçuk saat"),
        ("¾", "dörtte üç"),
        ("1/2'si", "yarısı"),
        ("1/2'sini", "yarısını"),
        ("1/4'ü", "çeyreği"),
        ("3/4'ü", "dörtte üçü"),
        ("2/3'ü", "üçte ikisi"),
        ("1/25.000 ölçekli", "yirmi beş binde bir ölçekli"),
        ("1:1000 ölçekli", "binde bir ölçekli"),
        ("No: 5/7", "numara beş bölü yedi"),
        ("Madde 5/2'ye göre", "madde beş bölü ikiye göre"),  # no fraction is one or more
        ("7/24 açık", "yedi yirmi dört açık"),
        ("15/03 tarihinde", "on beş mart tarihinde"),
    ],
)
def test_fractions(source: str, expected: str) -> None:
    assert said(source) == expected


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("3-5 kişi", "üç beş kişi"),
        ("Skor 3-1", "skor üç bir"),
        ("2020-2025 yılları", "iki bin yirmi ile iki bin yirmi beş yılları"),
        ("1-5 Haziran", "bir ile beş haziran"),
        ("10–20 dakika", "on yirmi dakika"),
        ("-5 derece", "eksi beş derece"),
    ],
)
def test_ranges_scores_and_negatives(source: str, expected: str) -> None:
    assert said(source) == expected


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("120 km/sa", "saatte yüz yirmi kilometre"),
        ("5 m/s", "saniyede beş metre"),
        ("85 m²", "seksen beş metrekare"),
        ("25°C", "yirmi beş derece"),
        ("-3 °C", "eksi üç derece"),
        ("38,5°C'ye", "otuz sekiz virgül beş dereceye"),
        ("750 g", "yedi yüz elli gram"),
        ("340 ha", "üç yüz kırk hektar"),
        ("12 da büyüklüğünde", "on iki dekar büyüklüğünde"),
        ("2 kg'lık", "iki kilogramlık"),
        ("10-20 km", "on yirmi kilometre"),
        ("39°56'12\"K", "otuz dokuz derece elli altı dakika on iki saniye kuzey"),
        ("±0,5 mm", "artı eksi sıfır virgül beş milimetre"),
        ("1920x1080 ekran", "bin dokuz yüz yirmi çarpı bin seksen ekran"),
        ("2 x 3 m oda", "iki çarpı üç metre oda"),
    ],
)
def test_units(source: str, expected: str) -> None:
    assert said(source) == expected


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("0212 555 44 33", "sıfır iki bir iki beş beş beş dört dört üç üç"),
        ("0212-555-44-33", "sıfır iki bir iki beş beş beş dört dört üç üç"),
        ("0 (312) 444 55 66", "sıfır üç bir iki dört dört dört beş beş altı altı"),
        ("+90 532 123 45 67", "artı dokuz sıfır beş üç iki bir iki üç dört beş altı yedi"),
        ("ali.veli@ornek.com.tr", "ali nokta veli et ornek nokta com nokta te re"),
        ("destek_2@site.org.", "destek alt çizgi iki et site nokta org"),
        ("https://www.ornek.gov.tr/harita", "ornek nokta gov nokta te re bölü harita"),
        ("https://ornek.com/rapor.pdf", "ornek nokta com bölü rapor nokta pe de fe"),
        ("ornek.com.tr adresine", "ornek nokta com nokta te re adresine"),
        ("https://x.com/İş", "iks nokta com bölü iş"),
        ("Oraya gittim.De ki", "oraya gittim de ki"),  # a capital after the dot: no address
    ],
)
def test_phone_numbers_and_addresses(source: str, expected: str) -> None:
    assert said(source) == expected


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("Zeynep'e", "zeynebe"),
        ("Tokat'a", "tokada"),
        ("Aralık'ın", "aralığın"),
        ("Mehmet'in", "mehmedin"),
        ("Tokat'ta", "tokatta"),  # before a consonant nothing softens
        ("Kurt'a", "kurta"),  # a name of one syllable keeps its consonant
        ("Fırat'a", "fırata"),  # listed in abbreviations.toml: it does not soften
        ("Facebook'a Microsoft'a", "facebooka microsofta"),  # written the foreign way: no softening
        ("dokuz'da 1923'te 4'ü 6'yı 10'dan", "dokuzda bin dokuz yüz yirmi üçte dördü altıyı ondan"),
        ("2020'deki 1990'daki", "iki bin yirmideki bin dokuz yüz doksandaki"),
        ("TBMM'de ABD'li", "te be me mede a be deli"),
        ("KDV'li fiyat", "katma değer vergisili fiyat"),
        ("Prof.'a ve km'ye", "profesöre ve kilometreye"),  # the suffix follows the abbreviation's reading
    ],
)
def test_suffixes_keep_harmony_and_soften(source: str, expected: str) -> None:
    assert said(source) == expected


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("Sn. Dr. Ayşe", "sayın doktor ayşe"),
        ("Doç. Dr. Ali ve Av. Can", "doçent doktor ali ve avukat can"),
        ("Atatürk Cad. No. 5", "atatürk caddesi numara beş"),
        ("Gül Sok. No: 3", "gül sokak numara üç"),
        ("Sipariş No: 2024-0153", "sipariş numara iki bin yirmi dört sıfır bir beş üç"),  # a code, no range
        ("Pzt. ve Cmt. 10.00'da", "pazartesi ve cumartesi onda"),
        ("MÖ 500 yılında", "milattan önce beş yüz yılında"),
        ("ABC Ltd. Şti.", "a be ce limitet şirketi"),
        ("Kaya San. ve Tic. A.Ş.", "kaya sanayi ve ticaret anonim şirketi"),
        ("Ankara Üniv. Tıp Fak.", "ankara üniversitesi tıp fakültesi"),
        ("XYZ A.Ş. merkezi", "iks ye ze anonim şirketi merkezi"),
        ("vb. şeyler", "ve benzeri şeyler"),
        ("AKP ve CHP", "a ka pe ve ce he pe"),
        ("THY", "te ha ye"),
        ("ĞÜŞ", "yumuşak ge ü şe"),
        ("ASELSAN ve TÜRKSAT", "aselsan ve türksat"),
        ("%18 KDV", "yüzde on sekiz katma değer vergisi"),
    ],
)
def test_abbreviations_and_acronyms(source: str, expected: str) -> None:
    assert said(source) == expected


@pytest.mark.parametrize(
    "source",
    [
        "Toplantı 09:00'da, bütçenin 3/4'ü ve 2.499,90 TL'ye XIX. yüzyılda Zeynep'e 120 km/sa hızla.",
        "ali.veli@ornek.com.tr 0212 555 44 33 15.03.2026-16.03.2026 %10-20 ½ 39°56'12\"K",
    ],
)
def test_every_letter_points_into_what_it_reads(source: str) -> None:
    """Readings sit on the characters they read: number words on digits or signs, suffix letters on the
    suffix, a name's letters on the name; nothing points outside the source or into spaces."""
    for word in words(source):
        assert len(word.offsets) == len(word.text)
        assert all(0 <= offset < len(source) and not source[offset].isspace() for offset in word.offsets), (
            word
        )


def test_suffix_letters_sit_on_the_suffix() -> None:
    source = "Toplantı 09:00'da, bütçenin 2.499,90 TL'ye Zeynep'e gitti."
    suffixed = {word.text: word for word in words(source)}
    dokuzda = suffixed["dokuzda"]
    assert source[dokuzda.offsets[0]] == "9" and source[dokuzda.offsets[-2] : dokuzda.offsets[-1] + 1] == "da"
    assert [source[offset] for offset in suffixed["zeynebe"].offsets] == list("Zeynepe")
    assert source[suffixed["kuruşa"].offsets[-1]] == "e"  # the harmonised a sits on the written e


def test_emotion_spans_keep_their_readings() -> None:
    items = words("<HAPPY>Toplantı 09:00'da</HAPPY> başlar, <SAD>2.499,90 TL</SAD> ödendi.")
    assert [(word.text, word.style.emotion) for word in items] == [
        ("toplantı", "happy"),
        ("dokuzda", "happy"),
        ("başlar", None),
        ("iki", "sad"),
        ("bin", "sad"),
        ("dört", "sad"),
        ("yüz", "sad"),
        ("doksan", "sad"),
        ("dokuz", "sad"),
        ("lira", "sad"),
        ("doksan", "sad"),
        ("kuruş", "sad"),
        ("ödendi", None),
    ]


def test_spoken_text_shows_the_pauses() -> None:
    assert spoken_text("Toplantı 09:30'da, salonda.\n\nSonra çay.") == (
        "toplantı dokuz otuzda, salonda.\n\nsonra çay."
    )


def test_any_mix_of_digits_signs_and_words_gives_turkish_letters_at_real_indices() -> None:
    """Seeded random texts made of the pieces the readers look for: no crash, only Turkish letters, every
    letter at an index of the source."""
    pieces = [*"0123456789" * 3, *".,:/-–%$€₺£½¾°'’ ²@_+", "TL", "km", "XX", "II", "V", "I", "Zeynep", "da"]
    pieces += ["'da", "'ye", "'si", "'ü", "www.", "https://", "com", "tr", "No:", "saat ", "\n", "K", "°C"]
    pieces += ["m²", "km/sa", "Mart", "yüzyıl", "Sultan ", "KDV", "THY", "ı", "İ", "Ğ"]
    generator = random.Random(12)
    for _ in range(3000):
        source = "".join(generator.choice(pieces) for _ in range(generator.randint(1, 14)))
        try:
            result = words(source)
        except TextError:
            continue  # nothing to speak
        for word in result:
            assert word.text and set(word.text) <= TURKISH_LETTERS, (source, word)
            assert len(word.offsets) == len(word.text), (source, word)
            assert all(0 <= offset < len(source) for offset in word.offsets), (source, word)


def test_the_timeline_speaks_the_normalised_words_with_their_visemes() -> None:
    """What the normaliser reads is what the timeline times and the visemes shape (table timing, no engine):
    the softened b of "zeynebe" sits on the written p and closes the lips."""
    from turkish_lipsync.core.base.visemes import BILABIAL_VISEMES
    from turkish_lipsync.core.pipeline import LipSyncOptions, lip_sync

    source = "Toplantı 09:00'da, bilet 2.499,90 TL'ye; XIX. yüzyılda Zeynep'e ½ ekmek."
    result = lip_sync(source, LipSyncOptions(timing="table"))
    assert [word.text for word in result.timeline.words] == spoken_words(source)
    utterance = result.utterance
    word = next(word for word in utterance.words if word.text == "zeynebe")
    letters = utterance.letters[word.first_letter : word.first_letter + word.letter_count]
    assert [source[letter.offset] for letter in letters] == list("Zeynepe")
    assert letters[5].char == "b" and letters[5].viseme in BILABIAL_VISEMES
