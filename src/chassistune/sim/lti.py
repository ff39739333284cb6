"""Small dense linear-system helpers for compiled kernels: matrix exponential, exact discretization.

`expm_small` is scaling and squaring with a degree-16 Taylor polynomial (||M / 2^s||_1 <= 1/2, so
the truncation error is below 1e-19 relative); it is meant for matrices of order < 10.
`discretize_zoh` gives the exact step of x' = A x + b w with w held over the step:

    [[Phi, gamma], [0, 1]] = expm([[A, b], [0, 0]] dt)   (Van Loan)
"""

from __future__ import annotations

import numpy as np
from numba import njit

_TAYLOR_DEGREE = 16


@njit(cache=True, nogil=True)
def _matmul(x: np.ndarray, y: np.ndarray, out: np.ndarray) -> None:
    """out = x @ y with plain loops (faster than a BLAS call at these sizes)."""
    n = x.shape[0]
    for i in range(n):
        for j in range(n):
            acc = 0.0
            for k in range(n):
                acc += x[i, k] * y[k, j]
            out[i, j] = acc


@njit(cache=True, nogil=True)
def expm_small(mat: np.ndarray, out: np.ndarray) -> None:
    """out = exp(mat) for a small square matrix (scaling and squaring, Taylor degree 16)."""
    n = mat.shape[0]
    norm = 0.0
    for j in range(n):
        col = 0.0
        for i in range(n):
            col += abs(mat[i, j])
        norm = max(norm, col)
    s = 0
    while norm > 0.5:
        norm *= 0.5
        s += 1
    scaled = mat * (0.5**s)
    term = np.eye(n)
    tmp = np.empty((n, n))
    # Horner: T = I + M/k T for k = degree..1
    for k in range(_TAYLOR_DEGREE, 0, -1):
        _matmul(scaled, term, tmp)
        term[:, :] = tmp / k
        for i in range(n):
            term[i, i] += 1.0
    for _ in range(s):
        _matmul(term, term, tmp)
        term[:, :] = tmp
    out[:, :] = term


@njit(cache=True, nogil=True)
def discretize_zoh(
    a: np.ndarray, b: np.ndarray, m: int, dt: float, phi: np.ndarray, gam: np.ndarray
) -> None:
    """phi[:m, :m] = exp(A dt), gam[:m] = int_0^dt exp(A s) ds b, for A = a[:m, :m], b = b[:m]."""
    aug = np.zeros((m + 1, m + 1))
    aug[:m, :m] = a[:m, :m] * dt
    aug[:m, m] = b[:m] * dt
    e = np.empty((m + 1, m + 1))
    expm_small(aug, e)
    phi[:m, :m] = e[:m, :m]
    gam[:m] = e[:m, m]
