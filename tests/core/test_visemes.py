import pytest

from turkish_lipsync.core.base.errors import DataError
from turkish_lipsync.core.base.visemes import viseme_names
from turkish_lipsync.core.text.utterance import build_utterance
from turkish_lipsync.core.text.visemes import viseme_for_letter

THESIS_MODELS = (
    "a bpa cjae dta fvae gkya la ma na ra sza ta e bpe dte gkye le me ne re sze"
    " I Ii o bpo cjo do fvo gkyo lo mo no ro szto oi u neutral"
).split()


def test_the_37_models_in_the_thesis_numbering():
    assert viseme_names() == tuple(THESIS_MODELS)


def test_table_5_2_merhaba_benim_adim_erdem():
    # Table 5.2 lists one model per letter; its "da.obj" is the table's typo for dta.obj.
    expected = "me e re a a bpa a bpe e ne Ii me a dta I ma e re dte e me".split()
    utterance = build_utterance("Merhaba, benim adım Erdem.")
    assert "".join(letter.char for letter in utterance.letters) == "merhababenimadımerdem"
    assert [letter.viseme for letter in utterance.letters] == expected


# (example word of Table 5.1, letter, model of that row); words whose example contradicts the table's own
# syllable rule (öğürmek, füme, üre: the letter sits in a syllable with another vowel) are left out.
TABLE_5_1_EXAMPLES = [
    ("kal", "a", "a"), ("bal", "b", "bpa"), ("abla", "b", "bpa"), ("kılıbık", "b", "bpa"),
    ("bel", "b", "bpe"), ("tebliğ", "b", "bpe"), ("bir", "b", "bpe"), ("iblik", "b", "bpe"),
    ("böl", "b", "bpo"), ("büst", "b", "bpo"), ("bol", "b", "bpo"), ("cam", "c", "cjae"),
    ("cimri", "c", "cjae"), ("cılk", "c", "cjae"), ("coş", "c", "cjo"), ("ücra", "c", "cjo"),
    ("çam", "ç", "cjae"), ("içki", "ç", "cjae"), ("çıban", "ç", "cjae"), ("çocuk", "ç", "cjo"),
    ("üç", "ç", "cjo"), ("dam", "d", "dta"), ("ad", "d", "dta"), ("dıt", "d", "dta"),
    ("edil", "d", "dte"), ("idrak", "d", "dte"), ("dobra", "d", "do"), ("dün", "d", "do"),
    ("ödlek", "d", "do"), ("kel", "e", "e"), ("fal", "f", "fvae"), ("fır", "f", "fvae"),
    ("iffet", "f", "fvae"), ("fol", "f", "fvo"), ("üfle", "f", "fvo"), ("öfke", "f", "fvo"),
    ("galip", "g", "gkya"), ("gel", "g", "gkye"), ("giriş", "g", "gkye"), ("gol", "g", "gkyo"),
    ("gül", "g", "gkyo"), ("ağrı", "ğ", "a"), ("yağmur", "ğ", "a"), ("eğri", "ğ", "e"),
    ("tığ", "ğ", "I"), ("iğne", "ğ", "Ii"), ("boğmak", "ğ", "o"), ("tuğra", "ğ", "u"),
    ("öğüt", "ğ", "u"), ("halı", "h", "a"), ("ah", "h", "a"), ("hepsi", "h", "e"), ("ehli", "h", "e"),
    ("hıçkırık", "h", "I"), ("ıhlamur", "h", "I"), ("hile", "h", "Ii"), ("ihtiyaç", "h", "Ii"),
    ("hol", "h", "o"), ("köhne", "h", "oi"), ("hurma", "h", "u"), ("hüp", "h", "u"), ("kıl", "ı", "I"),
    ("kil", "i", "Ii"), ("jel", "j", "cjae"), ("jambon", "j", "cjae"), ("jöle", "j", "cjo"),
    ("kal", "k", "gkya"), ("ak", "k", "gkya"), ("kel", "k", "gkye"), ("iklim", "k", "gkye"),
    ("kol", "k", "gkyo"), ("küp", "k", "gkyo"), ("lamba", "l", "la"), ("ılgın", "l", "la"),
    ("elit", "l", "le"), ("liret", "l", "le"), ("olgu", "l", "lo"), ("flüt", "l", "lo"),
    ("mal", "m", "ma"), ("mızrak", "m", "ma"), ("emlak", "m", "me"), ("misil", "m", "me"),
    ("omlet", "m", "mo"), ("ömür", "m", "mo"), ("nara", "n", "na"), ("anı", "n", "na"),
    ("nem", "n", "ne"), ("nil", "n", "ne"), ("on", "n", "no"), ("not", "n", "no"), ("kol", "o", "o"),
    ("köle", "ö", "oi"), ("para", "p", "bpa"), ("apar", "p", "bpa"), ("peloş", "p", "bpe"),
    ("toprak", "p", "bpo"), ("tüp", "p", "bpo"), ("pul", "p", "bpo"), ("ray", "r", "ra"),
    ("ırmak", "r", "ra"), ("er", "r", "re"), ("reklam", "r", "re"), ("örtü", "r", "ro"),
    ("rota", "r", "ro"), ("ruj", "r", "ro"), ("sal", "s", "sza"), ("ıslak", "s", "sza"),
    ("sel", "s", "sze"), ("sil", "s", "sze"), ("sol", "s", "szto"), ("us", "s", "szto"),
    ("süne", "s", "szto"), ("aşk", "ş", "cjae"), ("iş", "ş", "cjae"), ("koş", "ş", "cjo"),
    ("kuş", "ş", "cjo"), ("şölen", "ş", "cjo"), ("at", "t", "ta"), ("kıt", "t", "ta"),
    ("tek", "t", "dte"), ("tiz", "t", "dte"), ("ot", "t", "szto"), ("şut", "t", "szto"),
    ("kul", "u", "u"), ("kül", "ü", "u"), ("ev", "v", "fvae"), ("kıvrak", "v", "fvae"),
    ("vole", "v", "fvo"), ("övgü", "v", "fvo"), ("yal", "y", "gkya"), ("ay", "y", "gkya"),
    ("yel", "y", "gkye"), ("giy", "y", "gkye"), ("yol", "y", "gkyo"), ("uy", "y", "gkyo"),
    ("zar", "z", "sza"), ("azı", "z", "sza"), ("zemin", "z", "sze"), ("iz", "z", "sze"),
    ("öz", "z", "szto"), ("uzun", "z", "szto"),
]  # fmt: skip


@pytest.mark.parametrize(("word", "letter", "model"), TABLE_5_1_EXAMPLES)
def test_table_5_1_example_words(word, letter, model):
    utterance = build_utterance(word)
    models = {lt.viseme for lt in utterance.letters if lt.char == letter}
    assert models == {model}


def test_vowel_context_changes_the_consonant_model():
    assert (viseme_for_letter("m", "o"), viseme_for_letter("m", "e"), viseme_for_letter("m", "a")) == (
        "mo",
        "me",
        "ma",
    )


def test_a_letter_outside_the_table_is_refused_with_its_name():
    with pytest.raises(DataError, match="'q'"):
        viseme_for_letter("q", "a")
