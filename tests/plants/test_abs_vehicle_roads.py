"""mu_scale on the vehicle's roads: it scales every surface's curve, the bounds follow, 1 changes
nothing, and robust tuning knows it."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune.scenarios.abs_vehicle import PLANT


@pytest.mark.parametrize("road", ["dry-concrete", "ice", "mu-jump", "split-mu"])
def test_mu_scale_scales_both_surfaces_and_the_bound(road):
    nominal = PLANT.scenario(None, road, "pid")
    same = PLANT.scenario(None, road, "pid", {"mu_scale": "1"})
    slick = PLANT.scenario(None, road, "pid", {"mu_scale": "0.8"})
    assert same.road_spec == nominal.road_spec
    assert same.params()["mu_scale"] == 1.0 and slick.params()["mu_scale"] == 0.8
    for a, b in zip(nominal.road_spec.surfaces, slick.road_spec.surfaces, strict=True):
        assert b.mu_peak == pytest.approx(0.8 * a.mu_peak, rel=1e-15)
        assert b.mu_lock == pytest.approx(0.8 * a.mu_lock, rel=1e-15)
        assert b.slip_opt == a.slip_opt
    assert slick.target_slips == nominal.target_slips
    if road != "mu-jump":  # the jump's first stretch is fixed in metres
        assert slick.bound_distance_m > nominal.bound_distance_m * 1.2


def test_mu_scale_one_gives_the_nominal_run_bit_for_bit_and_less_grip_a_longer_stop():
    g = PLANT.scenario(None, "dry-concrete", "pid").gains_array(None)[None, :]
    nominal = PLANT.scenario(None, "dry-concrete", "pid").raw(g)
    np.testing.assert_array_equal(
        PLANT.scenario(None, "dry-concrete", "pid", {"mu_scale": "1.0"}).raw(g), nominal
    )
    slick = PLANT.scenario(None, "dry-concrete", "pid", {"mu_scale": "0.7"})
    m = slick.metrics(g)
    base = PLANT.scenario(None, "dry-concrete", "pid").metrics(g)["stop_distance_m"][0]
    assert m["stopped"][0] and m["stop_distance_m"][0] > 1.3 * base
    assert m["distance_ratio"][0] >= 1.0


def test_robust_tuning_declares_mu_scale_for_the_vehicle():
    from chassistune.tuning.robust.plant_params import known_ranges

    ranges = known_ranges(PLANT.scenario(None, "split-mu", "pid"))
    assert "mu_scale" in ranges and "mass_kg" in ranges and "dt_s" not in ranges
