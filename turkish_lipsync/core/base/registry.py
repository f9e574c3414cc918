"""Registries by name (as phonemizer picks backends and aeneas sync-map formats): one class per entry.

Cue formats, export formats, timing sources and motion models each keep one `Registry`. An entry is a class
with a `name` in a module of the registry's package, decorated with `registry.register`; the package's
modules are imported the first time the registry is read, so a new entry is one new file.
"""

from __future__ import annotations

import importlib
import pkgutil
from pathlib import Path
from typing import Generic, TypeVar

from .choices import Choice
from .errors import LipSyncError

T = TypeVar("T")


class Registry(Generic[T]):
    def __init__(self, kind: str, package: str, package_path: str | Path) -> None:
        self.kind = kind  # what an entry is, for errors: "export format", "timing source"
        self.package = package
        self.package_path = Path(package_path)
        self._entries: dict[str, T] = {}
        self._loaded = False

    def register(self, cls: type[T]) -> type[T]:
        """Class decorator: one instance of the class, known by its `name`."""
        instance = cls()
        name = getattr(instance, "name", "")
        if not name:
            raise TypeError(f"{cls.__name__} needs a name to be a {self.kind}")
        if name in self._entries and type(self._entries[name]) is not cls:
            raise TypeError(f"two {self.kind}s are named {name!r}: {cls.__name__} and another")
        self._entries[name] = instance
        return cls

    def unregister(self, name: str) -> None:
        """Forget an entry registered from outside the package (the Blender layer's, when it unregisters)."""
        self._entries.pop(name, None)

    def entries(self) -> dict[str, T]:
        """Every entry by name, ordered by their `order` (where they have one), then by name."""
        if not self._loaded:
            self._loaded = True
            for module in sorted(pkgutil.iter_modules([str(self.package_path)]), key=lambda m: m.name):
                importlib.import_module(f"{self.package}.{module.name}")
        ranked = sorted(self._entries.items(), key=lambda item: (getattr(item[1], "order", 0), item[0]))
        return dict(ranked)

    def get(self, name: str) -> T:
        entries = self.entries()
        if name not in entries:
            raise LipSyncError(f"unknown {self.kind} {name!r}; choose one of: {', '.join(entries)}")
        return entries[name]

    def choices(self) -> tuple[Choice, ...]:
        """The entries as choices (each has label and description)."""
        return tuple(Choice(e.name, e.label, e.description) for e in self.entries().values())
