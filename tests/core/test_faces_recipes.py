"""The viseme and emotion recipes: complete, validated, and shaped the way the thesis describes."""

import numpy as np
import pytest

from turkish_lipsync.core.base.errors import DataError
from turkish_lipsync.core.base.model import (
    BLINK_KEYS,
    BROW_RAISE_KEY,
    EMOTIONS,
    emotion_key_name,
    emotion_release_key_name,
    viseme_key_name,
)
from turkish_lipsync.core.faces.arkit_names import is_mouth_unit
from turkish_lipsync.core.faces.recipes import VISEME_NAMES, combine_units, empower, key_deltas, load_recipes
from turkish_lipsync.core.faces.reference import load_reference_head


def test_every_key_moves_the_face_and_a_release_gives_the_lips_back():
    """Every built key moves the reference head; an emotion plus its mouth release leaves the lips where the
    rest pose has them (so a closure under the emotion closes) while its eyes and brows keep moving."""
    head = load_reference_head()
    deltas = key_deltas(head.units, len(head.vertices))
    expected = {viseme_key_name(name) for name in VISEME_NAMES if name != "neutral"}
    expected |= {emotion_key_name(e) for e in EMOTIONS} | {*BLINK_KEYS, BROW_RAISE_KEY}
    moved = {name for name, delta in deltas.items() if np.abs(delta).max() > 1e-4}
    assert expected <= moved, sorted(expected - moved)
    assert np.abs(deltas[viseme_key_name("neutral")]).max() == 0.0
    lips = [
        head.landmark_vertices[name]
        for name in ("upper_lip", "lower_lip", "upper_lip_inner", "lower_lip_inner")
    ]
    corners = [head.landmark_vertices["mouth_corner_left"], head.landmark_vertices["mouth_corner_right"]]
    brows = [head.landmark_vertices["brow_left"], head.landmark_vertices["brow_right"]]
    for emotion in EMOTIONS:
        released = deltas[emotion_key_name(emotion)] + deltas[emotion_release_key_name(emotion)]
        assert np.abs(deltas[emotion_key_name(emotion)][lips + corners]).max() > 1e-3, emotion
        assert np.abs(released[lips]).max() < 5e-4, emotion  # the lips back within half a mm (a sneer)
        assert np.abs(released[corners]).max() < 1e-3, emotion  # cheeks may pull a corner under a mm
        if emotion != "happy":  # a smile moves cheeks and eyes, not the brows
            assert np.abs(released[brows]).max() > 5e-4, emotion


def _mouth_width(deltas):
    head = load_reference_head()
    left, right = head.landmark_vertices["mouth_corner_left"], head.landmark_vertices["mouth_corner_right"]
    shape = head.vertices + deltas
    return np.linalg.norm(shape[left] - shape[right])


def test_vowel_context_changes_the_consonant():
    """Thesis 5.2.3: m before o is rounder (narrower) than m before a, which is narrower than before e."""
    head = load_reference_head()
    deltas = key_deltas(head.units, len(head.vertices))
    for consonant in ("m", "bp", "n", "r", "gky", "l"):
        names = {"a": f"{consonant}a", "e": f"{consonant}e", "o": f"{consonant}o"}
        widths = {context: _mouth_width(deltas[f"TR_viseme_{name}"]) for context, name in names.items()}
        assert widths["o"] < widths["a"] < widths["e"], (consonant, widths)
        assert widths["e"] - widths["o"] > 0.005  # visibly different: more than 5 mm


def test_empowered_emotions_scale_by_rho():
    head = load_reference_head()
    plain = key_deltas(head.units, len(head.vertices))
    empowered = empower(plain, 3.0)
    np.testing.assert_allclose(empowered["TR_emotion_angry"], 3 * plain["TR_emotion_angry"], atol=1e-6)
    np.testing.assert_allclose(empowered["TR_viseme_a"], plain["TR_viseme_a"])
    # The release cancels the mouth units and keeps the rest (cheeks, eyes) of the emotion.
    total = empowered["TR_emotion_happy"] + empowered["TR_emotion_happy_mouth_release"]
    upper_face = {u: w for u, w in load_recipes().emotions["happy"].units.items() if not is_mouth_unit(u)}
    np.testing.assert_allclose(
        total, 3 * combine_units(upper_face, head.units, len(head.vertices)), atol=1e-6
    )
    with pytest.raises(DataError, match="rho must be positive"):
        empower(plain, 0.0)


def test_bad_recipe_files_name_the_file(tmp_path):
    visemes = tmp_path / "visemes.toml"
    visemes.write_text("[visemes.a]\nunits = { jawOpn = 0.4 }\n", encoding="utf-8")
    with pytest.raises(DataError, match="visemes.toml"):
        load_recipes(visemes, tmp_path / "missing.toml")
    good = (load_recipes.__globals__["VISEMES_FILE"]).read_text(encoding="utf-8")
    visemes.write_text(good.replace("mouthPress = ", "mouthPres = ", 1), encoding="utf-8")
    emotions = load_recipes.__globals__["EMOTIONS_FILE"]
    with pytest.raises(DataError, match=r"visemes.toml.*'mouthPres' is not one of the 52 ARKit units"):
        load_recipes(visemes, emotions)


def test_rounded_vowels_are_narrow_and_s_z_show_the_teeth():
    """o, ö, u/ü draw the corners in by more than 1 cm; ı, i, s/z part the lips over nearly closed teeth."""
    head = load_reference_head()
    deltas = key_deltas(head.units, len(head.vertices))
    neutral = _mouth_width(np.zeros_like(head.vertices))
    for viseme in ("o", "oi", "u"):
        assert _mouth_width(deltas[f"TR_viseme_{viseme}"]) < neutral - 0.01, viseme
    upper, lower = head.landmark_vertices["upper_lip_inner"], head.landmark_vertices["lower_lip_inner"]
    for viseme in ("I", "Ii", "sza", "sze"):
        shape = head.vertices + deltas[f"TR_viseme_{viseme}"]
        assert shape[upper, 2] - shape[lower, 2] > 0.004, viseme  # lips parted 4 mm or more
        assert np.abs(deltas[f"TR_viseme_{viseme}"][head.parts["lower_teeth"], 2]).max() < 0.002, viseme
