"""The Blender layer: registers properties, preferences, operators, the panel and the Turkish UI."""

from __future__ import annotations

from . import (
    audio_decoding,
    operators,
    panel,
    preferences,
    properties,
    recording_browser,
    rig_operators,
    translations,
)

# Registration order: data types first, then what uses them; unregistered in reverse.
MODULES = (
    translations,
    audio_decoding,
    properties,
    preferences,
    operators,
    rig_operators,
    recording_browser,
    panel,
)


def register() -> None:
    for module in MODULES:
        module.register()


def unregister() -> None:
    for module in reversed(MODULES):
        module.unregister()
