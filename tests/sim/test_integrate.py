"""Integration helpers: RK3 and RK4 orders, fused multiply-add, exact quadrature."""

from __future__ import annotations

import math

import pytest

from chassistune._branchfree import fma
from chassistune.sim.integrate import (
    error_integrals,
    rk3_point2,
    rk3_point3,
    rk3_update,
    rk4_point,
    rk4_update,
)


def _rk3(h: float, steps: int) -> float:
    x = 1.0
    for _ in range(steps):  # x' = -x
        k1 = -x
        k2 = -rk3_point2(x, 0.5 * h, k1)
        k3 = -rk3_point3(x, -h, 2.0 * h, k1, k2)
        x = rk3_update(x, h / 6.0, k1, k2, k3)
    return x


def _rk4(h: float, steps: int) -> float:
    x = 1.0
    for _ in range(steps):
        k1 = -x
        k2 = -rk4_point(x, 0.5 * h, k1)
        k3 = -rk4_point(x, 0.5 * h, k2)
        k4 = -rk4_point(x, h, k3)
        x = rk4_update(x, h / 6.0, k1, k2, k3, k4)
    return x


@pytest.mark.parametrize(("method", "order"), [(_rk3, 3), (_rk4, 4)])
def test_convergence_order(method, order) -> None:  # type: ignore[no-untyped-def]
    e1 = abs(method(0.1, 10) - math.exp(-1.0))
    e2 = abs(method(0.05, 20) - math.exp(-1.0))
    assert order - 0.2 < math.log2(e1 / e2) < order + 0.2


def test_fma_rounds_once() -> None:
    a, b = 1.0 + 2.0**-30, 1.0 - 2.0**-30
    assert a * b - 1.0 == 0.0  # the product rounds to 1
    assert fma(a, b, -1.0) == -(2.0**-60)


@pytest.mark.parametrize(("a", "b"), [(0.3, 0.1), (0.2, -0.2), (-0.05, 0.15), (0.0, 0.0)])
def test_error_integrals_are_exact_for_linear_errors(a: float, b: float) -> None:
    t, h, n = 2.0, 0.01, 20000
    iae = itae = ise = 0.0
    for i in range(n):  # midpoint rule on a fine grid
        s = (i + 0.5) / n
        e = a + (b - a) * s
        iae += abs(e) * h / n
        itae += (t + s * h) * abs(e) * h / n
        ise += e * e * h / n
    got = error_integrals(a, b, t, h)
    assert got == pytest.approx((iae, itae, ise), rel=1e-6, abs=1e-15)
