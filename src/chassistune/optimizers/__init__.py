"""Batch ask/tell optimizers (registry in `registry`), the one loop `drive`, and `minimize`."""

from chassistune.optimizers.driver import OptimizeResult, drive
from chassistune.optimizers.minimize import minimize

__all__ = ["OptimizeResult", "drive", "minimize"]
