"""Step-refinement check of a tuned winner: re-simulate it at a fraction of the integration step
and report how much its cost and metrics move.

A fixed-step kernel can flatter a chattering candidate (the slip ITAE reads low at a coarse step
when the loop switches inside steps); the optimizer finds exactly such candidates. Re-running
the winner at dt / factor costs a few single runs and shows whether its figures are converged:
a relative change above `threshold` (default 1e-3) comes with a warning.

    check = step_refinement(scenario, gains, base, objective)  # gains: (k,) in gain_names order;
                                                               # base: the --param overrides
    check.as_dict()  # {"factor", "dt_s", "cost", "cost_refined", "cost_rel_change",
                     #  "metrics_rel_change": {name: float}, "max_rel_change", "warning"}
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, TypeVar, cast

import numpy as np

from chassistune.scenarios.base import Scenario

S = TypeVar("S", bound=Scenario)

THRESHOLD = 1e-3


@dataclass(frozen=True)
class StepCheck:
    """Cost and metrics of one candidate at dt and at dt / factor, and their relative change."""

    factor: int
    dt_s: float
    cost: float
    cost_refined: float
    cost_rel_change: float
    metrics_rel_change: dict[str, float] = field(default_factory=dict)
    status_changed: bool = False
    threshold: float = THRESHOLD

    @property
    def max_rel_change(self) -> float:
        return max([self.cost_rel_change, *self.metrics_rel_change.values()])

    @property
    def warning(self) -> str | None:
        """A one-line warning when the figures move by more than the threshold, else None."""
        if self.status_changed:
            return f"the run ends differently at dt/{self.factor}: not converged in the step"
        if not self.max_rel_change > self.threshold:
            return None
        worst = max(
            self.metrics_rel_change, key=lambda k: self.metrics_rel_change[k], default="cost"
        )
        if self.cost_rel_change >= self.metrics_rel_change.get(worst, 0.0):
            worst = "cost"
        return (
            f"{worst} changes by {self.max_rel_change:.2e} (relative) at dt/{self.factor}: "
            f"above {self.threshold:g}, the step is too coarse for this candidate"
        )

    def as_dict(self) -> dict[str, Any]:
        return {
            "factor": self.factor,
            "dt_s": self.dt_s,
            "cost": self.cost,
            "cost_refined": self.cost_refined,
            "cost_rel_change": self.cost_rel_change,
            "metrics_rel_change": dict(self.metrics_rel_change),
            "max_rel_change": self.max_rel_change,
            "warning": self.warning,
        }


def _rel_change(coarse: float, fine: float) -> float:
    if coarse == fine:  # includes both zero; NaN == NaN is False and falls through
        return 0.0
    if np.isnan(coarse) and np.isnan(fine):
        return 0.0
    return float(abs(coarse - fine) / abs(fine)) if fine != 0.0 else float("inf")


def refined_scenario(scenario: S, factor: int, base: Mapping[str, object]) -> S:
    """The scenario built again from the parameter overrides `base` it was built from, at
    dt_s / factor (sample periods such as ts_s do not follow dt_s: the controller is unchanged),
    by the same plant, hence of the same type."""
    from chassistune.scenarios.registry import get_plant

    dt_s = float(scenario.params()["dt_s"]) / factor
    return cast(
        S,
        get_plant(scenario.plant).scenario(
            scenario.preset,
            scenario.road,
            scenario.controller.name,
            {**base, "dt_s": dt_s},
            scenario.seed,
        ),
    )


def step_refinement(
    scenario: Scenario,
    gains: np.ndarray,
    base: Mapping[str, object],
    objective: str | None = None,
    factor: int = 4,
    threshold: float = THRESHOLD,
) -> StepCheck:
    """Re-simulate `gains` (k,) at dt / factor (the scenario rebuilt from its overrides `base`);
    relative change of the cost and of every numeric metric (see the module docstring)."""
    g = np.asarray(gains, dtype=np.float64).reshape(1, -1)
    fine = refined_scenario(scenario, factor, base)
    m0, m1 = scenario.metrics(g), fine.metrics(g)
    changes = {}
    for name, values in m0.items():
        if values.dtype.kind == "f":
            changes[name] = _rel_change(float(values[0]), float(m1[name][0]))
    status_changed = bool("status" in m0 and m0["status"][0] != m1["status"][0])
    c0 = float(scenario.cost(g, objective)[0])
    c1 = float(fine.cost(g, objective)[0])
    return StepCheck(
        factor,
        float(scenario.params()["dt_s"]),
        c0,
        c1,
        _rel_change(c0, c1),
        changes,
        status_changed,
        threshold,
    )
