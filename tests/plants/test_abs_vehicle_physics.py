"""Physics of the 7-DOF vehicle ABS (design.md 3.3): bounds, straightness, locked wheels, load
transfer, the single-wheel limit, the reference figures, mu-jump switching, split-mu yaw."""

from __future__ import annotations

import math

import numpy as np
import pytest

import chassistune
from chassistune.plants.abs_vehicle import axle_limited_deceleration, mu_jump_bound
from chassistune.plants.abs_vehicle_params import VehicleParams
from chassistune.scenarios.abs_vehicle import PLANT

CONTROLLERS = ["none", "pid", "fuzzy-pid", "threshold"]
FINE = {"v_stop_m_s": 0.5, "dt_s": 2.5e-4}  # the reference figures quoted at v_stop 0.5 m/s


def run(road: str, controller: str, gains=None, **params):
    sc = PLANT.scenario(None, road, controller, params)
    return sc, sc.trace(sc.gains_array(gains))


def steady(tr, name: str) -> float:
    """Mean of a signal over the steady phase t in [1, 3] s."""
    t = tr.signals["time_s"]
    sel = (t >= 1.0) & (t <= 3.0)
    return float(np.mean(tr.signals[name][sel]))


@pytest.mark.parametrize("road", ["dry-concrete", "ice", "mu-jump", "split-mu"])
@pytest.mark.parametrize("controller", CONTROLLERS)
def test_no_controller_beats_the_bound(road, controller):
    _sc, tr = run(road, controller)
    m = tr.metrics
    assert m["stopped"], m["status"]
    assert m["stop_distance_m"] >= m["bound_distance_m"] * (1 - 1e-9)
    assert m["stop_time_s"] >= m["bound_time_s"] * (1 - 1e-9)


def test_bounds_have_their_closed_forms():
    pp = VehicleParams()
    g, v0, vs = pp.g_m_s2, pp.v0_m_s, pp.v_stop_m_s
    dry = PLANT.scenario(None, "dry-concrete", "pid")
    assert dry.bound_distance_m == pytest.approx((v0**2 - vs**2) / (2 * 0.9 * g), rel=1e-14)
    assert dry.bound_distance_m == pytest.approx(62.761, abs=5e-4)
    split = PLANT.scenario(None, "split-mu", "pid")
    assert split.bound_distance_m == pytest.approx(
        (v0**2 - vs**2) / ((0.9 + 0.1028) * g), rel=1e-14
    )
    jump = PLANT.scenario(None, "mu-jump", "pid", {"v_stop_m_s": 0.5, "dt_s": 2.5e-4})
    assert jump.bound_distance_m == pytest.approx(85.74, abs=5e-3)


def test_mu_jump_bound_integrates_the_axle_wise_limit():
    """The bound against an independent integration of v dv/dx = -a_max(x) in small steps."""
    pp = VehicleParams(v_stop_m_s=0.5)
    mu1, mu2, xj = 0.1028, 0.9, 25.0
    a_mix = axle_limited_deceleration(pp, mu2, mu1)
    # the axle-wise limit is the fixed point of "each axle at its peak under its own load"
    fz_f = pp.mass_kg * (pp.g_m_s2 * pp.cg_to_rear_m + a_mix * pp.cg_height_m) / pp.wheelbase_m
    fz_r = pp.mass_kg * pp.g_m_s2 - fz_f
    assert pp.mass_kg * a_mix == pytest.approx(mu2 * fz_f + mu1 * fz_r, rel=1e-12)
    x = np.linspace(0.0, 200.0, 2_000_001)
    a = np.where(x < xj, mu1, np.where(x < xj + pp.wheelbase_m, a_mix / pp.g_m_s2, mu2))
    half_v2 = 0.5 * pp.v0_m_s**2 - np.concatenate(([0.0], np.cumsum(a[:-1] * np.diff(x)))) * (
        pp.g_m_s2
    )
    x_stop = float(np.interp(-0.5 * pp.v_stop_m_s**2, -half_v2, x))
    bound = mu_jump_bound(pp, mu1, mu2, xj)
    assert bound.distance_m == pytest.approx(x_stop, abs=2e-4)
    # high to low: the same integral with the surfaces swapped
    down = mu_jump_bound(pp, mu2, mu1, xj)
    assert down.distance_m > bound.distance_m


@pytest.mark.parametrize(
    "road,params",
    [
        ("dry-concrete", {}),
        ("ice", {}),
        ("mu-jump", {}),
        ("mu-jump", {"first_surface": "dry-concrete", "second_surface": "ice"}),
    ],
)
@pytest.mark.parametrize("controller", CONTROLLERS)
def test_straight_line_braking_stays_straight(road, params, controller):
    _sc, tr = run(road, controller, **params)
    s = tr.signals
    for name in ("yaw_rate_rad_s", "heading_rad", "y_m", "vy_m_s"):
        assert np.max(np.abs(s[name])) <= 1e-9, name


