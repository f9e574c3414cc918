"""Choices of an option (timing, motion, export format, ...): identifier, label and description, once.

The command line's choices and --help, the panel's enum items and render.py's flags are all built from
these, so an option's choices are written in one place.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Choice:
    """One choice of an option: its identifier, a label and a one-line description for the UI and --help."""

    identifier: str
    label: str
    description: str


def identifiers(choices: tuple[Choice, ...]) -> tuple[str, ...]:
    return tuple(choice.identifier for choice in choices)
