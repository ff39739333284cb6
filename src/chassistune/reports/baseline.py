"""The baseline a study's tuned controllers must beat: the registry's default gains, scored on
each scenario's own problem (objective, aggregate, roads, parameters) and traced for the key
metrics, so a report can put them beside every optimizer's medians."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from chassistune.reports.tables import StudyData, quantities
from chassistune.tuning.functions import FUNCTION_KIND

LABEL = "default gains"
"""The baseline's name in the report's tables."""


@dataclass(frozen=True)
class Baseline:
    """The default gains of a scenario's controller and their value of each report quantity
    (`tables.quantities`: final cost, key metrics; NaN where a quantity has no value)."""

    gains: dict[str, float]
    values: dict[str, float]


def default_baseline(data: StudyData, scenario: str) -> Baseline | None:
    """The default gains' cost (median over the distinct problems of the completed runs: one
    per scenario seed where the road is random) and key metrics (on one run's problem);
    None for a benchmark function or a scenario without completed runs."""
    from chassistune.studies.problems import problem_for

    runs = data.runs(scenario)
    if not runs or runs[0].spec.plant == FUNCTION_KIND:
        return None
    specs = {r.spec.scenario_seed: r.spec for r in reversed(runs)}.values()
    built = [problem_for(s.model_dump(), s.scenario_seed, s.seed_sequence()) for s in specs]
    problem = built[0]
    defaults = problem.scenarios[0].gains_array(None)
    costs = [float(p(defaults[None, :])[0]) for p in built]
    metrics = {sc.road: sc.trace(defaults).metrics for sc in problem.scenarios}
    values = {"best_cost": float(np.median(costs)), "nfev": math.nan}
    for q in quantities(data, scenario)[2:]:
        name, _, road = q.partition("@")
        value = metrics.get(road or problem.roads[0], {}).get(name)
        values[q] = math.nan if value is None else float(value)
    return Baseline(dict(zip(problem.gain_names, defaults.tolist(), strict=True)), values)
