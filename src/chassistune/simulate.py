"""`chassistune.simulate(...)`: one closed-loop run of any plant, as a result object."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from chassistune.params import to_float

if TYPE_CHECKING:  # the plants are imported on first use: `import chassistune` stays light
    from chassistune.scenarios.base import Scenario, Trace


@dataclass
class SimulationResult:
    """The scenario, the gains used, the metrics and the time series of one run."""

    scenario: Scenario
    gains: dict[str, float]
    trace: Trace

    @property
    def metrics(self) -> dict[str, Any]:
        return self.trace.metrics

    def as_dict(self) -> dict[str, Any]:
        """The `simulate --json` object (DESIGN 7)."""
        sc = self.scenario
        return {
            "plant": sc.plant,
            "preset": sc.preset,
            "road": sc.road,
            "controller": sc.controller.name,
            "gains": self.gains,
            "params": sc.params(),
            "metrics": self.metrics,
        }


def simulate(
    plant: str,
    preset: str | None = None,
    road: str | None = None,
    controller: str = "pid",
    params: Mapping[str, object] | None = None,
    gains: Mapping[str, object] | None = None,
    seed: int = 0,
) -> SimulationResult:
    """Simulate `plant` on `road` under `controller` with `gains` (registry defaults otherwise).

    `params` overrides plant, road, solver and controller parameters by name (SI). Bad names or
    values raise `chassistune.errors.InputError` (a ValueError).
    """
    from chassistune.scenarios.registry import get_plant

    scenario = get_plant(plant).scenario(preset, road, controller, params or {}, seed)
    numeric = {k: to_float(v, f"gains.{k}") for k, v in (gains or {}).items()}
    g = scenario.gains_array(numeric)
    trace = scenario.trace(g)
    return SimulationResult(scenario, dict(zip(scenario.gain_names, g.tolist(), strict=True)),
                            trace)
