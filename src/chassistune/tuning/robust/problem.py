"""n candidates x K scenarios (x R roads): the robust tuning cost and the validation.

`robust_problem` takes the nominal problem (the plain `build_problem`: controller box, objective,
roads), draws the run's training set once (common random numbers) and builds its K R
scenarios before any evaluation, so a bad draw is refused before work starts. The cost of a
population is the (n, K, R) matrix of per-scenario costs, aggregated per candidate.

Evaluation is one kernel call of n rows per scenario (K R calls). The ABS kernel accepts per-row
plant parameters, but the tire curve, the controller vector and the scoring stay per call, so a
draw of `mu_scale` (or any curve parameter) splits the batch anyway; one call of n K rows would
save 1.27-1.28x where it applies (`perf.robust`; docs/robust.md, "Cost: n candidates x K
scenarios").

A `RobustProblem` is a `TuningProblem` (its `scenarios` are the nominal ones, one per road, used
for the tuned controller's metrics), so the optimizer loop drives it unchanged.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from chassistune.errors import InputError
from chassistune.scenarios.base import PENALTY, Scenario
from chassistune.tuning.problem import TuningProblem
from chassistune.tuning.robust.plant_params import known_ranges, scenario_builder
from chassistune.tuning.robust.sampling import (
    SENSITIVITY,
    TRAINING,
    VALIDATION,
    ScenarioSet,
    SeedLike,
    monte_carlo_set,
    scenario_stream,
    training_set,
)
from chassistune.tuning.robust.sensitivity import SensitivityResult, sobol_sensitivity
from chassistune.tuning.robust.spec import ParamRange, UncertaintySpec
from chassistune.tuning.robust.validation import ValidationResult, validate_draws

Builder = Callable[[Mapping[str, float]], Scenario]


def build_grid(builders: Sequence[Builder], draws: ScenarioSet) -> list[list[Scenario]]:
    """grid[j][r]: scenario j of the set on road r. A draw the plant refuses (v0 below v_stop,
    say) is an InputError of the varied parameter (`vary.NAME`)."""
    try:
        return [[build(row) for build in builders] for row in draws.rows()]
    except InputError as exc:
        name = exc.field.split()[-1].split(".")[-1]
        if name not in draws.names:
            raise
        raise InputError(f"vary.{name}", f"a draw the plant refuses: {exc.problem}") from None


def cost_matrix(
    grid: Sequence[Sequence[Scenario]], gains: np.ndarray, objective: str
) -> np.ndarray:
    """Costs (n, K, R) of n gain rows on every scenario of the grid: one kernel call each."""
    g = np.asarray(gains, dtype=np.float64)
    out = np.empty((g.shape[0], len(grid), len(grid[0])))
    for j, row in enumerate(grid):
        for r, sc in enumerate(row):
            out[:, j, r] = sc.cost(g, objective)
    return out


@dataclass
class RobustProblem(TuningProblem):
    """The nominal problem's box and objective, scored over the run's K training scenarios."""

    spec: UncertaintySpec
    builders: list[Builder]
    training: ScenarioSet
    grid: list[list[Scenario]]
    seed: SeedLike

    def costs(self, gains: np.ndarray) -> np.ndarray:
        """Per-scenario costs (n, K, R)."""
        return cost_matrix(self.grid, gains, self.objective)

    def __call__(self, gains: np.ndarray) -> np.ndarray:
        """Aggregate over the K R scenarios of each row, shape (n,), at most PENALTY."""
        return np.minimum(self.spec.aggregate(self.costs(gains)), PENALTY)

    def validate(self, gains: np.ndarray, draws: ScenarioSet | None = None) -> ValidationResult:
        """Validate one gain vector on `draws` (default: the run's own validation set)."""
        if draws is None:
            draws = validation_set(self.spec, self.seed)
        return validate_gains(self.builders, self.objective, gains, draws, self.spec)


def validation_set(spec: UncertaintySpec, seed: SeedLike) -> ScenarioSet:
    """The N = spec.validate fresh Monte Carlo draws of the run `seed` (its validation stream:
    independent of the training set; the same for every controller validated with that seed)."""
    return monte_carlo_set(spec.params, spec.validate, scenario_stream(seed, VALIDATION))


def validate_gains(
    builders: Sequence[Builder],
    objective: str,
    gains: np.ndarray,
    draws: ScenarioSet,
    spec: UncertaintySpec,
) -> ValidationResult:
    """Pass/fail of one gain vector on every draw: a draw passes when it passes on every road
    (`builders`, one per road); its distance ratio and cost are the worst over the roads."""
    row = np.asarray(gains, dtype=np.float64).reshape(1, -1)
    results = []
    for build in builders:
        metrics: dict[str, list[np.ndarray]] = {}
        costs = []
        for draw in draws.rows():
            sc = build(draw)
            for name, value in sc.metrics(row).items():
                metrics.setdefault(name, []).append(value)
            if spec.criterion.max_cost > 0.0:  # a second simulation: only when the test asks
                costs.append(sc.cost(row, objective))
        cost = np.concatenate(costs) if costs else np.zeros(len(draws))
        results.append(
            validate_draws(
                {k: np.concatenate(v) for k, v in metrics.items()}, cost, spec.criterion, spec.beta
            )
        )
    passed = np.logical_and.reduce([res.passed for res in results])
    ratios = [res.distance_ratio for res in results if res.distance_ratio is not None]
    costs = [res.cost for res in results if res.cost is not None]
    return ValidationResult(
        passed,
        spec.beta,
        np.max(ratios, axis=0) if ratios else None,
        np.max(costs, axis=0) if costs else None,
    )


def controller_sensitivity(
    build: Builder,
    spec: UncertaintySpec,
    gains: np.ndarray,
    n: int = 256,
    seed: SeedLike = 0,
    metric: str = "distance_ratio",
) -> SensitivityResult:
    """First-order and total Sobol indices of one controller's `metric` (default the stop
    distance over the adhesion bound) with respect to each uncertain parameter; n (d + 2)
    simulations, one scenario built per point, drawn from the run's sensitivity stream."""
    row = np.asarray(gains, dtype=np.float64).reshape(1, -1)

    def metric_at(values: np.ndarray) -> np.ndarray:
        draws = ScenarioSet(spec.names, values)
        return np.array([float(build(draw).metrics(row)[metric][0]) for draw in draws.rows()])

    return sobol_sensitivity(metric_at, spec.params, n, scenario_stream(seed, SENSITIVITY))


def known_for(nominal: TuningProblem) -> dict[str, ParamRange]:
    """Parameters that may vary in every scenario of the nominal problem (all its roads), with
    their valid ranges: what `--vary` and `[uncertainty]` are validated against."""
    per_road = [known_ranges(sc) for sc in nominal.scenarios]
    return {name: rng for name, rng in per_road[0].items() if all(name in k for k in per_road)}


def robust_problem(
    nominal: TuningProblem,
    spec: UncertaintySpec,
    params: Mapping[str, object] | None = None,
    seed: SeedLike = 0,
) -> RobustProblem:
    """The nominal problem (built with the same `params`) scored over the run's training set,
    drawn from `seed`'s training stream (an int, or a study run's SeedSequence: every optimizer
    at that seed index then sees the same K scenarios); every scenario is built here, before any
    evaluation (a draw the plant refuses is an InputError of `vary.NAME`). With K = 0 the grid
    is the nominal scenarios alone: nominal tuning, validated on the same distribution."""
    base = dict(params or {})
    draws = training_set(spec.params, spec.scenarios, spec.sampler, scenario_stream(seed, TRAINING))
    builders = [scenario_builder(sc, base) for sc in nominal.scenarios]
    grid = build_grid(builders, draws) if len(draws) else [list(nominal.scenarios)]
    return RobustProblem(
        nominal.scenarios,
        nominal.objective,
        str(spec.aggregate),
        nominal.bounds,
        spec,
        builders,
        draws,
        grid,
        seed,
        params=nominal.params,
    )
