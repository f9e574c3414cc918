"""KLettres' syllables in the languages the acoustic model may learn from, each with a Turkish spelling.

KDE's alphabet tutor (Debian `klettres-data`, GPL; unpacked by ../shared/voices/dev_voices.py into
people's `dev/packages`) has a native speaker of each language say short syllables and words. The five
languages of the dev voices (Russian, Tswana: trained on; Ukrainian, French, Czech: reported) are
lab/kit/people.py's; these are the others that have syllables and that the issue allows for training:
Malayalam (465 consonant-vowel syllables of one speaker: every consonant with every vowel), Lithuanian,
Low German, German, Danish, Dutch, Hebrew and English. KLettres' Hungarian, Spanish, Italian and Brazilian
Portuguese are kept for measuring only and are not read here.

Each spelling is what a Turkish reader would write for what is said (close, not exact): small languages
by hand, Lithuanian and Malayalam (its file names romanise each syllable) by a letter table.
"""

from __future__ import annotations

import re
from pathlib import Path

LANGUAGES = ("ml", "lt", "nds", "de", "da", "nl", "he", "en")

BY_NAME = {
    "de": {
        "AFFE": "afe", "AUCH": "auh", "BÄR": "ber", "BUS": "bus", "DEM": "dem", "DIE": "di", "DIR": "dir",
        "EIN": "ayn", "EULE": "oyle", "FISCH": "fiş", "FRAU": "frau", "FUß": "fus", "GUT": "gut",
        "HAUS": "haus", "HEU": "hoy", "HUND": "hunt", "IST": "ist", "JA": "ya", "KIND": "kint",
        "LISA": "liza", "NASE": "naze", "ÖL": "öl", "OPA": "opa", "PUTE": "pute", "REH": "re", "ROT": "rot",
        "SEIN": "zayn", "SITZ": "zits", "TÜR": "tür", "VOR": "for", "WAS": "vas", "WILL": "vil", "WO": "vo",
        "ZU": "tsu",
    },
    "nds": {
        "AAL": "al", "AL": "al", "ALL": "al", "BOOM": "bom", "CENT": "sent", "DEERT": "dert", "EER": "er",
        "EHR": "er", "EN": "en", "FÄHR": "fer", "GREEKSCH": "grekş", "HUUS": "hus", "IES": "is", "IK": "ik",
        "IMM": "im", "JÜST": "yüst", "KEERL": "kerl", "LEEF": "lef", "MUUR": "mur", "NAAM": "nam",
        "OCH": "oh", "OLL": "ol", "OOLT": "olt", "PANN": "pan", "QUEERN": "kvern", "REEG": "reg",
        "SACHTS": "zahts", "SCHIET": "şit", "TAACH": "tah", "UT": "ut", "UUL": "ul", "STUNN": "ştun",
        "VEEL": "fel", "VEEGTOORSCH": "fehtorş", "WAAG": "vah", "FIX": "fiks", "TYP": "tüp", "ZEEG": "tseg",
        "ÄTEN": "eten", "BÄÄR": "ber", "ÄNNERN": "enern", "ÖKO": "öko", "ÖÖL": "öl", "ÖLLER": "öler",
        "ÜM": "üm", "ÜNNER": "üner", "ÜÜTZ": "üts", "SPAAß": "şpas",
    },
    "da": {
        "AD": "ed", "BE": "be", "BÅ": "bo", "DA": "da", "DY": "dü", "EN": "en", "ER": "er", "ET": "et",
        "ES": "es", "FO": "fo", "GA": "ga", "HU": "hu", "HØ": "hö", "IN": "in", "LE": "le", "ME": "me",
        "MO": "mo", "MU": "mu", "NY": "nü", "OG": "ov", "OM": "om", "OP": "op", "RE": "re", "TE": "te",
        "UD": "ud", "VI": "vi", "VÆ": "ve", "ÅR": "or",
    },
    "nl": {
        "AA": "a", "AAN": "an", "AAP": "ap", "EE": "e", "EEN": "en", "EET": "et", "EI": "ey", "EN": "en",
        "EU": "ö", "IE": "i", "IK": "ik", "IN": "in", "IS": "is", "ME": "me", "OE": "u", "OM": "om",
        "OO": "o", "OOG": "oh", "OOM": "om", "OOR": "or", "OP": "op", "TE": "te", "UI": "öy", "UU": "ü",
        "UUR": "ür", "YS": "eys",
    },
    "he": {
        "אב": "av", "רק": "rak", "גם": "gam", "לא": "lo", "כן": "ken", "צח": "tsah", "לי": "li", "הר": "har",
        "נר": "ner", "חם": "ham", "קו": "kav", "בו": "bo", "בי": "bi", "כי": "ki", "די": "day", "סל": "sal",
        "יש": "yeş", "עד": "ad", "גר": "gar", "דג": "dag", "ים": "yam", "מי": "mi", "אף": "af", "קש": "kaş",
    },
    "en": {
        "AW": "o", "CAR": "kar", "DOG": "dog", "FIX": "fiks", "GAS": "ges", "GEM": "cem",
        "HOT": "hot", "JET": "cet", "KEY": "ki", "ME": "mi", "MY": "may", "NO": "nou", "PET": "pet",
        "SAW": "so", "SAY": "sey", "SIT": "sit", "SKY": "skay",
    },
}  # fmt: skip

