"""Fixed-step integration helpers for the compiled closed loops (numba, inline="always",
branch-free: callable in a vectorized loop body).

- Classic RK4 (Kutta 1901): stage points x + c k with c = 0, h/2, h/2, h and the update
  x + h/6 (k1 + 2 k2 + 2 k3 + k4).
- Kutta's third-order method (RK3): k1 = f(x), k2 = f(x + h/2 k1), k3 = f(x - h k1 + 2 h k2),
  x + h/6 (k1 + 4 k2 + k3), written with explicit fused multiply-adds (`_branchfree.fma`).
- The stage points and updates take floats or, element by element, tuples of floats (a whole
  state in one call, `_branchfree.add`/`mul`/`fmadd`: the same operations in the same order).
- Exact quadrature over one step of length h of a signal linear between its step-end values
  a and b: the trapezoid h (a + b) / 2, and the error integrals IAE, ITAE and ISE of e linear
  from a (at time t) to b (at t + h), exact also when e changes sign inside the step.
- Linear location of a threshold crossing inside the last step.
"""

from __future__ import annotations

from numba import njit

from chassistune._branchfree import add, fma, fmadd, mul, select

SIXTH = 1.0 / 6.0
THIRD = 1.0 / 3.0


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def rk4_point(x, c, k):
    """Stage point x + c k."""
    return add(x, mul(c, k))


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def rk4_update(x, h6, k1, k2, k3, k4):
    """RK4 update x + h/6 (k1 + 2 k2 + 2 k3 + k4), with h6 = h / 6."""
    return add(x, mul(h6, add(add(add(k1, mul(2.0, k2)), mul(2.0, k3)), k4)))


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def rk3_point2(x, hs, k1):
    """Second stage point x + h/2 k1 (hs = h / 2), fused."""
    return fmadd(hs, k1, x)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def rk3_point3(x, neg_h, h2, k1, k2):
    """Third stage point x - h k1 + 2 h k2 (neg_h = -h, h2 = 2 h), fused."""
    return fmadd(h2, k2, fmadd(neg_h, k1, x))


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def rk3_update(x, h6, k1, k2, k3):
    """RK3 update x + h/6 (k1 + 4 k2 + k3), fused (h6 = h / 6)."""
    return fmadd(h6, fmadd(4.0, k2, add(k1, k3)), x)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def trapezoid(a, b, h):
    """Integral over a step of length h of a signal linear from a to b."""
    return 0.5 * h * (a + b)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def error_integrals(a, b, t, h):
    """Integrals over [t, t + h] of |e|, t |e| and e^2 for e linear from a to b.

    If e crosses zero (a b < 0) at t + h1, h1 = h |a| / (|a| + |b|), each part is integrated
    on its own; both forms are evaluated and one selected (no branch).
    Constant divisions are products with 1/6 and 1/3, and sums of products fused (`fma`)."""
    aa = abs(a)
    bb = abs(b)
    same_sign = a * b >= 0.0
    iae_same = 0.5 * h * (aa + bb)
    itae_same = fma(t, iae_same, h * h * fma(aa, SIXTH, bb * THIRD))
    h1 = h * aa / (aa + bb)
    h2 = h - h1
    iae_cross = 0.5 * fma(aa, h1, bb * h2)
    itae_cross = fma(aa, h1 * fma(0.5, t, h1 * SIXTH), bb * h2 * fma(0.5, t + h1, h2 * THIRD))
    ise = h * fma(a, a, fma(a, b, b * b)) * THIRD
    return select(same_sign, iae_same, iae_cross), select(same_sign, itae_same, itae_cross), ise


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def crossing_fraction(x0, x1, level, crossed):
    """Fraction of the step at which x, linear from x0 to x1, reaches `level` (1 if not crossed)."""
    return select(crossed, (x0 - level) / (x0 - x1), 1.0)
