"""Declared kernel layouts: the named, unit-carrying slots of a kernel's input or output rows.

A compiled kernel reads and writes plain float arrays; which column holds what is declared once,
here, as a `Layout`. Kernel modules take their integer slot constants from it (numba freezes
module-level integers as compile-time constants), scenarios pack inputs and decode outputs by
name through it, and reports read the units from it: adding a metric or a trace signal is one
line in its layout plus the line of the kernel that writes it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Slot:
    """One column: its name, its unit (SI, "-" for dimensionless) and a one-line meaning."""

    name: str
    unit: str
    description: str = ""


class Layout:
    """An ordered set of named slots; `layout["name"]` is the column index."""

    def __init__(self, title: str, slots: tuple[Slot, ...]) -> None:
        names = [s.name for s in slots]
        if len(set(names)) != len(names):
            raise ValueError(f"layout {title!r} declares a slot twice")
        self.title = title
        self.slots = slots
        self._index = {s.name: i for i, s in enumerate(slots)}

    def __getitem__(self, name: str) -> int:
        return self._index[name]

    def __len__(self) -> int:
        return len(self.slots)

    def __contains__(self, name: object) -> bool:
        return name in self._index

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.slots)

    @property
    def units(self) -> dict[str, str]:
        return {s.name: s.unit for s in self.slots}

    def pack(self, values: Mapping[str, float]) -> np.ndarray:
        """A float vector with every slot filled from `values` (each slot exactly once)."""
        missing = [n for n in self.names if n not in values]
        extra = [n for n in values if n not in self._index]
        if missing or extra:
            raise ValueError(f"layout {self.title!r}: missing {missing}, unknown {extra}")
        return np.array([float(values[n]) for n in self.names], dtype=np.float64)

    def decode(
        self, rows: np.ndarray, names: tuple[str, ...] | None = None
    ) -> dict[str, np.ndarray]:
        """Columns of `rows` (m, len(self)) by name (copies), all slots or those named."""
        return {n: rows[:, self._index[n]].copy() for n in (names or self.names)}
