"""The MPC's QP solver (controllers/slip_mpc_qp.py) against an exact active-set enumeration and
scipy's SLSQP on random instances, its constraints, and its horizon-1 closed form."""

from __future__ import annotations

import numpy as np
import pytest
from literature_laws_reference import mpc_qp
from literature_laws_reference import qp_by_enumeration as exact
from scipy.optimize import minimize

from chassistune.controllers import slip_mpc_qp as qp


def _slsqp(h, f, lo, hi, q0, q_max):
    """scipy's SLSQP on the same QP, posed in units of the largest move limit
    and the cost divided by its largest coefficient (its tolerances are absolute: unscaled, it
    stops far from the minimiser)."""
    n = f.shape[0]
    scale = max(np.abs(lo).max(), np.abs(hi).max())
    size = max(np.abs(h).max() * scale**2, np.abs(f).max() * scale)
    hs, fs = h * scale**2 / size, f * scale / size
    low = np.tril(np.ones((n, n)))
    start = np.zeros(n)  # strictly inside: the first move halfway towards the middle pressure
    start[0] = 0.5 * np.clip((0.5 * q_max - q0) / scale, lo[0] / scale, hi[0] / scale)
    res = minimize(
        lambda x: 0.5 * x @ hs @ x + fs @ x,
        start,
        jac=lambda x: hs @ x + fs,
        method="SLSQP",
        bounds=list(zip(lo / scale, hi / scale, strict=True)),
        constraints=[
            {"type": "ineq", "fun": lambda x: q0 / scale + low @ x, "jac": lambda x: low},
            {
                "type": "ineq",
                "fun": lambda x: (q_max - q0) / scale - low @ x,
                "jac": lambda x: -low,
            },
        ],
        options={"ftol": 1e-15, "maxiter": 1000},
    )
    # status 8 ("positive directional derivative") is SLSQP stopping at its rounding floor
    assert res.status in (0, 8), res.message
    return res.x * scale


def instances(n: int, count: int, seed: int):
    """Random QPs of horizon n: half the model-predictive law's own (`mpc_qp` from random slips,
    speeds, pressures, targets and weights on the paper-derlsp-ao wheel), half generic ones (H =
    A A' + d I, f, move limits, q0 and q_max drawn) scaled like them."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(count):
        q_max = 1500.0
        if i % 2 == 0:
            rate_max = rng.uniform(2e3, 2e4)
            ts = rng.choice([1e-3, 2e-3, 5e-3, 1e-2])
            q0 = rng.uniform(0.0, q_max) if i % 4 else rng.choice([0.0, q_max])
            h, f, dq = mpc_qp(
                n,
                slip=rng.uniform(0.0, 1.0),
                target=rng.uniform(0.02, 0.4),
                v_m_s=rng.uniform(1.0, 40.0),
                q=q0,
                force_n=rng.uniform(0.0, 1200.0),
                ts_s=ts,
                rate_max=rate_max,
                lookahead_s=rng.uniform(0.0, 0.2),
                move_weight=10.0 ** rng.uniform(-4, 1),
            )
            lo, hi = np.full(n, -dq), np.full(n, dq)
        else:
            a = rng.normal(size=(n, n))
            h = (a @ a.T + 10.0 ** rng.uniform(-3, 0) * np.eye(n)) / 100.0
            f = rng.normal(scale=3.0, size=n)
            dq = rng.uniform(1.0, 100.0)
            lo, hi = -rng.uniform(0.0, dq, n), rng.uniform(0.0, dq, n)
            q0 = rng.uniform(0.0, 60.0)
            q_max = q0 + rng.uniform(0.0, 60.0)
        out.append((h, f, lo, hi, float(q0), float(q_max)))
    return out


def _solve(case, iterations: int = qp.IPM_ITERATIONS) -> np.ndarray:
    h, f, lo, hi, q0, q_max = case
    z = np.empty(f.shape[0])
    qp.solve_moves(h, f, lo, hi, q0, q_max, iterations, qp.POLISH_STEPS, z, *qp.scratch(len(f)))
    return z


def _error(case, z: np.ndarray, z_star: np.ndarray) -> float:
    """|z - z*| in units of the instance's largest move limit (the solver's scaled units)."""
    return float(np.abs(z - z_star).max() / max(np.abs(case[2]).max(), np.abs(case[3]).max()))


@pytest.fixture(scope="module")
def cases():
    cs = [c for n in range(1, qp.MAX_HORIZON + 1) for c in instances(n, 60, 100 + n)]
    return [(c, exact(*c)) for c in cs]


def test_equals_exact_enumeration_and_respects_constraints(cases) -> None:
    for case, z_star in cases:
        z = _solve(case)
        _, _, lo, hi, q0, q_max = case
        assert np.all(np.isfinite(z))
        assert _error(case, z, z_star) <= 1e-8
        assert np.abs(z - z_star).max() <= 2e-8
        assert np.all(z >= lo) and np.all(z <= hi)
        q = q0 + np.cumsum(z)  # summed in another order than the solver's clamp: rounding
        assert np.all(q >= -1e-12 * q_max) and np.all(q <= q_max * (1.0 + 1e-12))


def test_stated_iteration_count_is_the_one_measured(cases) -> None:
    """`ITERATIONS_MEASURED` reaches 1e-8 on every instance, one fewer does not (the stated
    count is the measured one), and `IPM_ITERATIONS` keeps a margin over it."""

    def worst(iterations: int) -> float:
        return max(_error(c, _solve(c, iterations), z) for c, z in cases)

    assert worst(qp.ITERATIONS_MEASURED) <= 1e-8
    assert worst(qp.ITERATIONS_MEASURED - 1) > 1e-8
    assert qp.IPM_ITERATIONS >= qp.ITERATIONS_MEASURED + 2


def test_equals_slsqp(cases) -> None:
    """Within 1e-6 in units of the largest move limit (SLSQP's own accuracy is about 1e-8 of it:
    the scaled problem it solves has moves of at most 1)."""
    for case, _ in cases[::3]:
        assert _error(case, _solve(case), _slsqp(*case)) <= 1e-6


def test_horizon_one_is_the_clamp() -> None:
    for h, f, lo, hi, q0, q_max in instances(1, 200, 7):
        z = _solve((h, f, lo, hi, q0, q_max))
        closed = qp.horizon1_move(h[0, 0], f[0], lo[0], hi[0], q0, q_max)
        assert abs(z[0] - closed) <= 1e-9 * (1.0 + abs(closed))
        assert z[0] == pytest.approx(exact(h, f, lo, hi, q0, q_max)[0], abs=1e-9)
