"""Matching a head's own shape-key names to the ARKit units, whatever the spelling."""

import pytest

from turkish_lipsync.core.faces.arkit_names import arkit_unit_for_key, has_arkit_basis, match_arkit_keys


@pytest.mark.parametrize(
    ("key_name", "unit"),
    [
        ("jawOpen", "jawOpen"),
        ("JawOpen", "jawOpen"),
        ("jaw_open", "jawOpen"),
        ("JAW_OPEN", "jawOpen"),
        ("blendShape1.jawOpen", "jawOpen"),
        ("eyeBlinkLeft", "eyeBlinkLeft"),
        ("eyeBlink_L", "eyeBlinkLeft"),
        ("EyeBlinkL", "eyeBlinkLeft"),
        ("eye_blink_right", "eyeBlinkRight"),
        ("cheekSquint.R", "cheekSquintRight"),
        ("ARKit_mouthSmile_R", "mouthSmileRight"),
        ("mouthLeft", "mouthLeft"),
        ("tongueOut", "tongueOut"),
        ("Basis", None),
        ("mouth-open", None),
        ("TR_viseme_a", None),
    ],
)
def test_spellings(key_name, unit):
    assert arkit_unit_for_key(key_name) == unit


def test_a_few_keys_are_not_a_basis():
    matched = match_arkit_keys(["Basis", "jaw_open", "mouth_close", "eyeBlink_L"])
    assert matched == {"jawOpen": "jaw_open", "mouthClose": "mouth_close", "eyeBlinkLeft": "eyeBlink_L"}
    assert not has_arkit_basis(matched)