@pytest.mark.parametrize("road", ["dry-concrete", "ice"])
@pytest.mark.parametrize("height", [0.5, 0.0])
def test_locked_wheels_skid_as_coulomb_friction_says(road, height):
    sc, tr = run(road, "none", cg_height_m=height)
    m, pp = tr.metrics, sc.plant_params
    mu_lock = sc.road_spec.surfaces[0].mu_lock
    assert m["all_locked_time_s"] is not None
    remaining = m["stop_distance_m"] - m["all_locked_distance_m"]
    expected = (m["all_locked_speed_m_s"] ** 2 - pp.v_stop_m_s**2) / (2 * mu_lock * pp.g_m_s2)
    assert remaining == pytest.approx(expected, rel=1e-4)
    assert max(m["lock_time_rl_s"], m["lock_time_rr_s"]) < min(
        m["lock_time_fl_s"], m["lock_time_fr_s"]
    )


def test_rear_and_front_lock_times_without_abs():
    _sc, tr = run("dry-concrete", "none")
    m = tr.metrics
    assert m["lock_time_rl_s"] == pytest.approx(0.111, abs=1.5e-3)
    assert m["lock_time_fl_s"] == pytest.approx(0.164, abs=1.5e-3)


def test_load_transfer_in_steady_pid_braking():
    _sc, tr = run("dry-concrete", "pid")
    g = 9.8
    assert steady(tr, "ax_m_s2") == pytest.approx(-0.900 * g, rel=5e-3)
    for w in ("fl", "fr"):
        assert steady(tr, f"load_{w}_n") == pytest.approx(4204.8, rel=5e-3)
        assert steady(tr, f"brake_torque_{w}_n_m") == pytest.approx(1524.3, rel=1e-2)
    for w in ("rl", "rr"):
        assert steady(tr, f"load_{w}_n") == pytest.approx(1234.2, rel=5e-3)
        assert steady(tr, f"brake_torque_{w}_n_m") == pytest.approx(454.9, rel=1e-2)


def test_load_transfer_with_locked_wheels_and_without_cg_height():
    _sc, tr = run("dry-concrete", "none")
    assert steady(tr, "ax_m_s2") == pytest.approx(-0.75 * 9.8, rel=1e-3)
    assert steady(tr, "load_fl_n") == pytest.approx(4047.9, rel=1e-3)
    assert steady(tr, "load_rl_n") == pytest.approx(1391.1, rel=1e-3)
    _sc, flat = run("dry-concrete", "pid", cg_height_m=0.0)
    assert steady(flat, "load_fl_n") == pytest.approx(3263.4, rel=1e-3)
    assert steady(flat, "load_rr_n") == pytest.approx(2175.6, rel=1e-3)
    # the loads always carry the car's weight
    total = sum(tr.signals[f"load_{w}_n"] for w in ("fl", "fr", "rl", "rr"))
    np.testing.assert_allclose(total, 1110 * 9.8, rtol=1e-12)


@pytest.mark.parametrize(
    "road,controller,reference",
    [
        ("dry-concrete", "pid", (64.895049, 3.780500)),
        ("dry-concrete", "none", None),
        ("ice", "none", None),
    ],
)
def test_single_wheel_limit(road, controller, reference):
    """lf = lr and h = 0: each wheel is the abs-wheel plant with M = m/4, I = J."""
    pp = VehicleParams()
    common = {
        "v0_m_s": pp.v0_m_s,
        "g_m_s2": pp.g_m_s2,
        "q_max": pp.q_max,
        "v_stop_m_s": 0.5,
        "dt_s": 2.5e-4,
        "wheel_radius_m": pp.wheel_radius_m,
        "actuator_gain": pp.actuator_gain,
        "actuator_tau_s": pp.actuator_tau_s,
        "brake_gain": pp.brake_gain,
    }
    gains = {"kp": 1200.0, "ki": 0.0, "kd": 20.0} if controller == "pid" else None
    half = pp.wheelbase_m / 2
    car = chassistune.simulate(
        "abs-vehicle",
        road=road,
        controller=controller,
        gains=gains,
        params={**common, "cg_to_front_m": half, "cg_to_rear_m": half, "cg_height_m": 0.0},
    )
    wheel = chassistune.simulate(
        "abs-wheel",
        road=road,
        controller=controller,
        gains=gains,
        params={**common, "mass_kg": pp.mass_kg / 4, "wheel_inertia_kg_m2": pp.wheel_inertia_kg_m2},
    )
    for key in ("stop_distance_m", "stop_time_s"):
        assert car.metrics[key] == pytest.approx(wheel.metrics[key], rel=1e-6)
    if reference:
        assert car.metrics["stop_distance_m"] == pytest.approx(reference[0], rel=1e-6)
        assert car.metrics["stop_time_s"] == pytest.approx(reference[1], rel=1e-6)


