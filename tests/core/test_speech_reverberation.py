"""Late reverberation taken out of mel energies (reading the RT60 is tested on a person's takes)."""

import numpy as np

from turkish_lipsync.core.speech.reverberation import (
    DRY_DECAY,
    FRAME_SECONDS,
    SUBTRACTED_FLOOR,
    dereverberate,
)


def ringing_sound(rt60: float, frames: int = 9000) -> np.ndarray:
    """A 200 ms sound in 32 bands, then its tail dying away as a room of this RT60 makes it (dry part out)."""
    room = np.sqrt(rt60**2 - DRY_DECAY**2)
    energies = np.full((frames, 32), 1e-6, np.float32)
    energies[100:120] = 1.0
    tail = 10 ** (-6.0 * FRAME_SECONDS * np.arange(1, 60) / room)
    energies[120:179] = tail[:, None]
    return energies


def test_a_rooms_tail_is_cut_down_and_the_sounds_onset_kept():
    energies = ringing_sound(0.4)
    cleaned = dereverberate(energies.copy(), 0.4)
    assert np.allclose(cleaned[100], 1.0)  # the onset has nothing before it to ring
    assert np.all(cleaned[100:120] > 0.5)  # the sound itself stays the loudest part
    tail = slice(124, 179)
    assert np.all(cleaned[tail] <= 1.05 * SUBTRACTED_FLOOR * energies[tail])  # the tail down 10 dB
    assert np.all(cleaned >= SUBTRACTED_FLOOR * energies * 0.999)  # never below the floor


def test_a_dry_take_keeps_its_energies_and_the_given_ones_are_left_alone():
    energies = ringing_sound(0.4)
    assert np.array_equal(dereverberate(energies, 0.15), energies)
    given = energies.copy()
    dereverberate(given, 0.4)
    assert np.array_equal(given, energies)
