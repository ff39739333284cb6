"""The 7-DOF vehicle's brake balance (design.md 3.3): the front axle's share s of the brake torque
at equal pressure, carried by the measured cars from CommonRoad."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune.plants.abs_vehicle_params import PRESETS, VehicleParams
from chassistune.plants.cars import CARS
from chassistune.scenarios.abs_vehicle import PLANT
from chassistune.sim.abs_vehicle_wheels import wheel_brake_gain


def trace(road: str, controller: str, preset: str | None = None, **params: object):
    sc = PLANT.scenario(preset, road, controller, params)
    return sc.trace(sc.gains_array(None))


@pytest.mark.parametrize("kq", [1.0, 0.1, 25.0, 1.3558179483314004, 7.0 / 3.0, 999.9])
def test_an_even_split_gives_every_wheel_the_brake_gain_exactly(kq: float) -> None:
    assert VehicleParams().front_brake_share == 0.5
    assert [wheel_brake_gain(kq, 0.5, j) for j in range(4)] == [kq] * 4


@pytest.mark.parametrize("share", [0.5, 0.64, 0.76, 0.9])
def test_the_gains_split_the_torque_as_the_share_says(share: float) -> None:
    kq = 1.7
    front, rear = wheel_brake_gain(kq, share, 0), wheel_brake_gain(kq, share, 2)
    assert wheel_brake_gain(kq, share, 1) == front and wheel_brake_gain(kq, share, 3) == rear
    assert front / rear == pytest.approx(share / (1 - share), rel=1e-14)
    assert (front + rear) / 2 == pytest.approx(kq, rel=1e-15)


@pytest.mark.parametrize("share", [0.5, 0.7])
def test_front_over_rear_brake_torque_at_equal_pressure_is_s_over_1_minus_s(share) -> None:
    """Without ABS every wheel gets the same pedal pressure: the traced torques' ratio is the
    split's, at every row where the brakes are applied."""
    s = trace("dry-concrete", "none", front_brake_share=share).signals
    on = s["brake_torque_rl_n_m"] > 0.0
    assert on.sum() > 100
    assert np.array_equal(s["brake_torque_fl_n_m"], s["brake_torque_fr_n_m"])
    assert np.array_equal(s["brake_torque_rl_n_m"], s["brake_torque_rr_n_m"])
    ratio = s["brake_torque_fl_n_m"][on] / s["brake_torque_rl_n_m"][on]
    np.testing.assert_allclose(ratio, share / (1 - share), rtol=1e-12)


def test_more_rear_braking_locks_the_rear_wheels_sooner() -> None:
    even = trace("dry-concrete", "none").metrics
    front_heavy = trace("dry-concrete", "none", front_brake_share=0.76).metrics
    assert front_heavy["lock_time_rl_s"] > even["lock_time_rl_s"]
    assert front_heavy["lock_time_fl_s"] < even["lock_time_fl_s"]


@pytest.mark.parametrize("car,t_sb", [("ford-escort", 0.76), ("bmw-320i", 0.66),
                                      ("vw-vanagon", 0.64)])  # fmt: skip
def test_the_cars_carry_commonroads_brake_split(car: str, t_sb: float) -> None:
    assert PRESETS[car].params.front_brake_share == t_sb
    assert f"T_sb = {t_sb}" in PRESETS[car].info.description


@pytest.mark.parametrize("car", CARS)
@pytest.mark.parametrize("road", ["dry-concrete", "mu-jump", "split-mu"])
@pytest.mark.parametrize("controller", ["none", "pid", "fuzzy-pid", "threshold"])
def test_no_car_beats_its_adhesion_bound_with_its_brake_split(car, road, controller) -> None:
    m = trace(road, controller, car).metrics
    assert m["stopped"], m["status"]
    assert m["stop_distance_m"] >= m["bound_distance_m"] * (1 - 1e-9)
    assert m["stop_time_s"] >= m["bound_time_s"] * (1 - 1e-9)