@pytest.mark.parametrize(
    "road,controller,params,distance,ratio",
    [
        ("dry-concrete", "pid", {}, 65.072, 1.037),
        ("dry-concrete", "none", {}, 76.584, 1.220),
        ("ice", "pid", {}, 556.42, 1.013),
        ("mu-jump", "pid", FINE, 87.62, 1.022),
    ],
)
def test_default_gain_reference_figures(road, controller, params, distance, ratio):
    _sc, tr = run(road, controller, **params)
    m = tr.metrics
    assert m["stop_distance_m"] == pytest.approx(distance, rel=5e-3)
    assert m["distance_ratio"] == pytest.approx(ratio, rel=5e-3)


@pytest.mark.parametrize("surfaces", [("ice", "dry-concrete"), ("dry-concrete", "ice")])
def test_mu_jump_each_wheel_switches_at_its_own_contact_point(surfaces):
    first, second = surfaces
    sc, tr = run("mu-jump", "pid", first_surface=first, second_surface=second)
    s = tr.signals
    t, x = s["time_s"], s["x_m"]
    k = {w: int(np.argmax(s[f"surface_{w}"] == 1)) for w in ("fl", "fr", "rl", "rr")}
    assert k["fl"] == k["fr"] > 0 and k["rl"] == k["rr"] > k["fl"]
    lf, big_l = sc.plant_params.cg_to_front_m, sc.plant_params.wheelbase_m
    x_jump = lf + 25.0
    v = s["speed_m_s"]
    dt = sc.plant_params.dt_s
    # the front contact point reached the jump within the switching step
    assert x[k["fl"] - 1] + lf < x_jump <= x[k["fl"]] + lf
    assert x[k["rl"]] - x[k["fl"]] == pytest.approx(big_l, abs=v[k["fl"]] * dt)
    lag = t[k["rl"]] - t[k["fl"]]
    if first == "ice":  # the default road: L / v_cross = 0.0799 s (design.md 3.3), not L / v0
        assert lag == pytest.approx(0.080, abs=2e-3)
    assert big_l / v[k["fl"]] - dt <= lag <= big_l / v[k["rl"]] + dt
    # the target slip switches with the surface
    st_second = sc.road_spec.surfaces[1].slip_opt
    assert s["target_slip_fl"][k["fl"]] == st_second
    assert s["target_slip_rl"][k["fl"]] != st_second or first == second


def test_split_mu_yaw_in_the_first_second():
    peaks = {}
    for label, ctrl, params in [
        ("none", "none", {}),
        ("pid", "pid", {}),
        ("select-low", "pid", {"rear": "select-low"}),
    ]:
        _sc, tr = run("split-mu", ctrl, steering="fixed", **params)
        peaks[label] = tr.metrics["yaw_rate_peak_1s_rad_s"]
        assert peaks[label] > 0  # towards the dry (left) side
    assert peaks["pid"] <= 0.9 * peaks["none"]
    assert peaks["select-low"] <= 0.85 * peaks["pid"]
    # reference model (design.md 3.3): 1.014 / 0.715 / 0.547 rad/s
    assert peaks["none"] == pytest.approx(1.014, rel=1e-2)
    assert peaks["pid"] == pytest.approx(0.715, rel=1e-2)
    assert peaks["select-low"] == pytest.approx(0.547, rel=1e-2)


def test_split_mu_with_fixed_steering_spins_and_the_driver_holds_the_heading():
    _sc, fixed = run("split-mu", "pid", steering="fixed")
    assert fixed.metrics["spun"] and 2.0 < fixed.metrics["spin_time_s"] < 3.0
    _sc, driven = run("split-mu", "pid", steering="driver")
    m = driven.metrics
    assert not m["spun"]
    assert np.max(np.abs(driven.signals["heading_rad"])) < math.radians(4.2)
    assert m["stop_distance_m"] == pytest.approx(143.2, rel=1e-2)


def test_split_mu_steers_by_default_and_the_straight_roads_do_not():
    """`steering = auto`: the driver on split-mu (as a user expects of a car with ABS), fixed on
    every other road (nothing yaws the car there, and the straight path stays the fast one)."""
    sc, default = run("split-mu", "pid")
    _sc, driven = run("split-mu", "pid", steering="driver")
    assert sc.params()["steering"] == "driver"
    assert default.metrics == driven.metrics
    for road in ("dry-concrete", "ice", "mu-jump"):
        assert PLANT.scenario(None, road, "pid").params()["steering"] == "fixed"


@pytest.mark.parametrize("controller", ["pid", "fuzzy-pid", "threshold"])
def test_select_low_rear_pressures_are_bitwise_equal(controller):
    _sc, tr = run("split-mu", controller, rear="select-low")
    s = tr.signals
    assert np.array_equal(s["brake_torque_rl_n_m"], s["brake_torque_rr_n_m"])
    assert np.max(s["brake_torque_rl_n_m"]) > 0
    assert not np.array_equal(s["brake_torque_fl_n_m"], s["brake_torque_fr_n_m"])
