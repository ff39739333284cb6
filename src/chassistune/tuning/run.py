"""One optimizer run on a tuning problem (`run_optimizer`) and its result (`TuneResult`): the
winner's gains, metrics and step checks, and the default gains' cost it must beat."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from chassistune._rng import SeedLike
from chassistune.errors import InputError
from chassistune.optimizers.base import check_covers_population
from chassistune.optimizers.driver import OptimizeResult, drive
from chassistune.optimizers.registry import make
from chassistune.scenarios.refine import StepCheck, step_refinement
from chassistune.scenarios.registry import plant_spec
from chassistune.tuning.problem import TuningProblem


@dataclass(frozen=True)
class BoundHit:
    """A tuned gain at a bound of the box past which the cost still falls: an optimum the box
    plausibly cuts off (`TuneResult.gains_cut_off`)."""

    gain: str
    value: float
    bound: float
    probe: float
    """The gain's value past the bound that was scored (the other gains as tuned)."""
    probe_cost: float


@dataclass(frozen=True, kw_only=True)
class TuneResult(OptimizeResult):
    """An optimizer run on a tuning problem: the gains by name, the tuned controller's metrics
    on each road, by road how they move at a quarter of the integration step (`step_checks`),
    and the registry's default gains with their cost on the same problem, the baseline a tune
    must beat (`x` and `fun` are `best_gains` and `best_cost` in the box's order)."""

    problem: TuningProblem
    best_gains: dict[str, float]
    metrics: dict[str, dict[str, Any]] = field(default_factory=dict)
    step_checks: dict[str, StepCheck] = field(default_factory=dict)
    default_gains: dict[str, float] = field(default_factory=dict)
    default_cost: float = math.nan

    @property
    def best_cost(self) -> float:
        return self.fun

    @property
    def optimizer(self) -> str:
        return self.method

    def gains_cut_off(self, tolerance: float = 0.01, beyond: float = 0.1) -> list[BoundHit]:
        """Each tuned gain within `tolerance` of the box's width from a bound, where the cost
        with that gain `beyond` widths past the bound (other gains as tuned; a positive lower
        bound is not crossed below half its value) is lower than the best cost: the optimum
        plausibly lies outside the box. A lower bound at 0 is a gain's natural floor (the term
        switched off), never a cut-off optimum; one batch of at most k extra evaluations."""
        names, bounds = self.problem.gain_names, self.problem.bounds
        best = np.array([self.best_gains[n] for n in names])
        hits: list[tuple[int, float, float]] = []
        for i, (lo, hi) in enumerate(bounds):
            margin, step = tolerance * (hi - lo), beyond * (hi - lo)
            if hi - best[i] <= margin:
                hits.append((i, hi, hi + step))
            elif best[i] - lo <= margin and lo != 0.0:
                hits.append((i, lo, max(lo - step, lo / 2) if lo > 0 else lo - step))
        if not hits:
            return []
        probes = np.repeat(best[None, :], len(hits), axis=0)
        for row, (i, _, probe) in enumerate(hits):
            probes[row, i] = probe
        try:
            costs = np.asarray(self.problem(probes), dtype=float)
        except InputError:  # a value past the bound the controller refuses: nothing beyond
            return []
        return [
            BoundHit(names[i], float(best[i]), bound, probe, float(cost))
            for (i, bound, probe), cost in zip(hits, costs, strict=True)
            if cost < self.best_cost
        ]

    def worse_than_default(self) -> str | None:
        """One line when the tuned cost is above the default gains' cost, saying why it can
        be (the budget, or defaults outside the box), else None."""
        if not self.best_cost > self.default_cost:
            return None
        inside = all(
            lo <= self.default_gains[n] <= hi
            for n, (lo, hi) in zip(self.problem.gain_names, self.problem.bounds, strict=True)
        )
        why = (
            f"the budget ({self.nfev} evaluations) did not reach the defaults, which lie in "
            "the box: give more --iters, --evals or --pop, or another --optimizer"
            if inside
            else "the default gains lie outside the box the optimizer searched"
        )
        return (
            f"the tuned gains cost {self.best_cost:.6g}, worse than the default gains' "
            f"{self.default_cost:.6g}: {why}"
        )

    def test_on(
        self, roads: Sequence[str], params: Mapping[str, object] | None = None
    ) -> dict[str, dict[str, Any]]:
        """Metrics of the tuned gains on other roads (same plant, preset, controller and
        `params`), by road."""
        from chassistune.scenarios.registry import get_plant

        first = self.problem.scenarios[0]
        plant = get_plant(first.plant)
        gains = np.array([self.best_gains[n] for n in self.problem.gain_names])
        return {
            road: plant.scenario(
                first.preset, road, first.controller.name, params or {}, first.seed
            )
            .trace(gains)
            .metrics
            for road in roads
        }

    def as_dict(self) -> dict[str, Any]:
        """The `tune --json` object (design.md 7); `metrics` by road when several were tuned."""
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
            "default_gains": self.default_gains,
            "default_cost": self.default_cost,
            "nfev": self.nfev,
            "nit": self.nit,
            "wall_time_s": self.wall_time_s,
            "history": self.history,
            "history_nfev": self.history_nfev,
            "metrics": metrics,
            "step_check": {road: c.as_dict() for road, c in self.step_checks.items()},
            "params": sc.params(),
        }

    def step_warnings(self) -> list[str]:
        """One line per road whose figures move by more than the tolerance at the finer step:
        the winner's figures there are not converged, so the tune's ranking of candidates on
        that road is not meaningful; the line names the finer step to tune at."""
        return [
            f"step check on {road}: {c.warning}; the tune's ranking of candidates on {road} "
            f"is not meaningful at dt_s = {c.dt_s:g}: tune again with "
            f"--param dt_s={c.dt_s / c.factor:g}"
            for road, c in self.step_checks.items()
            if c.warning
        ]


