"""A test-only plant: the quarter car with three more objectives: `raises`, whose cost raises,
`dies`, whose cost ends its (worker) process at once, like a crash in compiled code, and
`terminated`, whose cost sends SIGTERM to its own process (a worker killed from outside).

Registered under the name `raising-quarter-car` by `register()`, which worker processes run as
their initializer (this module is importable there: spawned workers inherit sys.path).
"""

from __future__ import annotations

import dataclasses
import os
import signal
import time
from collections.abc import Mapping

import numpy as np

from chassistune.scenarios import registry
from chassistune.scenarios.quarter_car import QuarterCarPlant, QuarterCarScenario

NAME = "raising-quarter-car"
MESSAGE = "test objective raised on purpose"


class RaisingScenario(QuarterCarScenario):
    objectives = (*QuarterCarScenario.objectives, "raises", "dies", "terminated")

    def cost(
        self, gains: np.ndarray, objective: str | None = None, workers: int | None = None
    ) -> np.ndarray:
        if objective == "raises":
            raise RuntimeError(MESSAGE)
        if objective == "dies":
            deaths = os.environ.get("CHASSISTUNE_TEST_DEATHS")
            if deaths:  # one file per try, for tests counting how often the run was tried
                open(os.path.join(deaths, f"death-{os.getpid()}"), "w").close()
            os._exit(3)
        if objective == "terminated":
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(30)  # a process that survives SIGTERM would come back here
        return super().cost(gains, objective, workers)


class RaisingPlant(QuarterCarPlant):
    spec = dataclasses.replace(registry.QUARTER_CAR, name=NAME)

    def scenario(
        self,
        preset: str | None = None,
        road: str | None = None,
        controller: str = "none",
        params: Mapping[str, object] | None = None,
        seed: int = 0,
    ) -> RaisingScenario:
        sc = super().scenario(preset, road, controller, params, seed)
        return RaisingScenario(
            sc.preset,
            sc.road,
            sc.controller,
            sc.vehicle,
            sc.road_params,
            sc.solver,
            sc.controller_params,
            sc.seed,
        )


PLANT = RaisingPlant()


def register() -> None:
    """Make `raising-quarter-car` a known plant in this process."""
    if NAME not in registry.plant_names():
        registry.register(PLANT.spec, PLANT)
