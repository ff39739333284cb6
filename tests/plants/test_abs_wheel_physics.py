"""Physics invariants of the single-wheel ABS (design.md 3.1): bounds, lock, slip, convergence."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune.plants.roads import BILINEAR_ROADS, friction_roads
from chassistune.scenarios.abs_wheel import PLANT
from chassistune.scenarios.base import PENALTY

PRESET_ROADS = [(p, r) for p, info in PLANT.presets().items() for r in info.roads]
ALL_ROADS = [("paper-derlsp-ao", r) for r in friction_roads() if r != "sldemo-table"] + [
    ("sldemo", "sldemo-table")
]
CONTROLLERS = ["none", "pid", "bang-bang", "threshold"]
GOOD_PID = {"kp": 5000.0, "ki": 0.0, "kd": 230.0}


def run(preset: str, road: str, controller: str, gains=None, **params):
    sc = PLANT.scenario(preset, road, controller, params)
    return sc, sc.trace(sc.gains_array(gains))


@pytest.mark.parametrize(("preset", "road"), ALL_ROADS)
@pytest.mark.parametrize("controller", CONTROLLERS)
def test_no_controller_beats_the_physical_bound_and_slip_stays_physical(preset, road, controller):
    # t_max 150 s: Burckhardt ice (mu 0.05) needs about 61 s from 30 m/s
    _sc, tr = run(
        preset, road, controller, GOOD_PID if controller == "pid" else None, t_max_s=150.0
    )
    m = tr.metrics
    assert m["stopped"], m["status"]
    assert m["stop_distance_m"] >= m["bound_distance_m"] * (1 - 1e-9)
    assert m["stop_time_s"] >= m["bound_time_s"] * (1 - 1e-9)
    # the unclipped slip (v - w R)/v stays in [0, 1]: the guard clip never acts beyond rounding
    assert m["slip_clip_max"] <= 1e-12
    assert m["min_slip_unclipped"] >= -1e-12
    assert np.all((tr.signals["slip"] >= 0) & (tr.signals["slip"] <= 1))


@pytest.mark.parametrize("road", list(BILINEAR_ROADS))
def test_without_abs_the_locked_wheel_skids_as_coulomb_friction_says(road):
    sc, tr = run("paper-derlsp-ao", road, "none")
    pp, g = sc.plant_params, sc.plant_params.g_m_s2
    mu_lock = float(sc.tire.mu(1.0))
    sig, m = tr.signals, tr.metrics
    assert m["wheel_lock_time_s"] is not None and 0.3 < m["wheel_lock_time_s"] < 1.5
    k = int(np.argmax(sig["time_s"] >= m["wheel_lock_time_s"] - 1e-12))
    v_lock = sig["vehicle_speed_m_s"][k]
    skid = m["stop_distance_m"] - sig["distance_m"][k]
    expected = (v_lock**2 - pp.v_stop_m_s**2) / (2 * mu_lock * g)
    assert skid == pytest.approx(expected, rel=5e-3)
    whole = (pp.v0_m_s**2 - pp.v_stop_m_s**2) / (2 * mu_lock * g)
    assert m["stop_distance_m"] == pytest.approx(whole, rel=0.05)


def test_energy_balance_kinetic_energy_equals_friction_work():
    sc, tr = run("paper-derlsp-ao", "wet-asphalt", "pid", GOOD_PID)
    s = tr.signals
    pp = sc.plant_params
    work_per_kg = np.trapezoid(s["mu"] * pp.g_m_s2 * s["vehicle_speed_m_s"], s["time_s"])
    kinetic_per_kg = 0.5 * (pp.v0_m_s**2 - s["vehicle_speed_m_s"][-1] ** 2)
    assert work_per_kg == pytest.approx(kinetic_per_kg, rel=2e-3)


@pytest.mark.parametrize(
    ("road", "tolerance"), [("dry-concrete", 0.08), ("wet-asphalt", 0.08), ("ice", 0.03)]
)
def test_a_hand_set_pid_stops_near_the_bound_and_tracks_the_target_slip(road, tolerance):
    sc, tr = run("paper-derlsp-ao", road, "pid", GOOD_PID)
    m = tr.metrics
    assert 1.0 <= m["distance_ratio"] <= 1.0 + tolerance
    after = tr.signals["time_s"] > 1.0
    assert np.mean(np.abs(tr.signals["slip"][after] - sc.target_slip)) <= 0.02
    assert m["wheel_lock_time_s"] is None


@pytest.mark.parametrize("controller", ["pid", "threshold", "none"])
def test_distance_and_itae_converge_as_the_step_halves(controller):
    gains = GOOD_PID if controller == "pid" else None
    res = {}
    for dt in (1e-3, 5e-4, 2.5e-4, 6.25e-5):
        sc = PLANT.scenario("paper-derlsp-ao", "dry-concrete", controller, {"dt_s": dt})
        m = sc.metrics(sc.gains_array(gains)[None, :])
        res[dt] = (m["stop_distance_m"][0], m["slip_itae"][0])
    ref = res[6.25e-5]
    for k in range(2):
        errs = [abs(res[dt][k] - ref[k]) / abs(ref[k]) for dt in (1e-3, 5e-4, 2.5e-4)]
        assert errs[0] >= errs[1] >= errs[2] or max(errs) < 1e-5, errs
        assert errs[0] < 2e-3


def test_a_batch_row_equals_the_single_run_and_runs_are_deterministic():
    rng = np.random.default_rng(7)
    gains = np.column_stack(
        [rng.uniform(0, 1e4, 70), rng.uniform(0, 1e3, 70), rng.uniform(0, 1e3, 70)]
    )
    sc = PLANT.scenario("paper-derlsp-ao", "wet-asphalt", "pid")
    batch = sc.raw(gains, workers=2)
    np.testing.assert_array_equal(batch, sc.raw(gains, workers=1))
    for i in (0, 33, 69):
        np.testing.assert_array_equal(batch[i], sc.raw(gains[i : i + 1], workers=1)[0])
        trace_metrics = sc.trace(gains[i]).metrics
        assert trace_metrics["stop_distance_m"] == batch[i, 2]


def test_wild_gains_get_a_finite_penalty_never_nan():
    sc = PLANT.scenario("paper-derlsp-ao", "dry-concrete", "pid")
    gains = np.array(
        [
            [1e12, 1e12, 1e12],
            [-1e4, -1e4, -1e3],
            [0.0, 0.0, 0.0],
            [1e-3, 0.0, 0.0],
            [5000.0, 0.0, 230.0],
        ]
    )
    for objective in sc.objectives:
        cost = sc.cost(gains, objective)
        assert np.all(np.isfinite(cost)) and np.all(cost <= PENALTY)
        assert cost[-1] < PENALTY
    assert sc.cost(gains[3:4])[0] == PENALTY  # never brakes hard enough: hopeless, stopped early


def test_a_wheel_lock_is_penalized_in_proportion_to_its_duration():
    sc = PLANT.scenario("paper-derlsp-ao", "dry-concrete", "pid")
    raw = sc.raw(np.array([[5000.0, 0.0, 230.0]]))
    locked = raw.copy()
    locked[0, 9] = 0.5  # M_LOCKED_S
    assert sc.cost_from_raw(locked)[0] == pytest.approx(
        sc.cost_from_raw(raw)[0] + 0.5 * sc.scoring.lock_penalty_per_s
    )


def test_sldemo_reproduces_mathworks_published_behaviour():
    # the demo runs to standstill (its wheel is locked by then): v_stop 0.01 m/s
    _, with_abs = run("sldemo", "sldemo-table", "bang-bang", v_stop_m_s=0.01)
    _, no_abs = run("sldemo", "sldemo-table", "none", v_stop_m_s=0.01)
    assert with_abs.metrics["stop_time_s"] == pytest.approx(14.0, abs=0.15)
    assert no_abs.metrics["wheel_lock_time_s"] == pytest.approx(6.85, abs=0.1)
    extra_m = no_abs.metrics["stop_distance_m"] - with_abs.metrics["stop_distance_m"]
    extra_s = no_abs.metrics["stop_time_s"] - with_abs.metrics["stop_time_s"]
    assert extra_m == pytest.approx(26.0, abs=1.5)  # "about 100 ft (30 m)" in the demo's text
    assert extra_s == pytest.approx(2.8, abs=0.2)
