"""Speech WAVs: written whole or not at all, named after their sound, ours told from the user's."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from turkish_lipsync.core.base.errors import AudioError
from turkish_lipsync.core.speech.base import Synthesis
from turkish_lipsync.core.speech.wav import is_our_wav, speech_wav_in, write_wav

soundfile = pytest.importorskip("soundfile")
ROOT = Path(__file__).resolve().parents[2]


def _speech(seconds: float, frequency: float = 220.0) -> Synthesis:
    t = np.arange(int(seconds * 22050)) / 22050
    return Synthesis((8000 * np.sin(2 * np.pi * frequency * t)).astype(np.int16), 22050, (), (), "test")


def test_a_written_wav_plays_its_samples_and_carries_our_mark(tmp_path):
    speech = _speech(0.3)
    path = write_wav(tmp_path / "speech.wav", speech)
    samples, rate = soundfile.read(str(path), dtype="int16")
    assert rate == 22050 and np.array_equal(samples, speech.samples)
    assert is_our_wav(path)
    soundfile.write(str(tmp_path / "theirs.wav"), samples, rate)
    assert not is_our_wav(tmp_path / "theirs.wav") and not is_our_wav(tmp_path / "missing.wav")
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []  # no partial file left


def test_an_unwritable_wav_is_one_error_and_no_traceback_at_exit():
    code = (
        "import numpy as np\n"
        "from turkish_lipsync.core.speech.base import Synthesis\n"
        "from turkish_lipsync.core.speech.wav import write_wav\n"
        "try:\n"
        "    write_wav('/sys/a.wav', Synthesis(np.zeros(10, np.int16), 22050, (), (), 'x'))\n"
        "except Exception as error:\n"
        "    print(type(error).__name__, error)\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True
    )
    assert result.stdout.startswith("AudioError cannot write the speech audio to /sys/a.wav")
    assert result.stderr == ""  # no "Exception ignored in Wave_write.__del__"


def test_speech_wavs_are_named_by_their_sound_and_never_overwrite(tmp_path):
    first, slower = _speech(1.0), _speech(1.4)
    a = speech_wav_in(tmp_path, "TR_merhaba", first)
    b = speech_wav_in(tmp_path, "TR_merhaba", slower)
    assert a != b and a.name.startswith("TR_merhaba-") and b.name.startswith("TR_merhaba-")
    assert speech_wav_in(tmp_path, "TR_merhaba", first) == a  # the same sound: the same file, unchanged
    a.write_bytes(b"a file of the user's under that name")
    c = speech_wav_in(tmp_path, "TR_merhaba", first)
    assert c.name.endswith("-2.wav") and a.read_bytes() == b"a file of the user's under that name"
    with pytest.raises(AudioError, match="cannot write the speech audio"):
        write_wav(tmp_path / "missing" / "x.wav", first)
