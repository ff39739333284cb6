"""Discrete ABS laws: the ECU table's error against exact inference, analytic cases of each law,
and the sampled closed loop against the kernel."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import CONTINUOUS, case, gain_rows, ideal_mode
from numba import njit

from chassistune.controllers import discrete, discrete_lookup, laws
from chassistune.export import closed_loop, source, vectors
from chassistune.fuzzy.engine import evaluate
from chassistune.fuzzy.loader import load_rulebase
from chassistune.scenarios.registry import get_plant


@njit(cache=True)
def _lookup_all(table, grid, x0, x1):
    out = np.empty((x0.size, table.shape[0]))
    for p in range(x0.size):
        cell = discrete_lookup.table_cell(table, grid, x0[p], x1[p])
        for k in range(table.shape[0]):
            out[p, k] = discrete_lookup.table_value(table, k, cell)
    return out


def _table_error(name: str, points: int) -> np.ndarray:
    """Largest error per output over random points, as a fraction of the output range."""
    rb = load_rulebase(name)
    table, grid, _ = discrete.ecu_table(rb, points)
    rng = np.random.default_rng(7)
    x = np.column_stack([rng.uniform(*v.universe, 40_000) for v in rb.inputs])
    err = np.abs(_lookup_all(table, grid, x[:, 0].copy(), x[:, 1].copy()) - evaluate(rb, x))
    return err.max(axis=0) / np.array([v.span for v in rb.outputs])


# the bounds stated in controllers/discrete.py (measured there over 200,000 points)
@pytest.mark.parametrize(
    ("name", "bound"), [("deffao", 0.044), ("classic", 0.064), ("immune", 0.077)]
)
def test_default_table_error_is_the_stated_one_and_falls_with_points(
    name: str, bound: float
) -> None:
    coarse = _table_error(name, discrete.DEFAULT_TABLE_POINTS)
    assert coarse.max() <= bound
    assert coarse.max() > 0.5 * bound  # the statement is not loose either
    fine = _table_error(name, 2 * discrete.DEFAULT_TABLE_POINTS - 1)
    assert fine.max() < 0.6 * coarse.max()  # first order across the remaining kinks


def test_table_reproduces_exact_inference_at_its_nodes_and_clips_outside() -> None:
    rb = load_rulebase("deffao")
    table, grid, bp = discrete.ecu_table(rb, 13)
    i, j = np.meshgrid(np.arange(13), np.arange(13), indexing="ij")
    x0, x1 = bp[0][i.ravel()], bp[1][j.ravel()]
    got = _lookup_all(table, grid, x0, x1)
    assert np.array_equal(got, evaluate(rb, np.column_stack([x0, x1])))
    far = _lookup_all(table, grid, np.array([-50.0, 50.0]), np.array([50.0, -50.0]))
    edge = evaluate(rb, np.array([[-3.0, 3.0], [3.0, -3.0]]))
    assert np.array_equal(far, edge)
    assert np.isnan(_lookup_all(table, grid, np.array([np.nan]), np.array([0.0]))).all()


def _pid_params(kp: float, ki: float, kd: float, n: float, ts: float) -> np.ndarray:
    return np.array([kp, ki, kd, n, 0.2, ts])


def test_pid_forward_euler_integral_and_conditional_integration() -> None:
    table, grid = discrete.no_table()
    ts, e = 1e-3, 0.05
    slip = 0.2 - e
    free = np.tile([slip, 0.0, 0.0], (50, 1))
    u = discrete.run_vectors(
        laws.kind("pid"), free, _pid_params(100.0, 30.0, 0.0, 100.0, ts), table, grid
    )
    k = np.arange(50)
    np.testing.assert_allclose(u, 100.0 * e + 30.0 * ts * e * k, rtol=1e-12)
    # pressure at q_max and e > 0: the integral holds (no windup); at q = 0 and e > 0 it runs
    held = np.tile([slip, 1.0, 0.0], (50, 1))
    u_held = discrete.run_vectors(
        laws.kind("pid"), held, _pid_params(100.0, 30.0, 0.0, 100.0, ts), table, grid
    )
    assert np.all(u_held == u_held[0])
    at_min = np.tile([slip, 0.0, 1.0], (50, 1))
    assert np.array_equal(
        discrete.run_vectors(
            laws.kind("pid"), at_min, _pid_params(100.0, 30.0, 0.0, 100.0, ts), table, grid
        ),
        u,
    )


@pytest.mark.parametrize("ts", [1e-3, 0.02, 0.05])
def test_backward_euler_filter_has_no_kick_and_is_stable_at_any_sample_time(ts: float) -> None:
    """d after a step in e decays by 1/(1 + N ts) per sample, without a sign change, also at
    N ts >= 2 where a forward-Euler filter diverges."""
    table, grid = discrete.no_table()
    n = 100.0
    rows = np.array([[0.2, 0.0, 0.0]] * 3 + [[0.1, 0.0, 0.0]] * 40)  # e: 0, 0, 0, then 0.1
    u = discrete.run_vectors(laws.kind("pid"), rows, _pid_params(0.0, 0.0, 1.0, n, ts), table, grid)
    assert np.all(u[:3] == 0.0)  # no derivative kick at the start
    a = ts * n
    expected = n * 0.1 * (1.0 / (1.0 + a)) ** np.arange(1, 41)
    np.testing.assert_allclose(u[3:], expected, rtol=1e-9, atol=1e-13 * expected[0])
    assert np.all(u[3:] > -1e-13 * expected[0])  # no oscillation


def test_an_unknown_kind_runs_no_law_it_is_refused() -> None:
    table, grid = discrete.no_table()
    rows = np.array([[0.2, 0.0, 0.0]] * 3)
    params = _pid_params(1.0, 0.0, 0.0, 100.0, 0.01)
    with pytest.raises(ValueError, match="no control law of kind 99"):
        discrete.run_vectors(99, rows, params, table, grid)
    assert np.all(np.isfinite(discrete.run_vectors(laws.kind("pid"), rows, params, table, grid)))


def test_immune_incremental_law_equals_the_positional_pid_at_fixed_gain() -> None:
    """eta = 0: u_k = kp e_k + ki ts sum(e) + kd (e_k - e_k-1) / ts, with e_-1 = e_0."""
    ec = case("fuzzy-immune-pid").ec
    params = ec.params.copy()
    names = ec.law.params
    kp, ki, kd, ts = 800.0, 40.0, 3.0, 1e-3
    for name, value in (("k_immune", kp), ("eta", 0.0), ("ki", ki), ("kd", kd), ("ts_s", ts)):
        params[names.index(name)] = value
    rng = np.random.default_rng(3)
    slip = rng.uniform(0.0, 0.4, 60)
    u = discrete.run_vectors(
        laws.kind("fuzzy-immune-pid"), slip[:, None], params, ec.table, ec.grid
    )
    e = 0.2 - slip
    e_prev = np.concatenate([[e[0]], e[:-1]])
    positional = kp * e + ki * ts * np.cumsum(e) + kd * (e - e_prev) / ts
    np.testing.assert_allclose(u, positional, rtol=1e-9, atol=1e-9)


def test_sampled_threshold_loop_gives_the_ideal_kernels_stop_bit_for_bit() -> None:
    """The loop integrates the plant as the kernels do: with the threshold law, sampled in the
    ideal kernel too, the stop distance and time are the ideal kernel's, exactly, on every tire
    law the kernels have (and the realistic kernel's with the export's ideal ECU)."""
    cases = [
        (None, None, {}),
        (None, None, {"ts_s": 0.004}),
        (None, None, {"dt_s": 5e-4, "ts_s": 0.002}),
        (None, "burckhardt-wet-asphalt", {}),
        ("sldemo", "sldemo-table", {}),
    ]
    for preset, road, params in cases:
        ts = float(params.get("ts_s", 1e-3))  # type: ignore[arg-type]
        ec = source.resolve(None, None, "threshold", {}, {**params, "ecu_ts_s": ts}, preset, road)
        run = vectors.stop(ec)
        ideal = ideal_mode(ec, params).metrics(np.zeros((1, 0)))
        realistic = ec.scenario.metrics(np.zeros((1, 0)))
        assert run.status == 0
        for kernel in (ideal, realistic):
            assert run.stop_distance_m == kernel["stop_distance_m"][0]
            assert run.stop_time_s == kernel["stop_time_s"][0]


@pytest.mark.parametrize("controller", CONTINUOUS)
def test_discrete_laws_stop_the_car_near_the_continuous_kernel(controller: str) -> None:
    """Physics: each sampled law (5 ms) stops the car, never beats the bound, and lands within
    0.5 % of the ideal kernel (continuous PID; fuzzy laws on the adaptive table)."""
    c = case(controller)
    run = vectors.stop(c.ec)
    sc = c.ec.scenario
    kernel = ideal_mode(c.ec, {}).metrics(gain_rows(c.ec))["stop_distance_m"][0]
    assert run.status == 0
    assert run.stop_distance_m > sc.bound_distance_m
    assert abs(run.stop_distance_m / kernel - 1.0) < 0.005
    assert np.array_equal(run.u, c.u)  # the recorded vectors are this run's
    assert run.signals["slip"].size == c.inputs.shape[0]


def test_loop_inputs_are_what_an_ideal_ecu_sees() -> None:
    run = vectors.stop(case("pid").ec)
    s = run.signals
    assert set(s) == set(closed_loop.SIGNALS)
    assert s["slip"][0] == 0.0 and np.all((s["slip"] >= 0.0) & (s["slip"] <= 1.0))
    assert set(np.unique(s["pressure_at_max"])) <= {0.0, 1.0}
    assert s["pressure_at_min"][0] == 1.0  # the brake starts released
    assert np.all(np.diff(s["wheel_speed_rad_s"][:5]) < 0.0)  # braking from the start


def test_immune_loop_converges_to_the_ideal_kernel_as_the_table_is_refined() -> None:
    """At the ideal kernel's 1 ms both sample the same incremental law; only the table differs
    (the ideal kernel reads its adaptive surface, within 2e-4 of exact): the stop converges."""
    gaps = []
    for points in (25, 49, 97):
        ec = source.resolve(
            None, None, "fuzzy-immune-pid", {}, {"fuzzy_table_points": points, "ecu_ts_s": 1e-3}
        )
        kernel = ideal_mode(ec, {}).metrics(gain_rows(ec))["stop_distance_m"][0]
        gaps.append(abs(vectors.stop(ec).stop_distance_m / kernel - 1.0))
    assert gaps[0] > gaps[1] > gaps[2]
    assert gaps[2] < 2e-5


def test_the_discrete_forms_declare_their_gains_first_and_fit_the_state_vector() -> None:
    """Each discrete form's parameters start with its spec's gains (the export fills them in that
    order), its state holds `started` and fits `N_STATE`, and the fuzzy PID, which runs the
    PID's filter and output, keeps the PID's state and inputs."""
    declared = {n: laws.get(n).discrete for n in laws.names() if laws.get(n).discrete}
    assert {"pid", "fuzzy-pid", "fuzzy-immune-pid", "threshold"} <= set(declared)
    for name, law in declared.items():
        assert law is not None and law.controller == name
        assert "started" in law.state and len(law.state) <= discrete.N_STATE
        assert law.params[: len(spec_gains(name))] == spec_gains(name)
        assert "slip" in law.inputs
    fuzzy, pid = declared["fuzzy-pid"], declared["pid"]
    assert fuzzy is not None and pid is not None
    assert fuzzy.state == pid.state and fuzzy.inputs == pid.inputs


def spec_gains(controller: str) -> tuple[str, ...]:
    return get_plant("abs-wheel").scenario(None, None, controller).gain_names
