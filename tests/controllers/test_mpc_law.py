"""Model-predictive slip control (controllers/laws/mpc.py, docs/abs_laws.md 5), horizons 1 (the
default, closed form) and 3 (the interior point): the ideal wheel kernel runs it as its scalar
reference (tests/controllers/literature_laws_reference.py: the QP built from the published
prediction model and solved by exact active-set enumeration, in a plain loop at RK4 steps of
1 ms); its move is the QP's first move (exact enumeration, and `slip_mpc_qp.horizon1_move` at
N = 1) at horizons 1 to 5; in closed loop every move respects the QP's pressure-rate and pressure
limits; from its registry defaults it stops within 1.5 adhesion bounds (single wheel in the
realistic ECU: dry concrete, ice; vehicle: dry concrete, mu-jump; and N = 3); a batch row is its
single run. Wild gains, conformance and the C replay are the registry-wide tests (tests/export,
with N = 3 in test_c99.py; tests/scenarios/test_check_plant.py)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from literature_laws_reference import (
    DRY_CONCRETE,
    ICE,
    LAWS,
    RATE_MAX,
    WHEEL,
    Measured,
    assert_batch_rows_are_single_runs,
    assert_kernel_runs_reference,
    closed_loop,
    mpc_qp,
    qp_by_enumeration,
)

from chassistune.controllers import slip_mpc_qp as qp
from chassistune.controllers.laws import mpc
from chassistune.errors import InputError
from chassistune.scenarios.registry import get_plant

LAW = mpc.LAW.name
ROADS = {"dry-concrete": DRY_CONCRETE, "ice": ICE}
TS_S = 0.005
DISTANCE_RTOL = 1e-7
"""Measured: 7e-9 (N = 1) and 1.1e-8 (N = 3) on dry concrete, 3e-11 on ice."""
SLIP_ATOL = 1e-6
"""On the slip at every sample instant."""
MOVE_RTOL = 1e-9
"""On the move, in units of the move limit r_max ts, against the exact minimiser."""
QP_MOVE_RTOL = 1e-8
"""The same at horizons 2 .. 5 (the interior point: the solver's 1e-8 of its largest move)."""
HORIZONS = (1, 3)
"""The closed form (the registry default) and a horizon the interior point solves."""


def _reference_gains(target: float, horizon: int):
    return dataclasses.replace(LAWS[LAW][1], horizon=horizon, target=target)


@pytest.mark.parametrize("horizon", HORIZONS)
@pytest.mark.parametrize("road", ROADS)
def test_the_ideal_kernel_runs_the_law_as_its_reference(road: str, horizon: int) -> None:
    """The kernel's QP (closed form at N = 1, the interior point at N = 3) against the
    reference's exact enumeration, in closed loop."""
    sc = get_plant("abs-wheel").scenario(None, road, LAW, {"ts_s": TS_S, "horizon": horizon}, 0)
    step = LAWS[LAW][0]
    ref = closed_loop(
        step,
        _reference_gains(sc.target_slip, horizon),
        ROADS[road],
        ts_s=TS_S,
        dt_s=sc.plant_params.dt_s,
    )
    assert_kernel_runs_reference(sc, ref, TS_S, DISTANCE_RTOL, SLIP_ATOL)


def _random_qp(rng: np.random.Generator, i: int, horizon: int) -> tuple:
    """A random instance of the law's own QP (every fourth with q on a limit): (the law's first
    move, the exact enumeration's, the move limit dq, q, H, f)."""
    ts = float(rng.choice([1e-3, 5e-3, 1e-2]))
    q = float(rng.uniform(0.0, WHEEL.q_max)) if i % 4 else float(rng.choice([0.0, 1500.0]))
    case = {
        "slip": rng.uniform(0.0, 1.0),
        "target": rng.uniform(0.03, 0.4),
        "v_m_s": rng.uniform(0.5, 40.0),
        "q": q,
        "force_n": rng.uniform(0.0, 1200.0),
        "lookahead_s": rng.uniform(0.005, 0.3),
        "move_weight": 10.0 ** rng.uniform(-5.0, 1.0),
    }
    got = mpc.compiled()[2](
        case["slip"],
        case["target"],
        case["v_m_s"],
        q,
        case["force_n"],
        case["lookahead_s"],
        case["move_weight"],
        ts,
        WHEEL.q_max,
        RATE_MAX,
        WHEEL.radius_m,
        WHEEL.inertia_kg_m2,
        WHEEL.mass_kg,
        WHEEL.brake_gain,
        horizon,
    )
    h, f, dq = mpc_qp(horizon, ts_s=ts, rate_max=RATE_MAX, **case)
    box = np.full(horizon, dq)
    exact = qp_by_enumeration(h, f, -box, box, q, WHEEL.q_max)[0]
    return got, exact, dq, q, h, f


def test_the_move_is_the_qps_minimiser() -> None:
    """On random instances of the law's own QP: the law's move equals the exact minimiser and
    the solver's closed form (horizon 1)."""
    rng = np.random.default_rng(3)
    active = 0
    for i in range(200):
        got, exact, dq, q, h, f = _random_qp(rng, i, 1)
        assert abs(got - exact) <= MOVE_RTOL * dq
        closed_form = qp.horizon1_move(h[0, 0], f[0], -dq, dq, q, WHEEL.q_max)
        assert abs(got - closed_form) <= MOVE_RTOL * dq
        reached = q + exact
        active += abs(exact) >= dq * (1.0 - 1e-9) or min(reached, WHEEL.q_max - reached) < 1e-9
    assert 10 < active < 190  # both the free minimiser and the limits are exercised


@pytest.mark.parametrize("horizon", range(2, qp.MAX_HORIZON + 1))
def test_a_longer_horizons_move_is_the_qps_first_move(horizon: int) -> None:
    """On random instances of the law's own QP of horizon 2 .. 5 (the interior point in the
    law's stack scratch) against the exact enumeration's first move."""
    rng = np.random.default_rng(horizon)
    for i in range(60):
        got, exact, dq, _, _, _ = _random_qp(rng, i, horizon)
        assert abs(got - exact) <= QP_MOVE_RTOL * dq


def test_the_interior_point_solves_a_qp_started_on_the_pressure_limit() -> None:
    """An instance of the law's QP (q = q_max, the free minimiser -25.49 inside its interval)
    that a start at z = 0, on the pressure limit, sent into a cycle ending at -25.0
    (`slip_mpc_qp` module docstring)."""
    h, f = np.array([[5.448022641609194e-06]]), np.array([0.00013884674186551857])
    lo, hi = np.array([-50.0]), np.array([50.0])
    mat, vec = qp.scratch(1)
    z = np.empty(1)
    qp.solve_moves(h, f, lo, hi, 1500.0, 1500.0, qp.IPM_ITERATIONS, qp.POLISH_STEPS, z, mat, vec)
    assert abs(z[0] + f[0] / h[0, 0]) <= 1e-8 * 50.0


@pytest.mark.parametrize("horizon", HORIZONS)
@pytest.mark.parametrize("road", ROADS)
def test_in_closed_loop_every_move_respects_the_qps_limits(road: str, horizon: int) -> None:
    """The law's discrete step (what the ECU runs and C ships) in the reference loop: each
    sample's rate r keeps |r| <= r_max and 0 <= q + r ts <= q_max."""
    _, step, _ = mpc.compiled()
    wheel = WHEEL
    values = {
        "lookahead_s": 0.05,
        "move_weight": 1e-2,
        "nominal_inertia_kg_m2": wheel.inertia_kg_m2,
        "nominal_mass_kg": wheel.mass_kg,
        "nominal_brake_gain": wheel.brake_gain,
        "nominal_q_max": wheel.q_max,
        "nominal_actuator_gain": wheel.actuator_gain,
        "rate_limit": RATE_MAX,
        "target_slip": ROADS[road].slip_opt,
        "ts_s": TS_S,
        "wheel_radius_m": wheel.radius_m,
        "horizon": horizon,
    }
    params = np.array([values[n] for n in mpc.DISCRETE.params])
    state, table, grid = np.zeros(len(mpc.DISCRETE.state)), np.zeros(1), np.zeros(1)
    seen: list[tuple[float, float]] = []

    def law(_gains: object, mem: tuple, m: Measured) -> tuple[tuple, float]:
        inputs = np.array(
            [
                m.slip,
                m.v_ref_m_s,
                m.wheel_speed_rad_s,
                m.wheel_speed_prev_rad_s,
                m.pressure,
                m.pressure_prev,
            ]
        )
        r = step(state, inputs, params, table, grid) * wheel.actuator_gain
        seen.append((m.pressure, r))
        return mem, r

    stop = closed_loop(law, None, ROADS[road], ts_s=TS_S, dt_s=1e-3)
    assert stop.stopped and len(seen) > 400
    q, r = np.array(seen).T
    tol = 1e-9 * wheel.q_max
    assert np.all(np.abs(r) <= RATE_MAX * (1.0 + 1e-12))
    q_next = np.clip(q, 0.0, wheel.q_max) + r * TS_S
    assert np.all(q_next >= -tol) and np.all(q_next <= wheel.q_max + tol)
    assert np.any(np.abs(r) >= RATE_MAX * (1.0 - 1e-12))  # the rate limit is active at times


@pytest.mark.parametrize(
    ("road", "params"),
    [
        ("ice", {"ecu": "realistic"}),
        ("ice", {"ecu": "realistic", "horizon": 3}),
        ("dry-concrete", {"horizon": 3}),
    ],
)
def test_the_batch_row_is_its_single_run(road: str, params: dict[str, object]) -> None:
    """In the realistic ECU and, at N = 3, in the ideal kernel."""
    sc = get_plant("abs-wheel").scenario(None, road, LAW, params, 0)
    assert_batch_rows_are_single_runs(sc)


@pytest.mark.parametrize(
    ("plant", "road", "params"),
    [
        ("abs-wheel", "dry-concrete", {"ecu": "realistic"}),
        ("abs-wheel", "ice", {"ecu": "realistic"}),
        ("abs-vehicle", "dry-concrete", {}),
        ("abs-vehicle", "mu-jump", {}),
        ("abs-wheel", "dry-concrete", {"ecu": "realistic", "horizon": 3}),
        ("abs-vehicle", "dry-concrete", {"horizon": 3}),
    ],
)
def test_from_its_defaults_the_law_stops_within_one_and_a_half_bounds(
    plant: str, road: str, params: dict[str, object]
) -> None:
    sc = get_plant(plant).scenario(None, road, LAW, params, 0)
    m = sc.metrics(sc.gains_array(None)[None, :])
    assert m["status"][0] == "stopped"
    assert m["stop_distance_m"][0] <= 1.5 * sc.bound_distance_m


@pytest.mark.parametrize("value", ["0", "6", "2.5", "-1"])
def test_a_horizon_outside_one_to_five_is_refused_naming_the_field(value: str) -> None:
    with pytest.raises(InputError, match=r"params\.horizon.*integer 1 \.\. 5"):
        get_plant("abs-wheel").scenario(None, "ice", LAW, {"horizon": value}, 0)
