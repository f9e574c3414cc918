"""The people's-voices measure's truth (lab/kit/people.py): where an item's sound starts, who speaks."""

from pathlib import Path

import numpy as np

from lab.kit.people import Recording, sound_onset

RATE = 16000


def item(offset: float, click: bool) -> np.ndarray:
    """0.3 s of faint noise, then 0.4 s of a voiced sound; on a DC offset, a click at its first sample."""
    rng = np.random.default_rng(1)
    time = np.arange(int(0.7 * RATE)) / RATE
    voice = 0.3 * np.sin(2 * np.pi * 140 * time) * (time >= 0.3)
    samples = voice + 0.0005 * rng.standard_normal(time.size) + offset
    if click:
        samples[:8] += 0.2 * np.sign(offset or 1)
    return samples


def test_the_sound_starts_with_the_voice_not_an_offset_or_a_click():
    assert abs(sound_onset(item(0.0, click=False), RATE) - 0.3) < 0.015
    assert abs(sound_onset(item(-0.2, click=True), RATE) - 0.3) < 0.015


def test_a_speaker_is_a_game_line_s_character_or_else_its_source():
    def recording(source: str, ident: str) -> Recording:
        return Recording("line", source, ident, Path("x.ogg"), "", "", "tune")

    assert recording("fillets-nl/airplane", "let-v-oko").speaker == "fillets-nl/v"
    assert recording("fillets-cs/airplane", "let-m-oko").speaker == "fillets-cs/m"
    assert recording("fillets-nl/briefcase", "help3").speaker == "fillets-nl/briefcase"
    assert recording("klettres-uk", "ba").speaker == "klettres-uk"
