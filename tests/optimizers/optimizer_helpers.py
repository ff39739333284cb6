"""Shared helpers for the optimizer tests."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from chassistune.optimizers.base import Optimizer
from chassistune.optimizers.registry import make


def drive(opt: Optimizer, fun: Callable[[np.ndarray], np.ndarray]) -> Optimizer:
    """Run an optimizer to its end with a vectorized objective."""
    while not opt.done:
        x = opt.ask()
        opt.tell(x, fun(x))
    return opt


def run(
    name: str,
    fun: Callable[[np.ndarray], np.ndarray],
    bounds: np.ndarray,
    pop: int = 30,
    seed: int = 0,
    **kw: object,
) -> Optimizer:
    return drive(make(name, bounds, pop, seed, **kw), fun)  # type: ignore[arg-type]
