"""The kernels' import path of the declared layouts (`chassistune.layout`, where `Layout` and
`Slot` live so that the control laws below `sim` declare theirs the same way)."""

from chassistune.layout import Layout, Slot

__all__ = ["Layout", "Slot"]
