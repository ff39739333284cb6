"""Compile every kernel once (numba caches the machine code on disk, keyed on the sources), so
that the first real run does not pay 10-40 s per kernel: `chassistune warmup`, run by `make`
at installation.

Every registered plant with each of its controllers: each objective on a population as large as
a tuning's (random gains in the controller's bounds: the chunked, threaded batch path), on one
row, and a trace (the Lyapunov kernel too for the quarter car).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from chassistune._rng import make_rng
from chassistune.scenarios.registry import get_plant, plant_names

POPULATION = 32
"""Rows of the warm-up population (several chunks per worker thread, as in a tuning)."""


def warm_up(progress: Callable[[str], None] | None = None) -> list[str]:
    """Compile the kernels of every plant and controller; the `plant/controller` pairs done."""
    done = []
    rng = make_rng(0)
    for name in plant_names():
        plant = get_plant(name)
        for spec in plant.controllers():
            sc = plant.scenario(None, None, spec.name, {}, 0)
            gains = sc.gains_array(None)
            box = np.array(spec.bounds(), dtype=float).reshape(-1, 2)
            population = box[:, 0] + rng.random((POPULATION, box.shape[0])) * (
                box[:, 1] - box[:, 0]
            )
            for objective in sc.objectives:
                sc.cost(population, objective)
                sc.cost(gains.reshape(1, -1), objective)
            sc.trace(gains)
            done.append(f"{name}/{spec.name}")
            if progress is not None:
                progress(done[-1])
    return done
