"""Exact stationary RMS of the quarter car from the Lyapunov equation, batched (design.md 3.4, 5).

For the linear closed loop x' = A x + b w with white noise of intensity W (W = 1/2 for the ISO
road, design.md 3.4) the stationary covariance P solves

    A P + P A^T + W b b^T = 0                                                  (1)

and the RMS of an output y = c x is sqrt(c P c^T). Eq. (1) is solved per candidate as a linear
system in the m (m + 1) / 2 unknowns of the symmetric P (21 for m = 6) by Gaussian elimination with
partial pivoting, inside one compiled loop over the candidates. The same factorization solves
A X + X A^T + I = 0, whose solution is positive definite if and only if A is Hurwitz (Lyapunov's
theorem): that is the stability test, so unstable loops get the penalty without an eigenvalue
solver. `rms-ratio-exact` is the iabc-suspension paper's eq. 10 on these RMS values.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from chassistune.layout import Layout, Slot
from chassistune.plants.iso_roads import NOISE_INTENSITY
from chassistune.plants.quarter_car import (
    MAX_STATES,
    N_OUT,
    OUT_ACC,
    OUT_FORCE,
    OUT_TIRE,
    OUT_TRAVEL,
    closed_loop,
)
from chassistune.sim.quarter_car_kernel import RMS_SLOTS

W_ROAD = NOISE_INTENSITY
"""Intensity of the road's white noise: W = 1/2, one-sided PSD 1 (design.md 3.4)."""

EXACT = Layout(
    "quarter-car exact stationary results",
    (*RMS_SLOTS, Slot("stable", "-", "1 if the closed loop is Hurwitz")),
)
"""Columns of exact_rms_batch's output: the simulation's RMS columns, then the stability flag."""
E_ACC, E_TRAVEL, E_TIRE, E_FORCE, E_STABLE = (EXACT[n] for n in EXACT.names)
N_EXACT = len(EXACT)

_PIVOT_TOL = 1e-14
_PD_TOL = 1e-13


@njit(cache=True, nogil=True)
def _sym_index(m: int) -> np.ndarray:
    """idx[k, l]: position of P[k, l] (= P[l, k]) among the upper-triangle unknowns."""
    idx = np.empty((m, m), dtype=np.int64)
    r = 0
    for k in range(m):
        for l in range(k, m):
            idx[k, l] = r
            idx[l, k] = r
            r += 1
    return idx


@njit(cache=True, nogil=True)
def solve_lyapunov(
    a: np.ndarray, m: int, b: np.ndarray, w: float, p: np.ndarray, x: np.ndarray
) -> bool:
    """Solve eq. (1) for P (into p[:m, :m]) and A X + X A^T + I = 0 (into x[:m, :m]).

    Returns True when A[:m, :m] is Hurwitz (X positive definite). When the linear system is
    singular (eigenvalues with l_i + l_j = 0, which a Hurwitz matrix never has) it returns False
    and leaves p and x undefined.
    """
    s = m * (m + 1) // 2
    idx = _sym_index(m)
    mat = np.zeros((s, s))
    rhs = np.zeros((s, 2))
    for i in range(m):
        for j in range(i, m):
            r = idx[i, j]
            for k in range(m):
                mat[r, idx[k, j]] += a[i, k]
                mat[r, idx[i, k]] += a[j, k]
            rhs[r, 0] = -w * b[i] * b[j]
            rhs[r, 1] = -1.0 if i == j else 0.0
    scale = 0.0
    for r in range(s):
        for q in range(s):
            scale = max(scale, abs(mat[r, q]))
    # LU with partial pivoting applied to both right-hand sides
    for col in range(s):
        piv = col
        best = abs(mat[col, col])
        for r in range(col + 1, s):
            v = abs(mat[r, col])
            if v > best:
                best = v
                piv = r
        if not best > _PIVOT_TOL * scale:
            return False
        if piv != col:
            for q in range(col, s):
                t = mat[col, q]
                mat[col, q] = mat[piv, q]
                mat[piv, q] = t
            for q in range(2):
                t = rhs[col, q]
                rhs[col, q] = rhs[piv, q]
                rhs[piv, q] = t
        inv = 1.0 / mat[col, col]
        for r in range(col + 1, s):
            f = mat[r, col] * inv
            if f != 0.0:
                for q in range(col + 1, s):
                    mat[r, q] -= f * mat[col, q]
                rhs[r, 0] -= f * rhs[col, 0]
                rhs[r, 1] -= f * rhs[col, 1]
    for r in range(s - 1, -1, -1):
        for q in range(2):
            acc = rhs[r, q]
            for c in range(r + 1, s):
                acc -= mat[r, c] * rhs[c, q]
            rhs[r, q] = acc / mat[r, r]
    for k in range(m):
        for l in range(m):
            p[k, l] = rhs[idx[k, l], 0]
            x[k, l] = rhs[idx[k, l], 1]
    return _positive_definite(x, m)


