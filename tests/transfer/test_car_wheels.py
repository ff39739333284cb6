"""The single-wheel presets of the real cars (docs/cars.md, "One wheel of the car"): a front
wheel's static load, the car's wheel, the paper preset's brake; the step converged."""

from __future__ import annotations

import warnings

import pytest

from chassistune.plants.abs_wheel import BRAKE_FIELDS, CAR_WHEEL_BASE, PRESETS
from chassistune.plants.cars import CARS, read_car, shared_tir_path
from chassistune.scenarios.registry import get_plant


@pytest.mark.parametrize("car", CARS)
def test_a_car_wheel_carries_a_front_wheels_static_load(car: str) -> None:
    v = read_car(car).vehicle
    p = PRESETS[car].params
    m, a, b = float(v["m"]), float(v["a"]), float(v["b"])
    rear_wheel_kg = m * a / (2.0 * (a + b))  # the rear axle's share, per wheel
    assert 2.0 * (p.mass_kg + rear_wheel_kg) == pytest.approx(m, rel=1e-12)
    assert p.mass_kg > rear_wheel_kg  # all three are front-heavy at rest
    assert (p.wheel_radius_m, p.wheel_inertia_kg_m2) == (float(v["R_w"]), float(v["I_y_w"]))
    base = PRESETS[CAR_WHEEL_BASE].params
    for name in (*BRAKE_FIELDS, "v0_m_s", "g_m_s2", "v_stop_m_s", "load_fraction"):
        assert getattr(p, name) == getattr(base, name), name


@pytest.mark.slow
@pytest.mark.parametrize("car", CARS)
def test_a_car_wheels_step_is_converged(car: str) -> None:
    """The stop distance at the preset's step within 1e-3 of dt/4 (design.md 8), the continuous
    laws at their defaults, with the road tire and CommonRoad's Magic Formula, with the lag."""
    tir = shared_tir_path()
    dt = PRESETS[car].params.dt_s
    tires = ({}, {"tire": tir}, {"tire": tir, "relaxation_length_m": 0.3})
    for extra in tires:
        for road in ("dry-concrete", "ice", "dirt-0.2"):
            for law in ("pid", "fuzzy-pid"):
                d = []
                for step in (dt, dt / 4):
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        sc = get_plant("abs-wheel").scenario(
                            car, road, law, {**extra, "dt_s": step}
                        )
                    m = sc.metrics(sc.gains_array(None).reshape(1, -1))
                    d.append(float(m["stop_distance_m"][0]))
                assert abs(d[0] - d[1]) <= 1e-3 * d[1], (extra, road, law, d)
