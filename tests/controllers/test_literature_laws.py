"""The ABS literature's slip laws in the registry (docs/abs_laws.md): the ideal wheel kernel runs
each as its scalar reference (tests/controllers/literature_laws_reference.py) at the same sample
period and step (the kernel's RK4); the realistic ECU's batch row i is its single run i; from the
registry defaults each stops within 1.5 adhesion bounds on the single wheel (realistic ECU: dry
concrete, ice) and on the vehicle (dry concrete, mu-jump); mixed slip-deceleration, told no
road, within 1.3 on Burckhardt snow and without lock on every road of the wheel at two speeds
(in the realistic ECU: lock only below 3 m/s, where the toothed wheel's readings come too seldom;
its ECU form holds the deceleration between readings). The conformance check
(tests/scenarios/test_check_plant.py) and the C export's bit-for-bit replays (tests/export) take
every registered law, these included."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from literature_laws_reference import (
    DRY_CONCRETE,
    ICE,
    LAWS,
    assert_kernel_runs_reference,
    closed_loop,
)

from chassistune.controllers import discrete, laws
from chassistune.controllers.laws import mixed_slip_deceleration
from chassistune.scenarios.registry import get_plant

REGISTERED = ("sliding-mode", "mixed-slip-deceleration", "adrc")
ROADS = {"dry-concrete": DRY_CONCRETE, "ice": ICE}
TS_S = 0.005
DISTANCE_RTOL = 1e-7
"""Measured: the stops agree to 6e-9 (relative) or better on both roads."""
SLIP_ATOL = 1e-6
"""On the slip at every sample instant."""


@pytest.mark.parametrize("law", REGISTERED)
def test_the_law_is_registered_on_both_plants(law: str) -> None:
    assert {s.plant for s in laws.get(law).specs} == {laws.ABS_WHEEL, laws.ABS_VEHICLE}


@pytest.mark.parametrize("road", ROADS)
@pytest.mark.parametrize("law", REGISTERED)
def test_the_ideal_kernel_runs_the_law_as_its_reference(law: str, road: str) -> None:
    sc = get_plant("abs-wheel").scenario(None, road, law, {"ts_s": TS_S}, 0)
    tire = sc.tire
    assert (tire.slip_opt, tire.mu_peak, tire.mu_lock) == dataclasses.astuple(ROADS[road])
    step, gains = LAWS[law]
    if law != "mixed-slip-deceleration":  # the scenario's target slip (the road's peak)
        gains = dataclasses.replace(gains, target=sc.target_slip)
    ref = closed_loop(step, gains, ROADS[road], ts_s=TS_S, dt_s=sc.plant_params.dt_s)
    assert_kernel_runs_reference(sc, ref, TS_S, DISTANCE_RTOL, SLIP_ATOL)


def test_mixed_slip_deceleration_reads_no_target_slip() -> None:
    law = mixed_slip_deceleration.LAW
    assert not law.needs_target  # `list controllers` says so
    assert law.discrete is not None and "target_slip" not in law.discrete.params
    assert "target_slip" not in law.discrete.inputs
    wheel = get_plant("abs-wheel")
    runs = [
        wheel.scenario(None, "ice", law.name, {"ts_s": TS_S, "target_slip": s}, 0)
        for s in (0.05, 0.3)
    ]
    d = [float(sc.metrics(sc.gains_array(None)[None, :])["stop_distance_m"][0]) for sc in runs]
    assert runs[0].target_slip != runs[1].target_slip and d[0] == d[1]


@pytest.mark.parametrize("law", REGISTERED)
def test_the_realistic_ecus_batch_row_is_its_single_run(law: str) -> None:
    sc = get_plant("abs-wheel").scenario(None, "ice", law, {"ecu": "realistic"}, 0)
    spec = sc.controller
    rng = np.random.default_rng(7)
    lo, hi = np.array([g.lo for g in spec.gains]), np.array([g.hi for g in spec.gains])
    pop = lo + (hi - lo) * rng.random((5, len(spec.gains)))
    batch = sc.metrics(pop)
    single = [sc.metrics(row[None, :]) for row in pop]
    assert list(batch["status"]) == [m["status"][0] for m in single]
    # a run that times out has no stop distance (NaN), in the batch as alone
    distances = np.array([m["stop_distance_m"][0] for m in single])
    assert np.array_equal(batch["stop_distance_m"], distances, equal_nan=True)


@pytest.mark.parametrize(
    ("plant", "road", "params"),
    [
        ("abs-wheel", "dry-concrete", {"ecu": "realistic"}),
        ("abs-wheel", "ice", {"ecu": "realistic"}),
        ("abs-vehicle", "dry-concrete", {}),
        ("abs-vehicle", "mu-jump", {}),
    ],
)
@pytest.mark.parametrize("law", REGISTERED)
def test_from_its_defaults_the_law_stops_within_one_and_a_half_bounds(
    law: str, plant: str, road: str, params: dict[str, object]
) -> None:
    sc = get_plant(plant).scenario(None, road, law, params, 0)
    m = sc.metrics(sc.gains_array(None)[None, :])
    assert m["status"][0] == "stopped"
    assert m["stop_distance_m"][0] <= 1.5 * sc.bound_distance_m


def test_mixed_slip_deceleration_stops_within_1_3_bounds_on_snow_it_is_not_told() -> None:
    """Realistic ECU on Burckhardt snow (peak 0.19 at S = 0.06): the scenario's target slip
    moves (two values) and the stop does not, so the law read none; the stop is within 1.3
    adhesion bounds (measured 1.074)."""
    wheel = get_plant("abs-wheel")
    runs = [
        wheel.scenario(
            None,
            "burckhardt-snow",
            "mixed-slip-deceleration",
            {"ecu": "realistic", "target_slip": s},
            0,
        )
        for s in (0.05, 0.3)
    ]
    m = [sc.metrics(sc.gains_array(None)[None, :]) for sc in runs]
    assert runs[0].target_slip != runs[1].target_slip
    assert m[0]["stop_distance_m"][0] == m[1]["stop_distance_m"][0]
    assert m[0]["status"][0] == "stopped"
    assert m[0]["stop_distance_m"][0] <= 1.3 * runs[0].bound_distance_m


GRID_ROADS = tuple(get_plant("abs-wheel").roads())
"""Every road the single wheel offers; the mixed law's defaults were set on dry concrete."""
GRID_SPEEDS_M_S = (30.0, 15.0)
LOCK_SPEED_M_S = 3.0
"""In the realistic ECU the wheel may lock only below this speed. Measured (defaults, 48 teeth,
5 ms): the highest true speed with slip >= 0.99 on any road but Burckhardt ice is 2.68 m/s (ice
from 30 m/s; 2.21 dirt-0.2, 2.12 Burckhardt snow from 15 m/s), each a dip of at most 0.24 s just
above the 2 m/s cut-out. The sensor's edge rate sets it, not the law: a reading every R (2 pi /
48) / (w R) = 25 to 46 ms there, in which the wheel goes from slip 0.1 to lock (0.1 s on ice at
2.7 m/s); with 96 teeth, or the ideal sensor, no lock above 1.92 m/s; the registry's pid locks
up to 2.34 m/s and sliding-mode up to 3.99 m/s in the same grid. (The plain one-sample
difference of the held reading, zero between edges and a spike of 5 to 11 g at an edge, locked
the wheel up to 3.73 m/s.)"""
NO_PEAK = "burckhardt-ice"
"""c3 = 0: mu(S) rises to S = 1, a locked wheel is the road's best; no lock to avoid there."""


