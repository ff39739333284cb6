"""Exact stationary RMS: compiled Lyapunov solver against scipy, stability test, realization."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import solve_continuous_lyapunov

from chassistune.plants import quarter_car as M
from chassistune.scenarios.quarter_car import PLANT
from chassistune.sim import lyapunov as L

FEEDBACKS = list(M.FEEDBACK_CODES.values())
SI_BOX = np.array([1e4, 1e5, 1e3])


def plant_vector(preset: str) -> np.ndarray:
    return PLANT.scenario(preset, controller="pid").plant_vector


def minimal(
    p: np.ndarray, fb: int, g: np.ndarray, n_filter: float = 100.0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    a = np.zeros((M.MAX_STATES, M.MAX_STATES))
    b = np.zeros(M.MAX_STATES)
    c = np.zeros((M.N_OUT, M.MAX_STATES))
    m = M.closed_loop(p, fb, g[0], g[1], g[2], n_filter, False, a, b, c)
    assert m > 0
    return a[:m, :m].copy(), b[:m].copy(), c[:, :m].copy()


def test_solver_matches_scipy_on_random_hurwitz_matrices() -> None:
    rng = np.random.default_rng(1)
    for m in range(1, 8):
        for _ in range(20):
            a = rng.normal(size=(m, m)) * rng.uniform(0.1, 100)
            a -= (np.max(np.linalg.eigvals(a).real) + rng.uniform(0.01, 5)) * np.eye(m)
            b = rng.normal(size=m)
            p = np.zeros((m, m))
            x = np.zeros((m, m))
            assert L.solve_lyapunov(a, m, b, 0.5, p, x)
            ref = solve_continuous_lyapunov(a, -0.5 * np.outer(b, b))
            assert np.max(np.abs(p - ref)) <= 1e-9 * np.max(np.abs(ref))


@pytest.mark.parametrize("preset", ["paper-iabc", "typical"])
@pytest.mark.parametrize("fb", FEEDBACKS)
def test_quarter_car_covariance_matches_scipy(preset: str, fb: int) -> None:
    p = plant_vector(preset)
    rng = np.random.default_rng(fb)
    gains = rng.uniform(0, 1, (40, 3)) * SI_BOX
    gains[::4, 1] = 0.0  # integrator dropped
    gains[1::4, 2] = 0.0  # filter dropped
    out = L.exact_rms(p, fb, 100.0, gains)
    checked = 0
    for g, row in zip(gains, out, strict=True):
        a, b, c = minimal(p, fb, g)
        if np.max(np.linalg.eigvals(a).real) >= 0:
            assert row[L.E_STABLE] == 0.0
            continue
        ref = solve_continuous_lyapunov(a, -L.W_ROAD * np.outer(b, b))
        pp = np.zeros_like(a)
        x = np.zeros_like(a)
        assert L.solve_lyapunov(a, a.shape[0], b, L.W_ROAD, pp, x)
        assert np.max(np.abs(pp - ref)) <= 1e-9 * np.max(np.abs(ref))
        rms_ref = np.sqrt(
            [c[j] @ ref @ c[j] for j in (M.OUT_ACC, M.OUT_TRAVEL, M.OUT_TIRE, M.OUT_FORCE)]
        )
        np.testing.assert_allclose(row[:4], rms_ref, rtol=1e-9)
        assert row[L.E_STABLE] == 1.0
        checked += 1
    assert checked >= 20


@pytest.mark.parametrize("preset", ["paper-iabc", "typical"])
def test_stability_flag_agrees_with_eigenvalues(preset: str) -> None:
    p = plant_vector(preset)
    rng = np.random.default_rng(5)
    for fb in FEEDBACKS:
        gains = rng.uniform(-0.3, 1, (150, 3)) * SI_BOX
        out = L.exact_rms(p, fb, 100.0, gains)
        for g, row in zip(gains, out, strict=True):
            a = np.zeros((M.MAX_STATES, M.MAX_STATES))
            m = M.closed_loop(
                p,
                fb,
                g[0],
                g[1],
                g[2],
                100.0,
                False,
                a,
                np.zeros(M.MAX_STATES),
                np.zeros((M.N_OUT, M.MAX_STATES)),
            )
            if m < 0:
                assert row[L.E_STABLE] == 0.0
                continue
            top = np.max(np.linalg.eigvals(a[:m, :m]).real)
            if abs(top) > 1e-6:
                assert row[L.E_STABLE] == float(top < 0), (fb, g, top)


def test_minimal_realization_sizes() -> None:
    p = plant_vector("typical")
    for fb, g, m in [
        (M.FB_VELOCITY, (0, 0, 0), 5),
        (M.FB_VELOCITY, (100, 100, 0), 5),
        (M.FB_VELOCITY, (100, 100, 10), 6),
        (M.FB_ACCELERATION, (100, 100, 10), 6),
        (M.FB_DISPLACEMENT, (100, 0, 0), 5),
        (M.FB_DISPLACEMENT, (100, 100, 10), 7),
        (M.FB_TRAVEL, (100, 100, 0), 6),
    ]:
        assert minimal(p, fb, np.array(g, dtype=float))[0].shape == (m, m)


@pytest.mark.parametrize("fb", FEEDBACKS)
def test_realization_matches_laplace_domain_equations(fb: int) -> None:
    """RMS from the frequency response written from the equations of motion (independent path)."""
    p = plant_vector("typical")
    g = {
        M.FB_DISPLACEMENT: (2000.0, 3000.0, 300.0),
        M.FB_VELOCITY: (800.0, 1500.0, 150.0),
        M.FB_ACCELERATION: (50.0, 400.0, 2.0),
        M.FB_TRAVEL: (500.0, 800.0, 100.0),
    }[fb]
    exact = L.exact_rms(p, fb, 100.0, np.array([g]))[0]
    assert exact[L.E_STABLE] == 1.0
    omega = np.geomspace(1e-6, 1e6, 240_001)
    resp = M.frequency_response(p, fb, *g, 100.0, omega)
    road = p[M.P_B] / (1j * omega + p[M.P_LAM])  # Z0 / w
    for col, key in [
        (L.E_ACC, "body_acc"),
        (L.E_TRAVEL, "susp_travel"),
        (L.E_TIRE, "tire_defl"),
        (L.E_FORCE, "force"),
    ]:
        power = np.abs(resp[key] * road) ** 2
        var = L.W_ROAD / np.pi * np.trapezoid(power * omega, np.log(omega))
        assert np.sqrt(var) == pytest.approx(exact[col], rel=1e-5), key


def test_unstable_and_singular_loops_are_flagged_not_nan() -> None:
    p = plant_vector("paper-iabc")
    gains = np.array([[-2e4, 0, 0], [0, -1e6, 0], [0, 0, -400.0]])
    out = L.exact_rms(p, M.FB_VELOCITY, 100.0, gains)
    assert np.all(out[:, L.E_STABLE] == 0.0)
    # body-acceleration feedback with 1 + (kp + kd N)/ms <= 0 has no closed loop at all
    out = L.exact_rms(p, M.FB_ACCELERATION, 100.0, np.array([[-320.0, 0, 0]]))
    assert out[0, L.E_STABLE] == 0.0
    q = L.rms_ratio(out, np.ones(3), out[:, L.E_STABLE] == 1.0, 1e9)
    assert q.tolist() == [1e9]
