"""Fuzzy controllers in the single-wheel ABS kernel (design.md 4)."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune.scenarios.abs_wheel import PLANT
from chassistune.scenarios.base import PENALTY

CLASSIC = {
    "ke": 15.0,
    "kec": 0.3,
    "ku_p": 500.0,
    "ku_i": 0.0,
    "ku_d": 20.0,
    "kp0": 5000.0,
    "ki0": 0.0,
    "kd0": 230.0,
}
"""Factors for the signed classic tables (outputs on [-3, 3]) around the hand-set PID."""

CASES = [
    # the registry's default factors (deffao and immune), and CLASSIC for the classic tables
    ("fuzzy-pid", "paper-derlsp-ao", "dry-concrete", {}, None),
    ("fuzzy-pid", "paper-derlsp-ao", "dry-concrete", {"rulebase": "classic"}, CLASSIC),
    ("fuzzy-immune-pid", "paper-fuzzy-immune", "asphalt-0.8", {}, None),
]


@pytest.mark.parametrize(("controller", "preset", "road", "params", "gains"), CASES)
def test_fuzzy_controllers_stop_within_10_percent_of_the_bound(
    controller, preset, road, params, gains
):
    sc = PLANT.scenario(preset, road, controller, params)
    m = sc.trace(sc.gains_array(gains)).metrics
    assert m["stopped"] and m["wheel_lock_time_s"] is None
    assert 1.0 <= m["distance_ratio"] <= 1.10
    assert m["slip_clip_max"] <= 1e-12 and m["min_slip_unclipped"] >= -1e-12


def test_the_immune_controller_does_not_change_when_the_step_halves():
    res = []
    for dt in (1e-3, 5e-4, 2.5e-4):
        sc = PLANT.scenario("paper-fuzzy-immune", "asphalt-0.8", "fuzzy-immune-pid", {"dt_s": dt})
        m = sc.metrics(sc.gains_array(None)[None, :])
        res.append((m["stop_distance_m"][0], m["slip_itae"][0]))
    for k in range(2):
        assert abs(res[0][k] - res[2][k]) / res[2][k] < 2e-3
        assert abs(res[1][k] - res[2][k]) <= abs(res[0][k] - res[2][k]) + 1e-9


def test_fuzzy_pid_batch_equals_single_runs_and_wild_gains_get_the_penalty():
    sc = PLANT.scenario("paper-derlsp-ao", "wet-asphalt", "fuzzy-pid")
    lo, hi = np.array(sc.controller.bounds()).T
    gains = np.random.default_rng(3).uniform(lo, hi, (12, len(lo)))
    gains[0] = -gains[0]
    batch = sc.raw(gains, workers=2)
    for i in (0, 5, 11):
        np.testing.assert_array_equal(batch[i], sc.raw(gains[i : i + 1], workers=1)[0])
    cost = sc.cost(gains)
    assert np.all(np.isfinite(cost)) and np.all(cost <= PENALTY)


def test_a_rulebase_with_the_wrong_outputs_is_bad_input():
    from chassistune.errors import InputError

    with pytest.raises(InputError, match="rulebase"):
        PLANT.scenario("paper-derlsp-ao", "dry-concrete", "fuzzy-pid", {"rulebase": "immune"})
    with pytest.raises(InputError, match="rulebase"):
        PLANT.scenario(
            "paper-derlsp-ao", "dry-concrete", "fuzzy-pid", {"rulebase": "/no/such/file.toml"}
        )