@pytest.mark.parametrize("v0_m_s", GRID_SPEEDS_M_S)
def test_mixed_slip_deceleration_never_locks_on_roads_it_was_not_tuned_on(v0_m_s: float) -> None:
    """Ideal kernel, every road of the wheel at two initial speeds: each run stops, finite,
    within 1.4 adhesion bounds (measured at most 1.33, cobblestone), and the wheel never locks."""
    wheel = get_plant("abs-wheel")
    for road in GRID_ROADS:
        sc = wheel.scenario(None, road, "mixed-slip-deceleration", {"v0_m_s": v0_m_s}, 0)
        m = sc.metrics(sc.gains_array(None)[None, :])
        assert m["status"][0] == "stopped", road
        assert np.isfinite(m["stop_distance_m"][0]), road
        assert m["stop_distance_m"][0] <= 1.4 * sc.bound_distance_m, road
        assert m["locked_time_s"][0] == 0.0 and np.isnan(m["wheel_lock_time_s"][0]), road


@pytest.mark.parametrize("v0_m_s", GRID_SPEEDS_M_S)
def test_mixed_slip_deceleration_in_the_ecu_locks_only_at_walking_speed(v0_m_s: float) -> None:
    """Realistic ECU (toothed wheel, accelerometer reference, three-state valves), every road
    of the wheel at two initial speeds: each run stops, finite, within 1.4 adhesion bounds
    (measured at most 1.35, Burckhardt cobblestone-dry from 15 m/s), the slip finite throughout,
    and on every road with a peak the wheel locked (slip >= 0.99) only below LOCK_SPEED_M_S."""
    wheel = get_plant("abs-wheel")
    for road in GRID_ROADS:
        params = {"ecu": "realistic", "v0_m_s": v0_m_s}
        sc = wheel.scenario(None, road, "mixed-slip-deceleration", params, 0)
        g = sc.gains_array(None)
        m = sc.metrics(g[None, :])
        assert m["status"][0] == "stopped", road
        assert np.isfinite(m["stop_distance_m"][0]), road
        assert m["stop_distance_m"][0] <= 1.4 * sc.bound_distance_m, road
        s = sc.trace(g).signals
        assert np.all(np.isfinite(s["slip"])), road
        if road != NO_PEAK:
            locked = s["slip"] >= 0.99
            assert np.all(s["vehicle_speed_m_s"][locked] < LOCK_SPEED_M_S), road


