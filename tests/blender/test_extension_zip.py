"""The extension zip: built by Blender's own builder, only the extension inside, installs and enables."""

import importlib.util
import tomllib
import zipfile
from pathlib import Path

import pytest

bpy = pytest.importorskip("bpy")

REPOSITORY = Path(__file__).resolve().parents[2]
SCRIPT = REPOSITORY / "scripts" / "build_extension.py"
_spec = importlib.util.spec_from_file_location("build_extension", SCRIPT)
build_extension = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(build_extension)


@pytest.fixture(scope="module")
def built_zip(tmp_path_factory) -> Path:
    # Without wheels: the test stays offline; the wheels path is exercised by `make dist`-style runs.
    return build_extension.build(tmp_path_factory.mktemp("dist"), with_wheels=False)


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
    assert any(name.startswith("shapekeys/") and name.endswith(".toml") for name in names)
    forbidden = ("tests/", "scripts/", ".venv", ".git/", "Makefile", "requirements", "pyproject", "examples/")
    assert [n for n in names if n.startswith(forbidden) or "__pycache__" in n] == []


def test_zip_installs_and_enables_in_a_fresh_profile(built_zip):
    line = build_extension.check_install(built_zip)
    assert line.startswith("EXTENSION_OK")
