"""Fixed-step integration helpers for the compiled closed loops (numba, inline="always",
branch-free: callable in a vectorized loop body).

- Classic RK4 (Kutta 1901): stage points x + c k with c = 0, h/2, h/2, h and the update
  x + h/6 (k1 + 2 k2 + 2 k3 + k4).
- Exact quadrature over one step of length h of a signal linear between its step-end values
  a and b: the trapezoid h (a + b) / 2, and the error integrals IAE, ITAE and ISE of e linear
  from a (at time t) to b (at t + h), exact also when e changes sign inside the step.
- Linear location of a threshold crossing inside the last step.
"""

from __future__ import annotations

from numba import njit

from chassistune._branchfree import select


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def rk4_point(x, c, k):
    """Stage point x + c k."""
    return x + c * k


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def rk4_update(x, h6, k1, k2, k3, k4):
    """RK4 update x + h/6 (k1 + 2 k2 + 2 k3 + k4), with h6 = h / 6."""
    return x + h6 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def trapezoid(a, b, h):
    """Integral over a step of length h of a signal linear from a to b."""
    return 0.5 * h * (a + b)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def error_integrals(a, b, t, h):
    """Integrals over [t, t + h] of |e|, t |e| and e^2 for e linear from a to b.

    If e crosses zero (a b < 0) at t + h1, h1 = h |a| / (|a| + |b|), each part is integrated
    on its own; both forms are evaluated and one selected (no branch)."""
    aa = abs(a)
    bb = abs(b)
    same_sign = a * b >= 0.0
    iae_same = 0.5 * h * (aa + bb)
    itae_same = t * iae_same + h * h * (aa / 6.0 + bb / 3.0)
    h1 = h * aa / (aa + bb)
    h2 = h - h1
    iae_cross = 0.5 * (aa * h1 + bb * h2)
    itae_cross = aa * (0.5 * t * h1 + h1 * h1 / 6.0) + bb * (0.5 * (t + h1) * h2 + h2 * h2 / 3.0)
    ise = h * (a * a + a * b + b * b) / 3.0
    return select(same_sign, iae_same, iae_cross), select(same_sign, itae_same, itae_cross), ise


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def crossing_fraction(x0, x1, level, crossed):
    """Fraction of the step at which x, linear from x0 to x1, reaches `level` (1 if not crossed)."""
    return select(crossed, (x0 - level) / (x0 - x1), 1.0)
