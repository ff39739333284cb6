"""One run of a study, in whatever process the executor chose: a spec in, a plain dict out.

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

from chassistune.studies.spec import RunSpec

COMPLETED = "completed"
FAILED = "failed"


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


def plain(x: Any) -> Any:
    """JSON-ready Python values (numpy scalars and arrays converted; NaN kept as float)."""
    if isinstance(x, dict):
        return {str(k): plain(v) for k, v in x.items()}
    if isinstance(x, list | tuple | np.ndarray):
        return [plain(v) for v in (x.tolist() if isinstance(x, np.ndarray) else x)]
    if isinstance(x, bool | np.bool_):
        return bool(x)
    if isinstance(x, int | np.integer):
        return int(x)
    if isinstance(x, float | np.floating):
        return float(x)
    return x if x is None or isinstance(x, str) else str(x)


def _run(spec: RunSpec) -> dict[str, Any]:
    from chassistune.scenarios.registry import get_plant
    from chassistune.tuning.problem import build_problem
    from chassistune.tuning.tune import run_optimizer

    seed = spec.scenario_seed
    problem = build_problem(spec.plant, spec.controller, spec.preset, list(spec.roads),
                            spec.objective, spec.aggregate, spec.params, spec.bounds, seed)
    hyper: dict[str, Any] = dict(spec.hyperparameters)
    result = run_optimizer(problem, spec.optimizer_name, spec.pop_size, spec.max_iter,
                           spec.max_evals, spec.optimizer_rng(), **hyper)
    best = np.array([result.best_gains[n] for n in problem.gain_names]).reshape(1, -1)
    tuned = {sc.road: sc for sc in problem.scenarios}
    plant = get_plant(spec.plant)
    test_costs = {}
    for road in spec.test_roads:
        sc = tuned.get(road) or plant.scenario(spec.preset, road, spec.controller, spec.params,
                                               seed)
        test_costs[road] = float(sc.cost(best, spec.objective)[0])
    return {
        "best_gains": result.best_gains,
        "best_cost": result.best_cost,
        "nfev": result.nfev,
        "nit": result.nit,
        "history": result.history,
        "history_nfev": result.history_nfev,
        "metrics": result.metrics,
        "test_costs": test_costs,
    }


def execute_run(spec: RunSpec) -> dict[str, Any]:
    """Do one run; return {key, spec_hash, status, error, wall_time_s, versions, ...results}."""
    t0 = time.perf_counter()
    out: dict[str, Any] = {"key": spec.key, "spec_hash": spec.spec_hash}
    try:
        out.update(plain(_run(spec)))
        if not math.isfinite(out["best_cost"]):
            raise FloatingPointError(f"best cost is {out['best_cost']}")
        out["status"], out["error"] = COMPLETED, None
    except Exception as exc:
        last = traceback.extract_tb(exc.__traceback__)[-1:]
        where = f" (at {last[0].filename.rsplit('/', 1)[-1]}:{last[0].lineno})" if last else ""
        out = {"key": spec.key, "spec_hash": spec.spec_hash, "status": FAILED,
               "error": f"{type(exc).__name__}: {exc}{where}"}
    out["wall_time_s"] = time.perf_counter() - t0
    out["versions"] = versions()
    return out


def failed_result(spec: RunSpec, error: str) -> dict[str, Any]:
    """The result recorded when a run could not finish for reasons outside it (lost worker)."""
    return {"key": spec.key, "spec_hash": spec.spec_hash, "status": FAILED, "error": error,
            "wall_time_s": math.nan, "versions": versions()}
