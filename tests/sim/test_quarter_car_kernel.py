"""Compiled quarter-car simulation: exact discretization, batch = single runs, divergence."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from chassistune.plants import iso_roads
from chassistune.plants import quarter_car as M
from chassistune.scenarios.quarter_car import PLANT, QuarterCarScenario
from chassistune.sim import lti
from chassistune.sim import quarter_car_kernel as K


def test_expm_matches_scipy() -> None:
    rng = np.random.default_rng(2)
    for n in range(1, 9):
        for scale in (1e-3, 0.3, 2.0, 8.0):
            a = rng.normal(size=(n, n)) * scale
            out = np.empty((n, n))
            lti.expm_small(a, out)
            ref = expm(a)
            assert np.max(np.abs(out - ref)) <= 1e-12 * np.max(np.abs(ref))


def test_zoh_step_of_a_first_order_lag() -> None:
    a = np.array([[-3.0]])
    phi = np.zeros((1, 1))
    gam = np.zeros(1)
    lti.discretize_zoh(a, np.array([2.0]), 1, 0.1, phi, gam)
    assert phi[0, 0] == pytest.approx(np.exp(-0.3), rel=1e-14)
    assert gam[0] == pytest.approx(2.0 * (1 - np.exp(-0.3)) / 3.0, rel=1e-14)


def run(
    scenario: QuarterCarScenario, gains: np.ndarray, n_rec: int = 0
) -> tuple[np.ndarray, np.ndarray]:
    pid = scenario.pid_gains(gains)
    out = np.empty((pid.shape[0], K.N_RESULT))
    rec = np.zeros((M.N_OUT, n_rec))
    K.simulate_batch(
        scenario.plant_vector,
        scenario.feedback_code,
        100.0,
        pid,
        scenario.noise,
        scenario.solver.dt_s,
        rec,
        1,
        out,
    )
    return out, rec


@pytest.mark.parametrize("feedback", list(M.FEEDBACK_CODES))
def test_batch_rows_equal_single_runs(feedback: str) -> None:
    sc = PLANT.scenario("typical", controller="pid", params={"duration_s": 3, "feedback": feedback})
    rng = np.random.default_rng(11)
    gains = rng.uniform(0, 1, (70, 3)) * np.array([3e3, 3e3, 100.0])
    batch = sc.simulate(gains)  # chunked over threads
    serial, _ = run(sc, gains)
    np.testing.assert_array_equal(batch, serial)
    for i in (0, 1, 37, 63, 64, 69):
        single, _ = run(sc, gains[i : i + 1])
        np.testing.assert_array_equal(single[0], batch[i])
    exact = sc.exact(gains)
    for i in (0, 5, 69):
        np.testing.assert_array_equal(sc.exact(gains[i]), exact[i : i + 1])


def test_road_in_the_loop_is_the_generated_profile() -> None:
    sc = PLANT.scenario("paper-iabc", controller="pid", params={"duration_s": 20}, seed=4)
    _, rec = run(sc, np.array([[500.0, 500.0, 100.0]]), n_rec=sc.solver.n_steps + 1)
    z = iso_roads.road_profile(sc.road_params, sc.noise, sc.solver.dt_s)
    np.testing.assert_allclose(rec[M.OUT_ROAD], z, rtol=0, atol=1e-12 * np.max(np.abs(z)))
    assert np.all(rec[:, 0] == 0.0)


def test_trace_samples_match_the_rms() -> None:
    sc = PLANT.scenario("typical", controller="pid", params={"duration_s": 5}, seed=2)
    out, rec = run(sc, np.array([[800.0, 900.0, 50.0]]), n_rec=sc.solver.n_steps + 1)
    for col, row in [
        (K.R_ACC, M.OUT_ACC),
        (K.R_TRAVEL, M.OUT_TRAVEL),
        (K.R_TIRE, M.OUT_TIRE),
        (K.R_FORCE, M.OUT_FORCE),
    ]:
        assert out[0, col] == pytest.approx(np.sqrt(np.mean(rec[row, 1:] ** 2)), rel=1e-12)


def test_divergence_is_detected_and_frozen() -> None:
    sc = PLANT.scenario("paper-iabc", controller="pid", params={"duration_s": 10})
    gains = np.array([[0.0, -1e6, 0.0], [500.0, 500.0, 100.0]])
    out, _ = run(sc, gains)
    assert out[0, K.R_DIVERGED] == 1.0
    assert np.all(np.isnan(out[0, : K.N_RMS]))
    assert out[1, K.R_DIVERGED] == 0.0
    assert np.all(np.isfinite(out[1, : K.N_RMS]))
