"""Reading a user's text files (scripts, JSML, cue files): one encoding rule, errors that say where."""

from __future__ import annotations

import os
import tempfile
from collections.abc import Mapping
from pathlib import Path

from .errors import LipSyncError


def read_user_text(path: Path | str, what: str, error: type[LipSyncError] = LipSyncError) -> str:
    """The file as text: UTF-8 with or without a byte-order mark (Windows editors write one).

    Errors are `error` with the path, what the file was meant to be and what to do.
    """
    path = Path(path)
    try:
        return path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise error(f"{path}: no such file (the {what})") from None
    except IsADirectoryError:
        raise error(f"{path}: is a folder, not the {what}") from None
    except UnicodeDecodeError as decode:
        raise error(f"{path}: the {what} is not UTF-8 text (byte {decode.start}); save it as UTF-8") from None
    except OSError as os_error:
        raise error(f"{path}: cannot read the {what} ({os_error.strerror})") from None


def _identities(path: Path) -> set:
    """What makes two paths one file: the resolved path, and the device and inode where it exists."""
    found = {("path", os.path.normcase(str(path.expanduser().resolve())))}
    try:
        status = path.expanduser().stat()
        found.add(("inode", status.st_dev, status.st_ino))
    except OSError:
        pass
    return found


def check_distinct_paths(
    inputs: Mapping[str, Path | None], outputs: Mapping[str, Path | None], error=LipSyncError
) -> None:
    """Refuse, before anything is written, an output that is one of the inputs or another output.

    Paths are compared after resolving symbolic links and relative parts, and by inode (hard links). The
    names are what the user wrote (a flag such as "--audio", a panel field), so the error says which two
    collide.
    """
    seen: list[tuple[str, Path, set]] = [
        (name, path, _identities(Path(path))) for name, path in inputs.items() if path is not None
    ]
    for name, path in outputs.items():
        if path is None:
            continue
        identities = _identities(Path(path))
        for other_name, other_path, other in seen:
            if identities & other:
                kind = "an input" if other_name in inputs else "another output"
                raise error(
                    f"{name} {path} is the same file as {other_name} {other_path}: writing it would replace "
                    f"{kind} of this run; choose another path"
                )
        seen.append((name, Path(path), identities))


def check_writable(path: Path | str, what: str, error=LipSyncError) -> Path:
    """Refuse, before any work, an output that cannot be written: a folder, or a place we may not write.

    The folder is created where it is missing (as the write would). Returns the path.
    """
    path = Path(path)
    if path.is_dir():
        raise error(f"{path} is a folder: give the {what} a file name")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=path.parent, prefix=".turkish_lipsync_", delete=True):
            pass
    except OSError as os_error:
        reason = os_error.strerror or str(os_error)
        raise error(f"cannot write the {what} {path}: {reason}; choose a writable place") from None
    return path
