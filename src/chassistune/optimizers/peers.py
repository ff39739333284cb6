"""Reference implementations beside ours: mealpy 3.0.3's AO, GWO, MFO, ABC, DE, PSO, GA, POA
(`mealpy:ao`, ...) and scipy's differential_evolution (`scipy:de`), for optimizer comparisons
that name them. Each runs with our hyperparameters where it has them, the same population and the
same budget, and returns our `OptimizeResult` (its history per epoch of the peer).

mealpy is optional (`pip install --no-deps mealpy==3.0.3 opfunu==1.0.4`, design.md 10); it is
imported only when a mealpy peer runs.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from chassistune._rng import int_seed, make_rng
from chassistune.optimizers.driver import Objective, OptimizeResult

MEALPY = ("ao", "gwo", "mfo", "abc", "de", "pso", "ga", "poa")
PEERS = (*(f"mealpy:{m}" for m in MEALPY), "scipy:de")


@dataclass(frozen=True)
class _Run:
    """What every peer is given: the batch objective, the box as an array, the population, the
    budgets and the seed."""

    fun: Objective
    bounds: np.ndarray
    pop: int
    max_iter: int | None
    max_evals: int | None
    seed: np.random.SeedSequence

    def epochs(self, per_epoch: int) -> int:
        """`max_iter`, else the epochs of `per_epoch` evaluations that `max_evals` pays for after
        the initial population (at least one)."""
        if self.max_iter is not None:
            return self.max_iter
        return max(1, (int(self.max_evals or 0) - self.pop) // per_epoch)


def _result(
    name: str,
    x: np.ndarray,
    fun: float,
    nfev: int,
    history: Sequence[float],
    history_nfev: Sequence[int],
    wall: float,
) -> OptimizeResult:
    return OptimizeResult(
        x=np.asarray(x, dtype=float),
        fun=float(fun),
        nfev=int(nfev),
        nit=len(history),
        history=np.asarray(history, dtype=float),
        history_nfev=np.asarray(history_nfev, dtype=np.int64),
        wall_time_s=wall,
        method=name,
        success=bool(np.isfinite(fun)),
        message="budget reached",
    )


def _mealpy(method: str, run: _Run) -> OptimizeResult:
    from mealpy import FloatVar
    from mealpy.evolutionary_based import DE, GA
    from mealpy.swarm_based import ABC, AO, GWO, MFO, POA, PSO

    fun, bounds, pop, max_evals = run.fun, run.bounds, run.pop, run.max_evals
    d = bounds.shape[0]
    per_epoch = 2 * pop if method in ("abc", "poa") else pop
    epochs = run.epochs(per_epoch)
    classes: dict[str, Callable[[], Any]] = {
        "ao": lambda: AO.OriginalAO(epoch=epochs, pop_size=pop),
        "gwo": lambda: GWO.OriginalGWO(epoch=epochs, pop_size=pop),
        "mfo": lambda: MFO.OriginalMFO(epoch=epochs, pop_size=pop),
        "abc": lambda: ABC.OriginalABC(epoch=epochs, pop_size=pop, n_limits=pop * d),
        "de": lambda: DE.OriginalDE(epoch=epochs, pop_size=pop, wf=0.5, cr=0.9, strategy=0),
        "pso": lambda: PSO.OriginalPSO(epoch=epochs, pop_size=pop, c1=1.49445, c2=1.49445, w=0.729),
        "ga": lambda: GA.BaseGA(epoch=epochs, pop_size=pop, pc=0.9, pm=1.0 / d),
        "poa": lambda: POA.OriginalPOA(epoch=epochs, pop_size=pop),
    }
    calls = [0]

    def one(x: np.ndarray) -> float:
        calls[0] += 1
        return float(np.asarray(fun(x[None, :]))[0])

    problem = {
        "obj_func": one,
        "bounds": FloatVar(lb=bounds[:, 0].tolist(), ub=bounds[:, 1].tolist()),
        "minmax": "min",
        "log_to": None,
    }
    model = classes[method]()
    t0 = time.perf_counter()
    best = model.solve(
        problem, termination={"max_fe": max_evals} if max_evals else None, seed=int_seed(run.seed)
    )
    wall = time.perf_counter() - t0
    history = [float(v) for v in model.history.list_global_best_fit]
    spent = [min(pop + per_epoch * (i + 1), calls[0]) for i in range(len(history))]
    return _result(
        f"mealpy:{method}", best.solution, best.target.fitness, calls[0], history, spent, wall
    )


def _scipy_de(run: _Run) -> OptimizeResult:
    """rand1bin, F 0.5, CR 0.9, `pop` uniform initial points, no polishing, no early stop."""
    from scipy.optimize import differential_evolution

    fun, bounds = run.fun, run.bounds
    rng = make_rng(run.seed)
    init = bounds[:, 0] + rng.random((run.pop, bounds.shape[0])) * (bounds[:, 1] - bounds[:, 0])
    rows = [0]
    history: list[float] = []
    spent: list[int] = []
    best = [np.inf]

    def batch(x: np.ndarray) -> np.ndarray:  # scipy passes (d, S) and counts calls, not rows
        pts = np.atleast_2d(x.T)
        rows[0] += pts.shape[0]
        f = np.asarray(fun(pts), dtype=float)
        best[0] = min(best[0], float(f.min()))
        return f

    def record(*_: object) -> None:
        history.append(best[0])
        spent.append(rows[0])

    t0 = time.perf_counter()
    res = differential_evolution(
        batch,
        bounds,
        strategy="rand1bin",
        maxiter=run.epochs(run.pop),
        mutation=0.5,
        recombination=0.9,
        rng=rng,
        polish=False,
        init=init,
        tol=0.0,
        atol=0.0,
        vectorized=True,
        updating="deferred",
        callback=record,
    )
    return _result("scipy:de", res.x, res.fun, rows[0], history, spent, time.perf_counter() - t0)


def run_peer(
    name: str,
    fun: Objective,
    bounds: Sequence[tuple[float, float]],
    pop_size: int,
    max_iter: int | None,
    max_evals: int | None,
    seed: np.random.SeedSequence,
) -> OptimizeResult:
    """Run peer `name` (one of PEERS) on the batch objective `fun` over `bounds`."""
    run = _Run(fun, np.asarray(bounds, dtype=float), pop_size, max_iter, max_evals, seed)
    if name == "scipy:de":
        return _scipy_de(run)
    return _mealpy(name.split(":", 1)[1], run)
