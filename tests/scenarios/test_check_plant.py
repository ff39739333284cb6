"""Every registered plant passes the conformance check; a deliberately broken toy plant fails it."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import Any

import numpy as np
import pytest

from chassistune.controllers.specs import ControllerSpec, GainSpec
from chassistune.plants.presets import PresetInfo
from chassistune.scenarios import registry
from chassistune.scenarios.base import PENALTY, Plant, PlantSpec, Scenario, Trace
from chassistune.scenarios.check import ConformanceError, check_plant

SHORT = {"abs-wheel": {"v0_m_s": 15.0}, "quarter-car": {"duration_s": 2.0}}
"""Shorter runs than the presets' (the checks do not depend on the run length)."""


@pytest.mark.parametrize("name", registry.plant_names())
def test_every_registered_plant_passes_the_conformance_check(name: str) -> None:
    check_plant(name, SHORT.get(name))


TOY = "broken-toy"
TOY_CONTROLLER = ControllerSpec(TOY, "gain", "one gain", gains=(GainSpec("k", "-", 1.0, 0.0, 2.0),))


class ToyScenario(Scenario):
    """Cost k^2, broken by `flaw`: "batch" adds the batch size (row i of a batch is not the
    single run of row i), "nan" gives NaN above the gain's bound."""

    plant = TOY
    preset = "only"
    road = "flat"
    controller = TOY_CONTROLLER
    objectives = ("square",)
    default_objective = "square"

    def params(self) -> dict[str, Any]:
        return {"offset": 0.0}

    def metrics(self, gains: np.ndarray) -> dict[str, np.ndarray]:
        return {"square": np.asarray(gains)[:, 0] ** 2}

    def __init__(self, flaw: str) -> None:
        self.flaw = flaw

    def cost(self, gains: np.ndarray, objective: str | None = None) -> np.ndarray:
        g = np.asarray(gains)[:, 0]
        if self.flaw == "nan":
            return np.where(g > 2.0, np.nan, g**2)
        return np.minimum(g**2 + len(g), PENALTY)

    def trace(self, gains: np.ndarray) -> Trace:
        return Trace({"time_s": np.zeros(3)}, {"square": float(gains[0] ** 2)}, {"time_s": "s"})


class ToyPlant(Plant):
    flaw = "batch"
    spec = PlantSpec(
        TOY,
        1,
        "a plant that breaks the batch contract",
        "only",
        ("square",),
        "chassistune.plots.abs_wheel:plot_trace",
    )

    def presets(self) -> dict[str, PresetInfo]:
        return {"only": PresetInfo("only", "the only preset", ("flat",))}

    def roads(self) -> dict[str, str]:
        return {"flat": "flat"}

    def controllers(self) -> list[ControllerSpec]:
        return [TOY_CONTROLLER]

    def scenario(
        self,
        preset: str | None = None,
        road: str | None = None,
        controller: str = "none",
        params: Mapping[str, object] | None = None,
        seed: int = 0,
    ) -> ToyScenario:
        return ToyScenario(self.flaw)


@pytest.fixture
def toy() -> Iterator[ToyPlant]:
    plant = ToyPlant()
    registry.register(plant.spec, plant)
    yield plant
    registry.unregister(TOY)


@pytest.mark.parametrize(
    ("flaw", "message"),
    [
        (
            "batch",
            "plant 'broken-toy' with controller 'gain': batch row 0 differs from its single "
            "run (square): ",
        ),
        (
            "nan",
            "plant 'broken-toy' with controller 'gain': cost not finite or above PENALTY for "
            "rows [7, 8] (square): [nan, nan] at gains [[2000.0], [2000000000.0]]",
        ),
    ],
)
def test_a_broken_toy_plant_fails_with_a_clear_message(
    toy: ToyPlant, flaw: str, message: str
) -> None:
    toy.flaw = flaw
    with pytest.raises(ConformanceError) as err:
        check_plant(TOY, plot=False)
    assert str(err.value).startswith(message)
    assert "\n" not in str(err.value)


def test_registering_a_plant_twice_is_refused(toy: ToyPlant) -> None:
    plant = ToyPlant()
    with pytest.raises(ValueError, match="registered already"):
        registry.register(plant.spec, plant)