MIXED_ECU_PARAMS = {"alpha": 1.0, "target": 0.0, "kp": 1.0, "kd": 0.0}
"""eps = eta, e = -eta, u = kp e / K = -eta: the command shows the deceleration the law uses."""


def _mixed_ecu_commands(speeds_rad_s: list[float], prev_rad_s: float) -> np.ndarray:
    """The ECU form's commands fed wheel speed readings (slip 0), from rest."""
    law = mixed_slip_deceleration.DISCRETE
    values = {**MIXED_ECU_PARAMS, "nominal_actuator_gain": 1.0, "rate_limit": 1e9}
    params = np.array([values.get(n, 0.0) for n in law.params])
    params[mixed_slip_deceleration.D_TS] = TS_S
    params[mixed_slip_deceleration.D_RADIUS] = 0.5
    inputs = np.array(
        [[0.0, w, p] for w, p in zip(speeds_rad_s, [prev_rad_s, *speeds_rad_s[:-1]], strict=True)]
    )
    table, grid = discrete.no_table()
    kind = laws.kind(mixed_slip_deceleration.LAW.name)
    return discrete.run_vectors(kind, inputs, params, table, grid)


def test_the_mixed_laws_ecu_form_holds_the_deceleration_between_readings() -> None:
    """A toothed wheel's reading held for n samples: eta = -R (w - w_last) / (n ts) / g at the
    new reading and held until the next (no zero between readings, no spike at one). The
    reading 60 stands from the sample before the first (its `wheel_speed_prev_rad_s`), so 59
    comes 4 samples after it."""
    u = _mixed_ecu_commands([60.0, 60.0, 60.0, 59.0, 59.0, 58.5], 60.0)
    eta3 = -0.5 * ((59.0 - 60.0) / (4.0 * TS_S)) / 9.81
    eta5 = -0.5 * ((58.5 - 59.0) / (2.0 * TS_S)) / 9.81
    assert list(-u) == [0.0, 0.0, 0.0, eta3, eta3, eta5]


def test_the_mixed_laws_ecu_form_with_a_reading_every_sample_is_the_plain_difference() -> None:
    speeds = [60.0, 59.0, 57.5, 57.25]
    u = _mixed_ecu_commands(speeds, 61.0)
    plain = [
        -0.5 * ((w - p) / TS_S) / 9.81 for w, p in zip(speeds, [61.0, *speeds[:-1]], strict=True)
    ]
    assert list(-u) == plain
