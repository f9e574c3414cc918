"""Festival's diphone voices as labelled people's speech (lab/kit/festival_voices.py): the phone tables
load and are checked, segments become frame labels; with Festival installed, every voice's phones are in
its table."""

import shutil
import subprocess
import wave

import numpy as np
import pytest

from lab.kit import festival_voices
from turkish_lipsync.core.base.errors import DataError
from turkish_lipsync.core.speech.acoustic.labels import CLASS_INDEX


@pytest.mark.parametrize("name", sorted({voice.inventory for voice in festival_voices.VOICES.values()}))
def test_every_table_loads_with_silence_and_the_bilabials(name):
    table = festival_voices.inventory(name)
    heard = {letter for letters in table.values() for letter in letters}
    assert {"_", "b", "m", "p", "a", "i", "u"} <= heard


def test_a_table_naming_no_letter_is_refused(tmp_path, monkeypatch):
    (tmp_path / "bad.toml").write_text('[phones]\naa = "a"\nth = "θ"\n', encoding="utf-8")
    monkeypatch.setattr(festival_voices, "INVENTORY", tmp_path)
    with pytest.raises(DataError, match="'th' maps to 'θ'"):
        festival_voices.inventory("bad")


def test_segments_become_frame_labels_shared_and_ignored(tmp_path):
    (tmp_path / "take.segs").write_text("#\n0.100 100 pau\n0.200 100 ay\n0.300 100 th\n0.400 100 m\n")
    _write_wav(tmp_path / "take.wav", np.zeros(int(0.4 * 16000)))
    _, labels = festival_voices.labelled(tmp_path / "take", festival_voices.inventory("english"))
    # 10 ms frames centred at 12.5, 22.5, ... ms: silence, then "ay" as a and y, then θ ignored, then m.
    assert labels[5] == CLASS_INDEX["_"]
    assert labels[11] == CLASS_INDEX["a"] and labels[18] == CLASS_INDEX["y"]
    assert (labels[21:29] == festival_voices.IGNORE).all()
    assert labels[33] == CLASS_INDEX["m"]


def test_a_phone_no_table_holds_is_an_error(tmp_path):
    (tmp_path / "take.segs").write_text("#\n0.100 100 pau\n0.200 100 qq\n")
    _write_wav(tmp_path / "take.wav", np.zeros(3200))
    with pytest.raises(DataError, match="'qq'"):
        festival_voices.labelled(tmp_path / "take", festival_voices.inventory("english"))


@pytest.mark.skipif(shutil.which("festival") is None, reason="Festival is not installed")
@pytest.mark.parametrize("name", sorted(festival_voices.VOICES))
def test_every_phone_a_voice_can_speak_is_in_its_table(name):
    voice = festival_voices.VOICES[name]
    if not festival_voices.installed(voice.package):
        pytest.skip(f"{voice.package} is not installed")
    script = (
        f"({voice.select})\n"
        "(print (mapcar car (car (cdr (assoc 'phones (PhoneSet.description '(phones)))))))\n"
    )
    printed = subprocess.run(["festival", "-b", "--pipe"], input=script, capture_output=True, text=True)
    phones = printed.stdout.strip().splitlines()[-1].strip("()").split()
    assert phones and set(phones) <= set(festival_voices.inventory(voice.inventory))


def test_a_voiceless_stop_after_a_pause_starts_at_its_sound(tmp_path):
    # 0.1 s of pause, a p whose first 60 ms are silent (the diphone's share of the pause), its burst, an a.
    (tmp_path / "take.segs").write_text("#\n0.100 100 pau\n0.200 100 p\n0.300 100 aa\n")
    rng = np.random.default_rng(1)
    samples = np.zeros(4800)
    samples[2560:3200] = 0.3 * rng.normal(size=640)  # the burst, from 160 ms
    samples[3200:] = 0.5 * np.sin(np.arange(1600) * 0.2)
    _write_wav(tmp_path / "take.wav", samples)
    _, labels = festival_voices.labelled(tmp_path / "take", festival_voices.inventory("english"))
    assert (labels[10:14] == CLASS_INDEX["_"]).all()  # frames centred at 112-142 ms: the pause's
    assert (labels[16:19] == CLASS_INDEX["p"]).all()


def _write_wav(path, samples):
    with wave.open(str(path), "wb") as out:
        out.setnchannels(1)
        out.setsampwidth(2)
        out.setframerate(16000)
        out.writeframes((np.asarray(samples) * 32767).astype(np.int16).tobytes())


def test_a_voiceless_stop_inside_speech_starts_at_its_burst(tmp_path):
    # An a, a p whose first 50 ms are its closure (silent), its burst, an a: the closure is the a's.
    (tmp_path / "take.segs").write_text("#\n0.100 100 aa\n0.200 100 p\n0.300 100 aa\n")
    rng = np.random.default_rng(2)
    samples = 0.5 * np.sin(np.arange(4800) * 0.2)
    samples[1600:2400] = 0.0
    samples[2400:3200] = 0.3 * rng.normal(size=800)
    _write_wav(tmp_path / "take.wav", samples)
    _, labels = festival_voices.labelled(tmp_path / "take", festival_voices.inventory("english"))
    assert (labels[11:14] == CLASS_INDEX["a"]).all()  # the closure, centred at 122-142 ms
    assert (labels[16:19] == CLASS_INDEX["p"]).all()
    assert (labels[21:29] == CLASS_INDEX["a"]).all()


def test_a_stem_made_for_another_text_is_made_again_and_a_stem_for_the_same_text_is_kept(tmp_path):
    """render keys what it keeps on the text, the stretch and the voice: read speech measured with
    another seed took the first seed's audio for its sentences before."""
    if shutil.which("festival") is None:
        pytest.skip("Festival is not installed")
    italian = festival_voices.Voice("festvox-italp16k", "voice_lp_diphone", "it", "iso-8859-1", "italian")
    candidates = [*festival_voices.VOICES.values(), italian]
    voice = next((v for v in candidates if festival_voices.installed(v.package)), None)
    if voice is None:
        pytest.skip("no Festival voice of the lab's is installed")
    first = festival_voices.render(voice, ["a"], [1.0], tmp_path)[0]
    words = first.with_suffix(".words").read_text(encoding="utf-8")
    made = first.with_suffix(".segs").stat().st_mtime_ns
    assert festival_voices.render(voice, ["a"], [1.0], tmp_path) == [first]
    assert first.with_suffix(".segs").stat().st_mtime_ns == made  # the same text: kept
    again = festival_voices.render(voice, ["a a a"], [1.0], tmp_path)[0]
    assert again == first and first.with_suffix(".words").read_text(encoding="utf-8") != words
    spoken = festival_voices.segments(first.with_suffix(".segs"))[-1][1]
    festival_voices.render(voice, ["a a a"], [2.0], tmp_path)
    assert festival_voices.segments(first.with_suffix(".segs"))[-1][1] > 1.5 * spoken  # another stretch
