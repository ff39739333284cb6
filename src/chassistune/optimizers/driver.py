"""The one ask/tell loop: drive an optimizer over a batch objective and return `OptimizeResult`.

`minimize`, `tune`, the study worker, the bench figures and the paper scripts all run their
optimizers through `drive`, so a run's numbers depend only on the optimizer, its seed and the
objective, never on which caller drove it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from chassistune.optimizers.base import FloatArray, Optimizer

Objective = Callable[[FloatArray], ArrayLike]
"""Costs of a batch: an (m, d) array of points in, m numbers out."""


@dataclass(frozen=True, kw_only=True)
class OptimizeResult:
    """The outcome of one optimizer run (scipy's OptimizeResult names where they exist)."""

    x: NDArray[np.float64]  # best point found
    fun: float  # its cost
    nfev: int
    nit: int
    history: NDArray[np.float64]  # best-so-far cost after each iteration
    history_nfev: NDArray[np.int64]  # evaluations spent at each of those points
    wall_time_s: float  # time spent in the ask/tell loop (objective included)
    method: str
    success: bool
    message: str
    hyperparameters: dict[str, Any] = field(default_factory=dict)
    diagnostics: dict[str, Any] = field(default_factory=dict)  # what the algorithm reports

    def __getitem__(self, key: str) -> Any:  # scipy's OptimizeResult is also a mapping
        return getattr(self, key)


Callback = Callable[[OptimizeResult], object]
"""Called after every iteration with the result so far; returning True stops the run."""


def drive(opt: Optimizer, fun: Objective, callback: Callback | None = None) -> OptimizeResult:
    """Ask, evaluate `fun` on the whole batch, tell, until the budget is spent or `callback`
    returns True; the result of the run."""
    stopped = False
    t0 = time.perf_counter()
    while not opt.done:
        x = opt.ask()
        before = opt.nit
        opt.tell(x, fun(x))
        if (
            callback is not None
            and opt.nit > before
            and callback(_result(opt, time.perf_counter() - t0, "running"))
        ):
            stopped = True
            break
    wall = time.perf_counter() - t0
    return _result(opt, wall, "stopped by the callback" if stopped else _why(opt))


def _why(opt: Optimizer) -> str:
    if opt.max_evals is not None and opt.nfev >= opt.max_evals:
        return "max_evals reached"
    return "max_iter reached"


def _result(opt: Optimizer, wall_time_s: float, message: str) -> OptimizeResult:
    return OptimizeResult(
        x=opt.best_x.copy(),
        fun=float(opt.best_f),
        nfev=int(opt.nfev),
        nit=int(opt.nit),
        history=opt.history,
        history_nfev=opt.history_nfev,
        wall_time_s=wall_time_s,
        method=opt.name,
        success=math.isfinite(opt.best_f),
        message=message,
        hyperparameters=opt.hyper.as_dict(),
        diagnostics=dict(opt.diagnostics),
    )
