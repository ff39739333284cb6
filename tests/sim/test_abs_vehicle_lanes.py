"""The vehicle kernel's pinned results (tests/golden/abs_vehicle.json) are reproduced bit for bit:
every controller on every road, the options (select-low, driver, per-axle gains, split by road,
high-to-low jump, h = 0) and populations with unstable and NaN gains (`abs_vehicle_pins`)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

import abs_vehicle_pins as pins

PINNED = json.loads(pins.PINNED.read_text())


@pytest.fixture(scope="module")
def computed() -> dict:
    return pins.compute()


def test_every_case_is_pinned(computed):
    assert sorted(computed) == sorted(PINNED)
    n_arrays = sum(len(case["raw"]) + len(case) - 1 for case in PINNED.values())
    assert len(PINNED) == 28 and n_arrays > 900


@pytest.mark.parametrize("key", sorted(PINNED))
def test_case_is_bitwise_unchanged(computed, key):
    assert computed[key] == PINNED[key]


def test_wild_candidates_end_with_a_status_not_an_exception():
    from chassistune.scenarios.abs_vehicle import PLANT
    from chassistune.scenarios.base import PENALTY

    sc = PLANT.scenario(None, "dry-concrete", "fuzzy-pid")
    pop = pins.population(sc.controller.bounds())
    cost = sc.cost(pop)
    assert np.all(np.isfinite(cost)) and cost[-1] == PENALTY
