"""Registered optimizers on the COCO/BBOB suite (Hansen et al. 2021, "COCO: a platform for
comparing continuous optimizers in a black-box setting"; the functions: Hansen et al. 2009).

One run is one optimizer on one BBOB problem (function 1-24, dimension, instance) at a budget
of `evals_per_dim` x D evaluations, evaluated by `cocoex` without an observer. It records its
improvement trace: every evaluation that lowered the best cost, as (evaluation number, cost,
point). Runs execute on the study executors (serial, process, Dask) through
`studies.worker.execute_run`, like every study run; `studies.bbob_runner.run_plan` writes each
finished run into the study store (DIR/study.sqlite, one transaction per run): `history` and
`history_nfev` hold the trace's costs and evaluation numbers, `metrics["improvements"]["x"]` its
points. A killed run leaves no row and is redone; finished ones are skipped. COCO's data
folder is written afterwards from the store alone (`studies.coco_data`): no observer ever writes
from a run.

Seeds: run seed index = the instance number, so every optimizer, function and dimension at one
instance starts from the same child of the root seed.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from chassistune.optimizers.base import FloatArray
from chassistune.studies.spec import RunSpec

SUITE = "bbob"
FUNCTIONS = tuple(range(1, 25))
DIMENSIONS = (2, 3, 5, 10, 20)
BBOB_KIND = "bbob"
"""The `plant` field of a BBOB run spec."""


def problem_id(function: int, dim: int, instance: int) -> str:
    """COCO's problem id, e.g. `bbob_f001_i01_d02`."""
    return f"{SUITE}_f{function:03d}_i{instance:02d}_d{dim:02d}"


_ID = re.compile(r"^bbob_f(\d{3})_i(\d{2,})_d(\d{2,})$")


def parse_problem_id(pid: str) -> tuple[int, int, int]:
    """(function, dimension, instance) of a COCO problem id."""
    m = _ID.match(pid)
    if m is None:
        raise ValueError(f"not a BBOB problem id: {pid!r}")
    return int(m.group(1)), int(m.group(3)), int(m.group(2))


def default_instances() -> tuple[int, ...]:
    """The suite's current instances (cocoex's default for `bbob`)."""
    import cocoex

    suite = cocoex.Suite(SUITE, "", "function_indices:1 dimensions:2")
    return tuple(sorted(p.id_instance for p in suite))


def get_problem(function: int, dim: int, instance: int) -> Any:
    """The cocoex problem (no observer)."""
    import cocoex

    suite = cocoex.Suite(
        SUITE,
        f"instances:{instance}",
        f"function_indices:{function} dimensions:{dim} instance_indices:1",
    )
    return suite.get_problem_by_function_dimension_instance(function, dim, instance)


@dataclass(frozen=True)
class BBOBPlan:
    """Optimizers x functions x dimensions x instances, at one budget and population."""

    name: str
    optimizers: tuple[str, ...]
    functions: tuple[int, ...] = FUNCTIONS
    dimensions: tuple[int, ...] = DIMENSIONS
    instances: tuple[int, ...] = field(default_factory=default_instances)
    evals_per_dim: int = 1000
    pop_size: int = 30
    root_seed: int = 0

    def runs(self) -> Iterator[RunSpec]:
        """One spec per run, ordered by optimizer, function, dimension, instance."""
        for opt in self.optimizers:
            for f in self.functions:
                for d in self.dimensions:
                    for i in self.instances:
                        yield self.spec(opt, f, d, i)

    def spec(self, optimizer: str, function: int, dim: int, instance: int) -> RunSpec:
        pid = problem_id(function, dim, instance)
        return RunSpec(
            study=self.name,
            group=SUITE,
            scenario=pid,
            plant=BBOB_KIND,
            preset="",
            controller="",
            objective="value",
            roads=(pid,),
            aggregate="mean",
            test_roads=(),
            params={},
            bounds={f"x{j + 1}": (-5.0, 5.0) for j in range(dim)},
            optimizer=optimizer,
            optimizer_name=optimizer,
            hyperparameters={},
            pop_size=self.pop_size,
            max_iter=None,
            max_evals=self.evals_per_dim * dim,
            root_seed=self.root_seed,
            seed=instance,
        )


class ImprovementTrace:
    """A batch objective that counts evaluations and keeps every improvement of the best cost."""

    def __init__(self, fun: Callable[[FloatArray], float]) -> None:
        self.fun = fun
        self.nfev = 0
        self.best = math.inf
        self.nfevs: list[int] = []
        self.costs: list[float] = []
        self.points: list[list[float]] = []

    def __call__(self, x: FloatArray) -> FloatArray:
        out = np.empty(x.shape[0])
        for k, row in enumerate(x):
            out[k] = self.fun(row)
            self.nfev += 1
            if out[k] < self.best:
                self.best = float(out[k])
                self.nfevs.append(self.nfev)
                self.costs.append(self.best)
                self.points.append(row.tolist())
        return out


def bbob_numbers(spec: RunSpec) -> dict[str, Any]:
    """One BBOB run's numbers: the optimizer through the ask/tell driver, costs from cocoex
    (`studies.worker.execute_run` makes them the run's result, on any executor)."""
    from chassistune.optimizers.driver import drive
    from chassistune.optimizers.registry import make

    function, dim, instance = parse_problem_id(spec.scenario)
    problem = get_problem(function, dim, instance)
    bounds = np.stack([problem.lower_bounds, problem.upper_bounds], axis=1)
    trace = ImprovementTrace(lambda x: float(problem(x)))
    opt = make(
        spec.optimizer_name,
        bounds,
        spec.pop_size,
        spec.optimizer_rng(),
        max_evals=spec.max_evals,
    )
    result = drive(opt, trace)
    problem.free()
    return {
        "best_cost": result.fun,
        "nfev": result.nfev,
        "nit": result.nit,
        "best_gains": dict(zip(spec.bounds, result.x.tolist(), strict=True)),
        "metrics": {"improvements": {"x": trace.points}},
        "test_costs": {},
        "history": trace.costs,
        "history_nfev": trace.nfevs,
        "diagnostics": result.diagnostics,
    }
