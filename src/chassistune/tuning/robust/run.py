"""`tune_robust(...)`: tune over a training set of K scenarios, then validate.

What `tune --vary ... --scenarios K --sampler S --aggregate A --validate N --beta B` does once
its options are checked (`spec.spec_from_options` over `problem.known_for(nominal)`, before any
work): the K training scenarios drawn from the run seed, any optimizer driven over the robust
cost, the winner validated on N fresh Monte Carlo draws. `as_dict()` is the `tune --json` object
plus `uncertainty`, `training` and `validation`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from chassistune.tuning.problem import TuningProblem
from chassistune.tuning.robust.problem import RobustProblem, robust_problem
from chassistune.tuning.robust.spec import UncertaintySpec
from chassistune.tuning.robust.validation import ValidationResult
from chassistune.tuning.run import TuneResult, run_optimizer


@dataclass
class RobustTuneResult:
    """The tuning result on the robust cost, the winner's costs per training scenario, and its
    validation (None when N = 0)."""

    result: TuneResult
    problem: RobustProblem
    training_costs: np.ndarray
    validation: ValidationResult | None

    def as_dict(self) -> dict[str, Any]:
        return {
            **self.result.as_dict(),
            **summary_fields(self.problem, self.training_costs, self.validation),
        }


def summary_fields(
    problem: RobustProblem, training_costs: np.ndarray, validation: ValidationResult | None
) -> dict[str, Any]:
    """`uncertainty`, `training` (the draws and the winner's cost on each scenario x road) and
    `validation` (None when N = 0): what a robust run adds to the `tune --json` object."""
    spec = problem.spec
    return {
        "uncertainty": {
            "vary": [p.describe() for p in spec.params],
            "scenarios": spec.scenarios,
            "sampler": spec.sampler,
            "aggregate": str(spec.aggregate),
        },
        "training": {
            "names": list(problem.training.names),
            "values": problem.training.values,
            "costs": np.asarray(training_costs).ravel(),
        },
        "validation": None if validation is None else validation.as_dict(),
    }


def robust_summary(problem: RobustProblem, gains: np.ndarray) -> dict[str, Any]:
    """`summary_fields` of one winner: its training costs and its validation (N = spec.validate
    draws of the run's validation stream)."""
    best = np.asarray(gains, dtype=np.float64)
    validation = problem.validate(best) if problem.spec.validate else None
    return summary_fields(problem, problem.costs(best[None, :])[0], validation)


def tune_robust(
    nominal: TuningProblem,
    spec: UncertaintySpec,
    optimizer: str = "derlsp-ao",
    pop_size: int = 30,
    max_iter: int | None = 100,
    max_evals: int | None = None,
    seed: int = 0,
    params: Mapping[str, object] | None = None,
    progress: Callable[[int, int, float], None] | None = None,
    **hyper: Any,
) -> RobustTuneResult:
    """Tune the nominal problem's controller (built with the same `params` and `seed`) over the
    training set of `spec`, then validate the winner on spec.validate fresh draws."""
    problem = robust_problem(nominal, spec, params, seed)
    result = run_optimizer(
        problem, optimizer, pop_size, max_iter, max_evals, seed, progress, **hyper
    )
    best = np.array([result.best_gains[n] for n in problem.gain_names])
    training_costs = problem.costs(best[None, :])[0]
    validation = problem.validate(best) if spec.validate else None
    return RobustTuneResult(result, problem, training_costs, validation)
