"""Paths a run reads and writes: an output never replaces an input or another output; unwritable outputs are
refused before any work; user text files are read one way."""

import os

import pytest

from turkish_lipsync.core.base.errors import LipSyncError
from turkish_lipsync.core.base.files import check_distinct_paths, check_writable, read_user_text


def test_an_output_that_is_an_input_is_refused_however_it_is_written(tmp_path):
    take = tmp_path / "take.wav"
    take.write_bytes(b"RIFF")
    (tmp_path / "link.wav").symlink_to(take)
    os.link(take, tmp_path / "hard.wav")
    sub = tmp_path / "sub"
    sub.mkdir()
    for same in (take, tmp_path / "link.wav", tmp_path / "hard.wav", sub / ".." / "take.wav"):
        with pytest.raises(LipSyncError, match=r"--wav .* is the same file as --audio .*replace an input"):
            check_distinct_paths({"--audio": take}, {"--wav": same})
    check_distinct_paths({"--audio": take}, {"--wav": tmp_path / "other.wav", "--out": None})


def test_two_outputs_of_one_run_may_not_be_one_file(tmp_path):
    with pytest.raises(LipSyncError, match="--wav .* is the same file as --out .*another output"):
        check_distinct_paths({}, {"--out": tmp_path / "x.tsv", "--wav": tmp_path / "x.tsv"})


def test_a_folder_or_a_place_we_may_not_write_is_refused(tmp_path):
    with pytest.raises(LipSyncError, match="is a folder: give the glTF a file name"):
        check_writable(tmp_path, "glTF")
    assert check_writable(tmp_path / "new" / "x.glb", "glTF") == tmp_path / "new" / "x.glb"
    assert (tmp_path / "new").is_dir() and list((tmp_path / "new").iterdir()) == []
    with pytest.raises(LipSyncError, match=r"cannot write the glTF /sys/x.glb"):  # sysfs: even root may not
        check_writable("/sys/x.glb", "glTF")


def test_user_text_is_utf8_with_or_without_a_byte_order_mark(tmp_path):
    path = tmp_path / "speech.jsml"
    path.write_bytes("\ufeffMerhaba, dünya".encode())
    assert read_user_text(path, "text") == "Merhaba, dünya"
    path.write_bytes("Merhaba".encode("utf-16"))
    with pytest.raises(LipSyncError, match="the text is not UTF-8 text"):
        read_user_text(path, "text")
    with pytest.raises(LipSyncError, match="is a folder, not the text"):
        read_user_text(tmp_path, "text")
