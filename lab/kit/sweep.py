"""The settings a tuning run tries: a baseline (`--set NAME=VALUE ...`), then each value of `--try
NAME=V1,V2,...` one at a time, as settings objects passed to the product's calls (never by changing its
modules)."""

from __future__ import annotations

from typing import TypeVar

from turkish_lipsync.core.base.settings import overridden

Settings = TypeVar("Settings")


def settings_tried(
    default: Settings, baseline: list[str], tries: list[str], untried: dict[str, tuple] | None = None
) -> list[tuple[str, Settings]]:
    """(label, settings) per setting tried: the baseline first, then each --try value alone on it
    (`untried`'s values where no --try is given)."""
    base = overridden(default, baseline)
    label = ", ".join(baseline) or "as shipped"
    varied = {name: values.split(",") for name, _, values in (text.partition("=") for text in tries)}
    if not varied and untried:
        varied = {name: [str(value) for value in values] for name, values in untried.items()}
    tried = [(label, base)]
    for name, values in varied.items():
        for value in values:
            assignment = f"{name}={value}"
            tried.append((f"{label}; {assignment}", overridden(base, [assignment])))
    return tried
