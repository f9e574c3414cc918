"""Reading a user's text files (scripts, JSML, cue files): one encoding rule, errors that say where."""

from __future__ import annotations

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
