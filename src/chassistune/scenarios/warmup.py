"""Compile every kernel once (numba caches the machine code on disk, keyed on the sources), so
that the first real run does not pay 10-40 s per kernel: `chassistune warmup`, run by `make`
at installation.

Every registered plant with each of its controllers: a batch cost, the default objective and a
trace (the kernels of the batch, single and trace paths; the Lyapunov kernel for the quarter car).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from chassistune.scenarios.registry import get_plant, plant_names


def warm_up(progress: Callable[[str], None] | None = None) -> list[str]:
    """Compile the kernels of every plant and controller; the `plant/controller` pairs done."""
    done = []
    for name in plant_names():
        plant = get_plant(name)
        for spec in plant.controllers():
            sc = plant.scenario(None, None, spec.name, {}, 0)
            gains = sc.gains_array(None)
            for objective in sc.objectives:
                sc.cost(np.vstack([gains, gains]), objective)
            sc.trace(gains)
            done.append(f"{name}/{spec.name}")
            if progress is not None:
                progress(done[-1])
    return done
