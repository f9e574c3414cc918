"""Settings objects changed by name: what tuning and measuring scripts and the command line pass to a call
instead of changing a module's constants (`--set LOOSE=1.5`, `--try loose=1.4,1.6`)."""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable
from typing import TypeVar, get_type_hints

from .errors import LipSyncError

Settings = TypeVar("Settings")


def setting_names(settings) -> tuple[str, ...]:
    """The names a settings dataclass (or an instance of one) may be changed by."""
    return tuple(field.name for field in dataclasses.fields(settings))


def overridden(settings: Settings, assignments: Iterable[str]) -> Settings:
    """A copy of the settings with each "name=value" applied (the name in either case, the value read as
    the setting's type); an unknown name or a value of the wrong kind is an error naming both."""
    kind = type(settings)
    types = get_type_hints(kind)
    changes = {}
    for assignment in assignments:
        name, equals, text = assignment.partition("=")
        field = name.strip().lower()
        if not equals or field not in types:
            raise LipSyncError(
                f"{assignment!r} sets no setting of {kind.__name__}: write NAME=VALUE with NAME one of "
                f"{', '.join(setting_names(kind))}"
            )
        changes[field] = _value(types[field], text.strip(), assignment)
    return dataclasses.replace(settings, **changes)


def _value(kind: type, text: str, assignment: str):
    try:
        if kind is bool:
            if text.lower() not in ("true", "false", "1", "0"):
                raise ValueError(text)
            return text.lower() in ("true", "1")
        return kind(text)
    except ValueError:
        raise LipSyncError(f"{assignment!r}: {text!r} is not a {kind.__name__}") from None
