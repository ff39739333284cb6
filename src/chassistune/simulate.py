"""`chassistune.simulate(...)`: one closed-loop run of any plant, as a result object."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from chassistune.params import to_float

if TYPE_CHECKING:  # the plants are imported on first use: `import chassistune` stays light
    import numpy as np

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

    def plot(self, path: str) -> None:
        """Draw this run into `path` (PNG) with the plant's figure (`PlantSpec.plot`)."""
        from chassistune._registry import resolve
        from chassistune.scenarios.registry import plant_spec

        draw: Any = resolve(plant_spec(self.scenario.plant).plot)
        draw(self.scenario, self.trace, path)

    def as_dict(self) -> dict[str, Any]:
        """The `simulate --json` object (design.md 7)."""
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
    scenario, g = prepare(plant, preset, road, controller, params, gains, seed)
    return run(scenario, g)


def prepare(
    plant: str,
    preset: str | None,
    road: str | None,
    controller: str,
    params: Mapping[str, object] | None,
    gains: Mapping[str, object] | None,
    seed: int,
) -> tuple[Scenario, np.ndarray]:
    """The validated scenario and gain vector of `simulate`'s arguments (nothing simulated
    yet)."""
    from chassistune.scenarios.registry import get_plant

    scenario = get_plant(plant).scenario(preset, road, controller, params or {}, seed)
    numeric = {k: to_float(v, f"gains.{k}") for k, v in (gains or {}).items()}
    return scenario, scenario.gains_array(numeric)


def run(scenario: Scenario, gains: np.ndarray) -> SimulationResult:
    """Simulate a prepared scenario with one gain vector."""
    return SimulationResult(
        scenario, dict(zip(scenario.gain_names, gains.tolist(), strict=True)), scenario.trace(gains)
    )


COMPARISON_PLOT = "chassistune.plots.overlay:plot_results"
"""The figure of `compare` (resolved on use: computation modules never import matplotlib)."""


@dataclass
class Comparison:
    """Several runs of one plant, preset and road: one result per label (controller)."""

    results: dict[str, SimulationResult]

    def table(self) -> list[dict[str, Any]]:
        """One row per run: label, controller, gains, then its metrics."""
        return [
            {
                "label": label,
                "controller": r.scenario.controller.name,
                "gains": r.gains,
                **r.metrics,
            }
            for label, r in self.results.items()
        ]

    def plot(self, path: str) -> None:
        """All runs on one figure (shared time axis, one panel per signal) into `path`."""
        from chassistune._registry import resolve

        draw: Any = resolve(COMPARISON_PLOT)
        draw(self.results, path)


def compare(
    plant: str,
    controllers: Sequence[str],
    preset: str | None = None,
    road: str | None = None,
    params: Mapping[str, object] | None = None,
    gains: Mapping[str, Mapping[str, object]] | None = None,
    seed: int = 0,
) -> Comparison:
    """Simulate each controller on the same plant, preset, road and parameters; `gains[c]`
    overrides controller c's registry defaults. Parameters a controller does not take (e.g.
    a PID's `n_filter` for `none`) are passed only to the controllers that take them."""
    from chassistune.errors import InputError
    from chassistune.scenarios.registry import get_plant

    if len(set(controllers)) != len(controllers) or not controllers:
        raise InputError("controllers", "name each controller once, at least one")
    values = dict(params or {})
    p = get_plant(plant)
    own = {c.name: set(c.param_names) for c in p.controllers()}
    everyone = set().union(*own.values()) if own else set()
    results = {}
    for name in controllers:
        if name not in own:
            p.scenario(preset, road, name, {}, seed)  # raises the one-line unknown-name error
        mine = {k: v for k, v in values.items() if k not in everyone or k in own[name]}
        results[name] = simulate(plant, preset, road, name, mine, (gains or {}).get(name), seed)
    return Comparison(results)
