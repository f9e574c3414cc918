"""The viseme set is the one source of the visemes: every table that names them is checked against it."""

import shutil

import pytest

from turkish_lipsync.core.base import data, visemes
from turkish_lipsync.core.base.errors import DataError
from turkish_lipsync.core.faces.recipes import load_recipes
from turkish_lipsync.core.motion import natural
from turkish_lipsync.core.speech.cues.shapes import SHAPES, shape_for_viseme
from turkish_lipsync.core.text import visemes as letters


def test_the_set_has_the_thesis_models_and_their_kinds():
    names = visemes.viseme_names()
    assert len(names) == 37 and names[0] == "a" and names[-1] == "neutral"
    assert visemes.BILABIAL_VISEMES == {"bpa", "bpe", "bpo", "ma", "me", "mo"}
    assert visemes.LABIODENTAL_VISEMES == {"fvae", "fvo"}
    assert visemes.VOWEL_VISEMES == {"a", "e", "I", "Ii", "o", "oi", "u"}
    assert all(viseme.meaning for viseme in visemes.viseme_set())


def test_the_other_tables_name_exactly_the_set():
    recipes = load_recipes()
    assert set(recipes.visemes) == set(visemes.VISEME_NAMES)
    assert set(natural.motion_parameters().classes) == set(visemes.VISEME_NAMES)
    assert {shape_for_viseme(name) for name in visemes.VISEME_NAMES} <= set(SHAPES)
    # every viseme but neutral is what some letter becomes in some vowel context (Table 5.1)
    table = letters.letter_table()
    reached = set(table.vowels.values()) | {model for row in table.consonants.values() for model in row}
    assert reached == set(visemes.VISEME_NAMES) - {"neutral"}


@pytest.fixture
def data_copy(tmp_path, monkeypatch):
    """The data tables copied to a folder the test may break, read from there with fresh caches."""
    folder = tmp_path / "shapekeys"
    shutil.copytree(data.DATA_DIR, folder)
    monkeypatch.setattr(data, "DATA_DIR", folder)
    for module in (visemes, letters, natural):
        monkeypatch.setattr(module, "DATA_DIR", folder, raising=False)
    caches = (data.load_table, visemes.viseme_set, letters.letter_table, natural.motion_parameters)
    for cached in caches:
        cached.cache_clear()
    yield folder
    for cached in caches:
        cached.cache_clear()


def _replace(path, old, new):
    text = path.read_text(encoding="utf-8")
    assert old in text
    path.write_text(text.replace(old, new, 1), encoding="utf-8")


def test_a_set_numbered_twice_is_refused(data_copy):
    _replace(data_copy / "viseme_set.toml", "[bpa]\nnumber = 1", "[bpa]\nnumber = 0")
    with pytest.raises(DataError, match="viseme_set.toml: the 37 visemes must be numbered 0..36 once each"):
        visemes.viseme_set()


def test_a_letter_mapped_outside_the_set_is_refused(data_copy):
    _replace(data_copy / "letters.toml", 'b = ["bpa", "bpe", "bpo"]', 'b = ["bpx", "bpe", "bpo"]')
    with pytest.raises(DataError, match=r"letters.toml: letter 'b' maps to 'bpx'"):
        letters.letter_table()


def test_motion_classes_must_hold_the_sets_closures(data_copy):
    _replace(
        data_copy / "viseme_set.toml",
        '[ma]\nnumber = 7\nkind = "bilabial"',
        '[ma]\nnumber = 7\nkind = "consonant"',
    )
    with pytest.raises(DataError, match=r"\[classes.bilabial\] must hold the visemes viseme_set.toml calls"):
        natural.motion_parameters()
