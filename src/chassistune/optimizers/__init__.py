"""Batch ask/tell optimizers (registry in `registry`), and `minimize`."""

from chassistune.optimizers.minimize import MinimizeResult, minimize

__all__ = ["MinimizeResult", "minimize"]
