"""One error family: every message says what is wrong, where, and what to do."""

from __future__ import annotations


class LipSyncError(Exception):
    """Base of every error the add-on reports to a user."""


class MarkupError(LipSyncError):
    """Malformed JSML; carries the 1-based line and column of the offending text."""

    def __init__(self, message: str, line: int, column: int, snippet: str) -> None:
        self.message = message
        self.line = line
        self.column = column
        self.snippet = snippet
        super().__init__(f"JSML error at line {line}, column {column}: {message} (near {snippet!r})")


class TextError(LipSyncError):
    """Text that cannot be spoken (empty, nothing Turkish left after normalisation)."""


class DataError(LipSyncError):
    """A data table in shapekeys/ is missing or invalid."""


class SpeechEngineError(LipSyncError):
    """The speech engine is missing or failed."""


class AudioError(LipSyncError):
    """An audio file that cannot be read or aligned."""


class HeadError(LipSyncError):
    """A head mesh on which the shape keys cannot be built."""