@njit(cache=True, nogil=True)
def _positive_definite(x: np.ndarray, m: int) -> bool:
    """Cholesky test of x[:m, :m] with pivots above _PD_TOL times the largest diagonal entry."""
    top = 0.0
    for i in range(m):
        top = max(top, x[i, i])
    if not top > 0.0:
        return False
    low = np.zeros((m, m))
    for j in range(m):
        d = x[j, j]
        for k in range(j):
            d -= low[j, k] * low[j, k]
        if not d > _PD_TOL * top:
            return False
        low[j, j] = np.sqrt(d)
        for i in range(j + 1, m):
            v = x[i, j]
            for k in range(j):
                v -= low[i, k] * low[j, k]
            low[i, j] = v / low[j, j]
    return True


@njit(cache=True, nogil=True)
def _quadratic(c: np.ndarray, p: np.ndarray, m: int) -> float:
    acc = 0.0
    for i in range(m):
        for j in range(m):
            acc += c[i] * p[i, j] * c[j]
    return acc


@njit(cache=True, nogil=True)
def exact_rms_batch(
    plant: np.ndarray,
    feedback: int,
    n_filter: float,
    gains: np.ndarray,
    w: float,
    out: np.ndarray,
) -> None:
    """Stationary RMS of each candidate's minimal closed loop into out (n, N_EXACT).

    gains: (n, 3) rows (kp, ki, kd) of the PID form. Unstable rows get NaN RMS and
    out[i, E_STABLE] = 0.
    """
    a = np.zeros((MAX_STATES, MAX_STATES))
    b = np.zeros(MAX_STATES)
    c = np.zeros((N_OUT, MAX_STATES))
    p = np.zeros((MAX_STATES, MAX_STATES))
    x = np.zeros((MAX_STATES, MAX_STATES))
    cols = (OUT_ACC, OUT_TRAVEL, OUT_TIRE, OUT_FORCE)
    for i in range(gains.shape[0]):
        out[i, :] = np.nan
        out[i, E_STABLE] = 0.0
        m = closed_loop(
            plant, feedback, gains[i, 0], gains[i, 1], gains[i, 2], n_filter, False, a, b, c
        )
        if m < 0:
            continue
        if not solve_lyapunov(a, m, b, w, p, x):
            continue
        out[i, E_STABLE] = 1.0
        for q in range(4):
            out[i, q] = np.sqrt(max(_quadratic(c[cols[q]], p, m), 0.0))


def exact_rms(
    plant: np.ndarray, feedback: int, n_filter: float, gains: np.ndarray, w: float = W_ROAD
) -> np.ndarray:
    """(n, N_EXACT) array: exact RMS of body acc., travel, tire deflection, force; stable flag."""
    g = np.ascontiguousarray(np.asarray(gains, dtype=np.float64).reshape(-1, 3))
    out = np.empty((g.shape[0], N_EXACT))
    exact_rms_batch(
        np.ascontiguousarray(plant, dtype=np.float64),
        int(feedback),
        float(n_filter),
        g,
        float(w),
        out,
    )
    return out


def rms_ratio(
    active: np.ndarray, passive: np.ndarray, usable: np.ndarray, penalty: float
) -> np.ndarray:
    """iabc-suspension eq. 10: Q = sum of active/passive RMS (acc, travel, tire), or the penalty.

    active: (n, >= 3), passive: (3,), usable: (n,) bool. Finite values are clipped below penalty.
    """
    q = np.sum(active[:, :3] / np.asarray(passive)[:3], axis=1)
    ok = usable & np.isfinite(q)
    return np.where(ok, np.minimum(np.where(ok, q, penalty), penalty), penalty)
