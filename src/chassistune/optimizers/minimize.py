"""`chassistune.minimize`: any registered optimizer over a (vectorized) objective, scipy-style."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from chassistune._rng import SeedLike
from chassistune.errors import InputError
from chassistune.optimizers.registry import make


@dataclass(frozen=True)
class MinimizeResult:
    """The outcome of `minimize` (scipy's OptimizeResult names where they exist)."""

    x: NDArray[np.float64]
    fun: float
    nfev: int
    nit: int
    history: NDArray[np.float64]  # best-so-far cost after each iteration
    history_nfev: NDArray[np.int64]  # evaluations spent at each of those points
    method: str
    success: bool
    message: str
    hyperparameters: dict[str, Any] = field(default_factory=dict)

    def __getitem__(self, key: str) -> Any:  # scipy's OptimizeResult is also a mapping
        return getattr(self, key)


def minimize(
    fun: Callable[..., Any],
    bounds: Sequence[tuple[float, float]] | NDArray[np.float64],
    method: str = "ao",
    pop_size: int = 30,
    max_iter: int | None = None,
    max_evals: int | None = None,
    seed: SeedLike = 0,
    vectorized: bool = True,
    callback: Callable[[MinimizeResult], object] | None = None,
    **hyper: Any,
) -> MinimizeResult:
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
    stopped = False
    while not opt.done:
        x = opt.ask()
        if vectorized:
            f = fun(x)
        else:
            try:
                f = np.array([fun(row) for row in x], dtype=float)
            except (TypeError, ValueError) as exc:
                raise InputError("fun", f"must return one number per point ({exc})") from None
        before = opt.nit
        opt.tell(x, f)
        if callback is not None and opt.nit > before and callback(_result(opt, method, "running")):
            stopped = True
            break
    message = "stopped by the callback" if stopped else _why(opt)
    return _result(opt, method, message)


def _why(opt: Any) -> str:
    if opt.max_evals is not None and opt.nfev >= opt.max_evals:
        return "max_evals reached"
    return "max_iter reached"


def _result(opt: Any, method: str, message: str) -> MinimizeResult:
    return MinimizeResult(
        x=opt.best_x.copy(),
        fun=float(opt.best_f),
        nfev=int(opt.nfev),
        nit=int(opt.nit),
        history=opt.history,
        history_nfev=opt.history_nfev,
        method=method,
        success=bool(np.isfinite(opt.best_f)),
        message=message,
        hyperparameters=opt.hyper.as_dict(),
    )