LITHUANIAN = (
    ("c", "ts"), ("dž", "c"), ("ž", "j"), ("š", "ş"), ("č", "ç"), ("ė", "e"), ("y", "i"), ("ai", "ay"),
    ("ei", "ey"), ("ui", "uy"), ("j", "y"),
)  # fmt: skip

# Malayalam's file names romanise a consonant (doubled for the retroflex, h for the aspirate) and a vowel
# (doubled for long; ae the short e, ai and au the diphthongs, am the nasal, a final aha the visarga).
MALAYALAM = (
    ("aha", "ah"), ("cch", "ç"), ("ch", "ç"), ("nj", "ny"), ("jh", "c"), ("j", "c"), ("ng", "n"),
    ("nh", "n"), ("tth", "t"), ("tt", "t"), ("th", "t"), ("dhh", "d"), ("dh", "d"), ("dd", "d"),
    ("kh", "k"), ("gh", "g"), ("bh", "b"), ("ph", "f"), ("shsh", "ş"), ("sh", "ş"), ("zh", "r"),
    ("ll", "l"), ("rr", "r"), ("eae", "e"), ("ae", "e"), ("oooo", "o"), ("ooo", "o"), ("oo", "o"),
    ("aa", "a"), ("ii", "i"), ("ee", "i"), ("uu", "u"), ("ai", "ay"), ("au", "av"), ("ou", "av"),
)  # fmt: skip

TURKISH_VOWELS = set("aeıioöuü")


def spell(language: str, name: str, stem: str) -> str | None:
    """A Turkish spelling of one syllable (its name in sounds.xml, its file's stem), or None where there is
    none (a consonant said alone, a name the tables do not hold)."""
    if language in BY_NAME:
        spelt = BY_NAME[language].get(name)
    elif language == "lt":
        spelt = name.lower()
        for written, turkish in LITHUANIAN:
            spelt = spelt.replace(written, turkish)
    elif language == "ml":
        spelt = stem
        for written, turkish in MALAYALAM:
            spelt = spelt.replace(written, turkish)
    else:
        raise ValueError(f"no Turkish spelling for KLettres' language {language!r}")
    if spelt is None or not TURKISH_VOWELS & set(spelt) or re.search(r"[^a-zçğıöşü]", spelt):
        return None
    return spelt


def rows(klettres: Path) -> list[tuple[str, ...]]:
    """Manifest rows (kind, source, id, wav, text, turkish) of every syllable with a spelling, in order."""
    found = []
    for language in LANGUAGES:
        sounds = (klettres / language / "sounds.xml").read_text(encoding="utf-8")
        for name, file in re.findall(rf'name="([^"]+)"\s+file="({language}/syllab/[^"]+)"', sounds):
            path = klettres / file
            spelt = spell(language, name, path.stem)
            if spelt and path.exists():
                found.append(
                    ("syllable", f"klettres-{language}", f"{language}-{path.stem}", str(path), name, spelt)
                )
    return found
