"""One run of a study, in whatever process the executor chose: a spec in, a `RunResult` out.

Workers never touch the store. Any exception of the run (a raising objective, a bad value found
late) becomes a `failed` result carrying the error text, so the study goes on.
"""

from __future__ import annotations

import math
import platform
import time
import traceback
from functools import cache
from typing import Any

import numpy as np

from chassistune._io import jsonable
from chassistune.studies.records import RunResult, RunStatus
from chassistune.studies.spec import RunSpec


@cache
def versions() -> dict[str, str]:
    """Versions that can change a run's numbers (recorded with every run)."""
    from importlib.metadata import PackageNotFoundError, version

    out = {"python": platform.python_version()}
    for pkg in ("chassistune", "numpy", "scipy", "numba"):
        try:
            out[pkg] = version(pkg)
        except PackageNotFoundError:  # pragma: no cover - source checkout without metadata
            out[pkg] = "unknown"
    return out


def _run_function(spec: RunSpec) -> dict[str, Any]:
    """A benchmark-function run: our optimizer through the driver, or a peer."""
    from chassistune.optimizers.driver import drive
    from chassistune.optimizers.peers import PEERS, run_peer
    from chassistune.optimizers.registry import make
    from chassistune.tuning.functions import build_function_problem

    problem = build_function_problem(spec.roads[0], spec.scenario_seed)
    if spec.optimizer_name in PEERS:
        result = run_peer(
            spec.optimizer_name,
            problem,
            problem.bounds,
            spec.pop_size,
            spec.max_iter,
            spec.max_evals,
            spec.seed_sequence(),
        )
    else:
        hyper: dict[str, Any] = dict(spec.hyperparameters)
        result = drive(
            make(
                spec.optimizer_name,
                problem.bounds,
                spec.pop_size,
                spec.optimizer_rng(),
                max_iter=spec.max_iter,
                max_evals=spec.max_evals,
                **hyper,
            ),
            problem,
        )
    return {
        "best_gains": dict(zip(problem.gain_names, result.x.tolist(), strict=True)),
        "best_cost": result.fun,
        "nfev": result.nfev,
        "nit": result.nit,
        "history": result.history,
        "history_nfev": result.history_nfev,
        "metrics": {},
        "test_costs": {},
        "diagnostics": result.diagnostics,
    }


def _run(spec: RunSpec) -> dict[str, Any]:
    from chassistune.scenarios.registry import get_plant
    from chassistune.studies.bbob import BBOB_KIND, bbob_numbers
    from chassistune.studies.problems import problem_for
    from chassistune.tuning.functions import FUNCTION_KIND
    from chassistune.tuning.robust.problem import RobustProblem
    from chassistune.tuning.robust.run import robust_summary
    from chassistune.tuning.run import run_optimizer

    if spec.plant == FUNCTION_KIND:
        return _run_function(spec)
    if spec.plant == BBOB_KIND:
        return bbob_numbers(spec)
    seed = spec.scenario_seed
    problem = problem_for(spec.model_dump(), seed, spec.seed_sequence())
    hyper: dict[str, Any] = dict(spec.hyperparameters)
    result = run_optimizer(
        problem,
        spec.optimizer_name,
        spec.pop_size,
        spec.max_iter,
        spec.max_evals,
        spec.optimizer_rng(),
        **hyper,
    )
    best = np.array([result.best_gains[n] for n in problem.gain_names]).reshape(1, -1)
    tuned = {sc.road: sc for sc in problem.scenarios}
    plant = get_plant(spec.plant)
    test_costs = {}
    for road in spec.test_roads:
        sc = tuned.get(road) or plant.scenario(
            spec.preset, road, spec.controller, spec.params, seed
        )
        test_costs[road] = float(sc.cost(best, spec.objective)[0])
    robust = None
    if isinstance(problem, RobustProblem):  # training summary and validation
        robust = robust_summary(problem, best[0])
    return {
        "robust": robust,
        "best_gains": result.best_gains,
        "best_cost": result.best_cost,
        "nfev": result.nfev,
        "nit": result.nit,
        "history": result.history,
        "history_nfev": result.history_nfev,
        "metrics": result.metrics,
        "test_costs": test_costs,
        "diagnostics": result.diagnostics,
        "step_check": {road: c.as_dict() for road, c in result.step_checks.items()},
    }


def execute_run(spec: RunSpec) -> RunResult:
    """Do one run: completed with its numbers, or failed with the error text."""
    t0 = time.perf_counter()
    try:
        numbers = _run(spec)
        if not math.isfinite(numbers["best_cost"]):
            raise FloatingPointError(f"best cost is {numbers['best_cost']}")
    except Exception as exc:
        last = traceback.extract_tb(exc.__traceback__)[-1:]
        where = f" (at {last[0].filename.rsplit('/', 1)[-1]}:{last[0].lineno})" if last else ""
        return failed_result(spec, f"{type(exc).__name__}: {exc}{where}", time.perf_counter() - t0)
    return RunResult(
        key=spec.key,
        spec_hash=spec.spec_hash,
        status=RunStatus.COMPLETED,
        wall_time_s=time.perf_counter() - t0,
        versions=versions(),
        **jsonable(numbers),
    )


def failed_result(spec: RunSpec, error: str, wall_time_s: float = math.nan) -> RunResult:
    """A failed run: raised in the worker, or lost outside it (a dead worker: no wall time)."""
    return RunResult(
        key=spec.key,
        spec_hash=spec.spec_hash,
        status=RunStatus.FAILED,
        wall_time_s=wall_time_s,
        versions=versions(),
        error=error,
    )
