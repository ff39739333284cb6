"""A tuning problem: the gains of one controller scored on one or several roads (design.md 5).

The box comes from the controller registry (or the caller's override); the cost of a population
is one kernel call per road, aggregated across roads by mean, max or cvar:ALPHA
(`tuning.robust.aggregate`; one controller for several roads is a first-class option).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from chassistune.errors import InputError
from chassistune.scenarios.base import PENALTY, Scenario
from chassistune.scenarios.registry import get_plant
from chassistune.tuning.robust.aggregate import parse_aggregate


@dataclass
class TuningProblem:
    """Scenarios that share a controller, an objective and an aggregate across roads."""

    scenarios: list[Scenario]
    objective: str
    aggregate: str
    bounds: list[tuple[float, float]]
    params: dict[str, Any] = field(default_factory=dict, kw_only=True)
    """The parameter overrides the scenarios were built from (to build them again, e.g. at a
    finer step: `scenarios.refine`)."""

    @property
    def gain_names(self) -> tuple[str, ...]:
        return self.scenarios[0].gain_names

    @property
    def roads(self) -> list[str]:
        return [s.road for s in self.scenarios]

    def __call__(self, gains: np.ndarray) -> np.ndarray:
        """Costs of an (n, k) population, shape (n,), finite and at most PENALTY."""
        costs = np.stack([s.cost(gains, self.objective) for s in self.scenarios], axis=1)
        return np.minimum(parse_aggregate(self.aggregate)(costs), PENALTY)


def build_problem(
    plant: str,
    controller: str,
    preset: str | None = None,
    roads: Sequence[str] | None = None,
    objective: str | None = None,
    aggregate: str = "mean",
    params: Mapping[str, object] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    seed: int = 0,
) -> TuningProblem:
    """Resolve the scenarios (one per road; default the preset's first road) and the box."""
    aggregate = str(parse_aggregate(aggregate))
    p = get_plant(plant)
    road_list: list[str | None] = list(roads) if roads else [None]
    if len(set(road_list)) != len(road_list):
        raise InputError("roads", "a road is listed twice")
    scenarios = [p.scenario(preset, r, controller, params or {}, seed) for r in road_list]
    spec = scenarios[0].controller
    if not spec.gains:
        raise InputError("controller", f"{controller} has no gains to tune")
    objective = scenarios[0].pick_objective(objective)
    box = dict(zip(spec.gain_names, spec.bounds(), strict=True))
    for name, (lo, hi) in (bounds or {}).items():
        if name not in box:
            raise InputError(
                "bounds",
                f"unknown gain {name!r} for {controller} (known: {', '.join(spec.gain_names)})",
            )
        if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
            raise InputError(f"bounds.{name}", f"need finite lo < hi, got [{lo}, {hi}]")
        box[name] = (float(lo), float(hi))
    return TuningProblem(
        scenarios,
        objective,
        aggregate,
        [box[n] for n in spec.gain_names],
        params=dict(params or {}),
    )
