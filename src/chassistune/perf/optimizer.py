"""Optimizer figures of design.md 8: `optimizer_us_per_eval` and `optimizer_speedup_vs_mealpy`.

AO on F5 (Rosenbrock), d = 30, N = 50, 500 iterations. The optimizer-side time is the wall time of
a whole run minus the time spent inside the objective, per evaluation. The baseline is mealpy
3.0.3's OriginalAO on the same problem with the same numpy-vectorized Rosenbrock (mealpy calls it
once per candidate), measured the same way in the same run. mealpy is imported here only, and only
when `figures` is called.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np

from chassistune.benchmarks.functions import get as get_function
from chassistune.optimizers.driver import drive
from chassistune.optimizers.registry import make

DIM, POP, ITERS = 30, 50, 500


class _Timed:
    """Wrap an objective and accumulate the time spent inside it and the number of calls."""

    def __init__(self, fun: Callable[[Any], Any]) -> None:
        self.fun = fun
        self.seconds = 0.0
        self.calls = 0

    def __call__(self, x: Any) -> Any:
        t0 = time.perf_counter()
        out = self.fun(x)
        self.seconds += time.perf_counter() - t0
        self.calls += 1
        return out


def ours_us_per_eval(seed: int = 0) -> float:
    """Optimizer-side microseconds per evaluation of our AO (one run)."""
    f5 = get_function("F5")
    timed = _Timed(f5)
    run = drive(make("ao", f5.bounds(DIM), POP, seed, max_iter=ITERS), timed)
    return 1e6 * (run.wall_time_s - timed.seconds) / run.nfev


def mealpy_us_per_eval(epochs: int, seed: int = 0) -> float:
    """Optimizer-side microseconds per evaluation of mealpy's OriginalAO (one run)."""
    from mealpy import FloatVar
    from mealpy.swarm_based.AO import OriginalAO

    f5 = get_function("F5")

    def rosenbrock(x: np.ndarray) -> float:  # numpy-vectorized over d, one candidate per call
        return float(np.sum(100.0 * (x[1:] - x[:-1] ** 2) ** 2 + (x[:-1] - 1.0) ** 2))

    timed = _Timed(rosenbrock)
    lo, hi = f5.bounds(DIM).T
    problem = {
        "obj_func": timed,
        "bounds": FloatVar(lb=lo.tolist(), ub=hi.tolist()),
        "minmax": "min",
        "log_to": None,
    }
    model = OriginalAO(epoch=epochs, pop_size=POP)
    t0 = time.perf_counter()
    model.solve(problem, seed=seed)
    wall = time.perf_counter() - t0
    return 1e6 * (wall - timed.seconds) / timed.calls


def figures(quick: bool = False) -> dict[str, float]:
    """`optimizer_us_per_eval` (target <= 5) and `optimizer_speedup_vs_mealpy` (target >= 10).

    Ours: the best of 3 (quick) or 7 runs of 500 iterations. mealpy: the best of 1 run of 100
    epochs (quick) or 2 runs of 500 epochs; its per-evaluation overhead does not depend on the
    epoch count. Best-of-n on both sides because this machine is shared and noisy.
    """
    reps_ours, reps_mealpy, epochs = (3, 1, 100) if quick else (7, 2, ITERS)
    ours = min(ours_us_per_eval(seed) for seed in range(reps_ours))
    theirs = min(mealpy_us_per_eval(epochs, seed) for seed in range(reps_mealpy))
    return {
        "optimizer_us_per_eval": ours,
        "optimizer_speedup_vs_mealpy": theirs / ours,
        "optimizer_mealpy_us_per_eval": theirs,
    }
