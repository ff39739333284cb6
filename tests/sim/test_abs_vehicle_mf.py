"""The Magic Formula tire on the 7-DOF vehicle (`--tire`): batch rows against single runs, the
symmetry of straight braking, the load solve's balance, the adhesion bound, the step check, the
closed loop against scipy, and convergence as the step halves."""

from __future__ import annotations

import math
import re
import warnings
from importlib.resources import files

import numpy as np
import pytest

from chassistune.errors import InputError
from chassistune.plants.mf_peak import braking_peak
from chassistune.plants.tir import read_tir
from chassistune.plants.vehicle_mf import braking_capacity_n, wheel_forces
from chassistune.scenarios.abs_vehicle import PLANT
from chassistune.sim import abs_vehicle_layout as VL

CHRONO = str(files("chassistune") / "data" / "tires" / "chrono_185_80R14_pac2002.tir")
MF = {"tire": CHRONO, "dt_s": 2e-4, "v0_m_s": 15.0}
"""The shipped PAC2002 file at the step its stiffness needs, from 15 m/s (shorter runs)."""


def scenario(road: str, controller: str = "pid", **params: object):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return PLANT.scenario(None, road, controller, {**MF, **params})


def population(sc, n: int) -> np.ndarray:
    b = np.array(sc.controller.bounds())
    return np.random.default_rng(2026).uniform(b[:, 0], b[:, 1], (n, len(b)))


def chrono():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read_tir(CHRONO, lateral=True)


@pytest.mark.parametrize("road", ["dry-concrete", "split-mu"])
def test_batch_row_equals_single_run_on_one_and_two_threads(road):
    sc = scenario(road)
    gains = population(sc, 6)
    batch = sc.raw(gains, workers=1)
    np.testing.assert_array_equal(batch, sc.raw(gains, workers=2))
    for i in (0, 3, 5):
        np.testing.assert_array_equal(sc.raw(gains[i : i + 1], workers=1)[0], batch[i])
    assert sc.trace(gains[3]).metrics["stop_distance_m"] == batch[3, VL.M_DIST]
    assert np.all(batch[:, VL.M_ITER] >= 1)  # every step took the Newton load solve


def test_the_files_tyre_pulls_sideways_and_its_mirror_image_cancels_it():
    """The file's conicity/ply-steer gives a lateral force at zero slip angle; the right wheels
    carry the mirror image, so straight braking on a uniform road stays exactly straight."""
    c = chrono().kernel_array()
    fy_left = wheel_forces(0.05, 0.0, 3000.0, c, False)[1]
    fy_right = wheel_forces(0.05, 0.0, 3000.0, c, True)[1]
    assert abs(fy_left) > 10.0 and fy_right == -fy_left
    s = scenario("dry-concrete").trace(scenario("dry-concrete").gains_array(None)).signals
    for name in ("vy_m_s", "yaw_rate_rad_s", "y_m", "heading_rad"):
        assert np.all(s[name] == 0.0), name
    assert s["speed_m_s"][-1] <= 2.0 + 1e-12


def test_the_load_solve_balances_forces_and_weight():
    """Every trace row: the loads sum to m g (the transfer terms cancel) and, the steering fixed
    (wheel frame = body frame in x), m a_x is the sum of the wheels' F_x."""
    sc = scenario("split-mu", steering="fixed", t_max_s=1.0)
    s = sc.trace(sc.gains_array(None)).signals
    pp = sc.plant_params
    loads = sum(s[f"load_{w}_n"] for w in ("fl", "fr", "rl", "rr"))
    np.testing.assert_allclose(loads, pp.mass_kg * pp.g_m_s2, rtol=1e-12)
    fx = sum(s[f"fx_{w}_n"] for w in ("fl", "fr", "rl", "rr"))
    np.testing.assert_allclose(s["ax_m_s2"] * pp.mass_kg, fx, rtol=1e-9, atol=1e-6)
    assert np.max(np.abs(s["yaw_rate_rad_s"])) > 0.05  # yaw: the lateral forces are in play


@pytest.mark.parametrize("road", ["dry-concrete", "split-mu", "mu-jump"])
@pytest.mark.parametrize("controller", ["pid", "fuzzy-pid"])
def test_no_stop_beats_the_bound(road, controller):
    sc = scenario(road, controller)
    gains = np.vstack([sc.gains_array(None), population(sc, 7)])
    m = sc.metrics(gains)
    assert m["stopped"].any()
    stopped = m["stop_distance_m"][m["stopped"]]
    assert np.all(stopped >= sc.bound_distance_m), (stopped.min(), sc.bound_distance_m)


def test_braking_capacity_is_the_best_load_split():
    """Two tires: the capacity equals a brute-force maximisation over the split of the load;
    four: the equal split (the peak force is concave in the load with the file's PDX2 < 0)."""
    tire = chrono()
    assert tire.pdx2 < 0.0
    total = 9000.0

    def peak(z: float) -> float:
        return -braking_peak(tire, z)[1] if z > 0.0 else 0.0

    brute = max(peak(z) + peak(total - z) for z in np.linspace(0.0, total, 2001))
    assert braking_capacity_n((tire, tire), total) == pytest.approx(brute, rel=1e-9)
    four = braking_capacity_n((tire,) * 4, total)
    assert four == pytest.approx(4.0 * peak(total / 4.0), rel=1e-12)


def test_the_step_check_takes_the_curves_slope():
    with pytest.raises(InputError) as err:
        scenario("dry-concrete", dt_s=1e-3)
    assert err.value.field == "params.dt_s"
    passing = float(re.search(r"dt_s = ([0-9.e-]+) \(the step divided", str(err.value)).group(1))
    assert scenario("dry-concrete", dt_s=passing).plant_params.dt_s == passing


@pytest.mark.slow
def test_the_closed_loop_agrees_with_an_independent_scipy_integration():
    """Split-mu, steering fixed: the kernel's RK4 against scipy's RK45 at rtol 1e-8 on the plain
    Python right-hand side of perf/vehicle.py with the Magic Formula's slips written from the
    wheel velocities (kappa = -(u - w R)/|u|, tan alpha = v/|u|) and the right tyres mirrored."""
    from chassistune.perf.vehicle import reference_solution

    sc = scenario("split-mu", steering="fixed", t_max_s=0.6)
    g = sc.gains_array(None)
    sol = reference_solution(sc, g, rtol=1e-8, atol=1e-9)
    s = sc.trace(g).signals
    for row, name in ((0, "vx_m_s"), (1, "vy_m_s"), (2, "yaw_rate_rad_s"), (5, "heading_rad")):
        assert s[name][-1] == pytest.approx(sol.y[row, -1], rel=1e-5), name
    assert abs(s["yaw_rate_rad_s"][-1]) > 0.05


@pytest.mark.slow
def test_the_stop_converges_as_the_step_halves():
    """Stop distances at dt, dt/2, dt/4: the gaps shrink (RK4 and the sampled stop)."""
    d = []
    for dt in (2e-4, 1e-4, 5e-5):
        sc = scenario("dry-concrete", dt_s=dt)
        d.append(sc.metrics(sc.gains_array(None)[None, :])["stop_distance_m"][0])
    assert abs(d[1] - d[2]) < abs(d[0] - d[1]) or abs(d[1] - d[2]) < 1e-6
    assert abs(d[0] - d[2]) / d[2] < 1e-3
    assert math.isfinite(d[2])
