"""`chassistune.minimize`: any registered optimizer over a (vectorized) objective, scipy-style."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from chassistune._rng import SeedLike
from chassistune.errors import InputError
from chassistune.optimizers.driver import Callback, OptimizeResult, drive
from chassistune.optimizers.registry import make


def minimize(
    fun: Callable[..., Any],
    bounds: Sequence[tuple[float, float]] | NDArray[np.float64],
    method: str = "ao",
    pop_size: int = 30,
    max_iter: int | None = None,
    max_evals: int | None = None,
    seed: SeedLike = 0,
    vectorized: bool = True,
    callback: Callback | None = None,
    **hyper: Any,
) -> OptimizeResult:
    """Minimize `fun` over the box `bounds` (a sequence of `(lo, hi)` pairs) with `method`.

    With `vectorized=True`, `fun` takes an `(n, d)` array and returns `n` costs; otherwise it takes
    one `(d,)` point and returns a number. NaN and inf costs count as +inf. At least one of
    `max_iter` and `max_evals` must be given; the first reached ends the run (`max_evals` exactly).
    `callback(intermediate)` runs after every iteration with the result so far; returning True
    stops the run. `**hyper` overrides the method's hyperparameters (see `chassistune list
    optimizers --json`).
    """
    if not callable(fun):
        raise InputError("fun", "expected a callable")
    opt = make(method, bounds, pop_size, seed, max_iter=max_iter, max_evals=max_evals, **hyper)
    return drive(opt, fun if vectorized else _pointwise(fun), callback)


def _pointwise(fun: Callable[..., Any]) -> Callable[[NDArray[np.float64]], NDArray[np.float64]]:
    """A batch objective calling the scalar `fun` once per row."""

    def batch(x: NDArray[np.float64]) -> NDArray[np.float64]:
        try:
            return np.array([fun(row) for row in x], dtype=float)
        except (TypeError, ValueError) as exc:
            raise InputError("fun", f"must return one number per point ({exc})") from None

    return batch
