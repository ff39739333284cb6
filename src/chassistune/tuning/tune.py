"""`chassistune.tune(...)`: tune a controller's gains with any registered optimizer."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, overload

import numpy as np

from chassistune._rng import SeedLike
from chassistune.errors import InputError
from chassistune.optimizers.driver import OptimizeResult, drive
from chassistune.optimizers.registry import make
from chassistune.tuning.problem import TuningProblem, build_problem

if TYPE_CHECKING:
    from chassistune.tuning.robust.run import RobustTuneResult
    from chassistune.tuning.robust.spec import UncertaintySpec


@dataclass(frozen=True, kw_only=True)
class TuneResult(OptimizeResult):
    """An optimizer run on a tuning problem: the gains by name and the tuned controller's metrics
    on each road (`x` and `fun` are `best_gains` and `best_cost` in the box's order)."""

    problem: TuningProblem
    best_gains: dict[str, float]
    metrics: dict[str, dict[str, Any]] = field(default_factory=dict)

    @property
    def best_cost(self) -> float:
        return self.fun

    @property
    def optimizer(self) -> str:
        return self.method

    def as_dict(self) -> dict[str, Any]:
        """The `tune --json` object (DESIGN 7); `metrics` by road when several were tuned."""
        roads = self.problem.roads
        metrics: dict[str, Any] = self.metrics[roads[0]] if len(roads) == 1 else self.metrics
        sc = self.problem.scenarios[0]
        return {
            "plant": sc.plant,
            "preset": sc.preset,
            "roads": roads,
            "controller": sc.controller.name,
            "optimizer": self.optimizer,
            "objective": self.problem.objective,
            "aggregate": self.problem.aggregate,
            "bounds": dict(zip(self.problem.gain_names, self.problem.bounds, strict=True)),
            "hyperparameters": self.hyperparameters,
            "best_gains": self.best_gains,
            "best_cost": self.best_cost,
            "nfev": self.nfev,
            "nit": self.nit,
            "wall_time_s": self.wall_time_s,
            "history": self.history,
            "history_nfev": self.history_nfev,
            "metrics": metrics,
            "params": sc.params(),
        }


Progress = Callable[[int, int, float], None]
"""progress(nit, nfev, best cost so far), after every iteration."""


def run_optimizer(
    problem: TuningProblem,
    optimizer: str,
    pop_size: int,
    max_iter: int | None,
    max_evals: int | None,
    seed: SeedLike,
    progress: Progress | None = None,
    **hyper: Any,
) -> TuneResult:
    """Drive `optimizer` over `problem`; `progress(nit, nfev, best)` after each iteration."""
    if max_iter is None and max_evals is None:
        raise InputError("--iters", "give an iteration or an evaluation budget")
    opt = make(optimizer, problem.bounds, pop_size, seed, max_iter=max_iter, max_evals=max_evals,
               **hyper)
    run = drive(opt, problem, None if progress is None else
                lambda r: progress(r.nit, r.nfev, r.fun))
    best = np.asarray(run.x, dtype=float)
    return TuneResult(
        **vars(run),
        problem=problem,
        best_gains=dict(zip(problem.gain_names, best.tolist(), strict=True)),
        metrics={sc.road: sc.trace(best).metrics for sc in problem.scenarios},
    )


@overload
def tune(plant: str, controller: str, optimizer: str = ..., preset: str | None = ...,
         roads: Sequence[str] | str | None = ..., objective: str | None = ...,
         aggregate: str = ..., pop_size: int = ..., max_iter: int | None = ...,
         max_evals: int | None = ..., seed: int = ..., params: Mapping[str, object] | None = ...,
         bounds: Mapping[str, tuple[float, float]] | None = ...,
         progress: Progress | None = ..., uncertainty: None = ..., **hyper: Any) -> TuneResult: ...


@overload
def tune(plant: str, controller: str, optimizer: str = ..., preset: str | None = ...,
         roads: Sequence[str] | str | None = ..., objective: str | None = ...,
         aggregate: str = ..., pop_size: int = ..., max_iter: int | None = ...,
         max_evals: int | None = ..., seed: int = ..., params: Mapping[str, object] | None = ...,
         bounds: Mapping[str, tuple[float, float]] | None = ...,
         progress: Progress | None = ..., *,
         uncertainty: UncertaintySpec | Mapping[str, Any], **hyper: Any) -> RobustTuneResult: ...


def tune(
    plant: str,
    controller: str,
    optimizer: str = "derlsp-ao",
    preset: str | None = None,
    roads: Sequence[str] | str | None = None,
    objective: str | None = None,
    aggregate: str = "mean",
    pop_size: int = 30,
    max_iter: int | None = None,
    max_evals: int | None = None,
    seed: int = 0,
    params: Mapping[str, object] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    progress: Callable[[int, int, float], None] | None = None,
    uncertainty: UncertaintySpec | Mapping[str, Any] | None = None,
    **hyper: Any,
) -> TuneResult | RobustTuneResult:
    """Tune `controller` of `plant` on `roads` with `optimizer` (defaults of DESIGN 7).

    Without a budget, 100 iterations. The same seed gives the same result. With `uncertainty`
    (an `UncertaintySpec`, or the study's `[uncertainty]` table as a dict: {"vary": {"mass_kg":
    "80:120"}, "scenarios": 16, "aggregate": "max", "validate": 300}) the controller is tuned
    over the K training scenarios drawn from `seed` and validated, like `tune --vary`: the
    result is a `RobustTuneResult` (`.result` the tuning, `.validation`, `.as_dict()`).
    """
    if max_iter is None and max_evals is None:
        max_iter = 100
    road_list = [roads] if isinstance(roads, str) else roads
    problem = build_problem(plant, controller, preset, road_list, objective, aggregate, params,
                            bounds, seed)
    if uncertainty is not None:
        from chassistune.tuning.robust.run import tune_robust

        return tune_robust(problem, robust_spec(problem, uncertainty), optimizer, pop_size,
                           max_iter, max_evals, seed, params, progress, **hyper)
    return run_optimizer(problem, optimizer, pop_size, max_iter, max_evals, seed, progress,
                         **hyper)


def robust_spec(nominal: TuningProblem,
                uncertainty: UncertaintySpec | Mapping[str, Any]) -> UncertaintySpec:
    """An `UncertaintySpec` as given, or parsed from an `[uncertainty]` table against the
    parameters every scenario of `nominal` may vary."""
    from chassistune.tuning.robust.problem import known_for
    from chassistune.tuning.robust.spec import UncertaintySpec, parse_table

    if isinstance(uncertainty, UncertaintySpec):
        return uncertainty
    return parse_table(uncertainty, known_for(nominal))