class Incumbent:
    """The objective, remembering the best candidate of every batch it has scored: what an
    interrupted tune can still save. `best` is replaced as a whole (read from other threads)."""

    def __init__(self, fun: TuningProblem) -> None:
        self.fun = fun
        self.best: tuple[np.ndarray, float, int] | None = None  # (gains, cost, nfev)

    def __call__(self, x: np.ndarray) -> np.ndarray:
        cost = np.asarray(self.fun(x), dtype=float)
        nfev = (self.best[2] if self.best else 0) + len(cost)
        gains, value = (self.best[0], self.best[1]) if self.best else (None, math.inf)
        if len(cost) and float(cost.min()) < value:
            i = int(np.argmin(cost))
            gains, value = np.array(x[i], dtype=float), float(cost[i])
        if gains is not None:
            self.best = (gains, value, nfev)
        return cost


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
    incumbent: Incumbent | None = None,
    **hyper: Any,
) -> TuneResult:
    """Drive `optimizer` over `problem`; `progress(nit, nfev, best)` after each iteration;
    `incumbent` (wrapping `problem`) keeps the best so far while the run goes on."""
    if max_iter is None and max_evals is None:
        raise InputError("max_iter", "give an iteration or an evaluation budget")
    check_covers_population(pop_size, max_evals)
    opt = make(
        optimizer, problem.bounds, pop_size, seed, max_iter=max_iter, max_evals=max_evals, **hyper
    )
    run = drive(
        opt,
        incumbent or problem,
        None if progress is None else lambda r: progress(r.nit, r.nfev, r.fun),
    )
    best = np.asarray(run.x, dtype=float)
    defaults = problem.scenarios[0].gains_array(None)
    return TuneResult(
        **vars(run),
        problem=problem,
        best_gains=dict(zip(problem.gain_names, best.tolist(), strict=True)),
        metrics={sc.road: sc.trace(best).metrics for sc in problem.scenarios},
        step_checks=step_checks(problem, best),
        default_gains=dict(zip(problem.gain_names, defaults.tolist(), strict=True)),
        default_cost=float(problem(defaults[None, :])[0]),
    )


def step_checks(problem: TuningProblem, gains: np.ndarray) -> dict[str, StepCheck]:
    """The winner re-simulated at a quarter of the step on every road of a plant whose spec
    says it is `refinable` (`scenarios.refine.step_refinement`), by road."""
    return {
        sc.road: step_refinement(sc, gains, problem.params, problem.objective)
        for sc in problem.scenarios
        if plant_spec(sc.plant).refinable
    }
