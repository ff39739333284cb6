"""One registry shape for everything looked up by name (plants, controllers, optimizers, F1-F23).

An entry is the object itself or a lazy "package.module:attr" path imported on first `get`, so
that listing names imports nothing heavy. Registering a name twice is a programming error; an
unknown name is bad input (InputError naming the field and listing the known names).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import Generic, TypeVar, cast

from chassistune.errors import InputError

T = TypeVar("T")


def resolve(path: str) -> object:
    """The object at "package.module:attr" (imported now)."""
    module, sep, attr = path.partition(":")
    if not sep or not module or not attr:
        raise ValueError(f"expected 'module:attr', got {path!r}")
    return getattr(importlib.import_module(module), attr)


class Registry(Generic[T]):
    """Entries of one kind by name, in registration order.

    `kind` words the error ("unknown optimizer 'x'"), `field` is the InputError's field path and
    `key` normalizes a looked-up name (e.g. `str.lower`).
    """

    def __init__(
        self, kind: str, field: str | None = None, key: Callable[[str], str] | None = None
    ) -> None:
        self.kind = kind
        self.field = field or kind
        self._key = key or (lambda name: name)
        self._entries: dict[str, T | str] = {}

    def register(self, name: str, entry: T | str) -> None:
        """Add `name` -> `entry` (an object, or a lazy "module:attr" path); refuses duplicates."""
        if name in self._entries:
            raise ValueError(f"{self.kind} {name!r} is registered already")
        self._entries[name] = entry

    def unregister(self, name: str) -> None:
        """Remove `name` (tests registering a temporary entry clean up with it)."""
        del self._entries[name]

    def names(self) -> list[str]:
        return list(self._entries)

    def __contains__(self, name: object) -> bool:
        return isinstance(name, str) and self._key(name) in self._entries

    def get(self, name: str, where: str = "") -> T:
        """The entry `name` (a lazy one is imported now), or InputError listing the known names.

        `where` completes the message, e.g. " for plant 'abs-wheel'".
        """
        key = self._key(str(name))
        if key not in self._entries:
            known = ", ".join(self._entries) or "none"
            raise InputError(self.field, f"unknown {self.kind} {name!r}{where} (known: {known})")
        entry = self._entries[key]
        if isinstance(entry, str):
            entry = cast(T, resolve(entry))
            self._entries[key] = entry
        return cast(T, entry)
