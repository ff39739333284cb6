"""Sobol indices against the Ishigami function's analytic values."""

from __future__ import annotations

import math

import numpy as np
import pytest

from chassistune.tuning.robust.sensitivity import sobol_sensitivity
from chassistune.tuning.robust.spec import ParamRange, UncertainParam

A, B = 7.0, 0.1


def ishigami(x: np.ndarray) -> np.ndarray:
    return np.sin(x[:, 0]) + A * np.sin(x[:, 1]) ** 2 + B * x[:, 2] ** 4 * np.sin(x[:, 0])


def analytic() -> tuple[np.ndarray, np.ndarray]:
    """Ishigami & Homma (1990): V = a^2/8 + b pi^4/5 + b^2 pi^8/18 + 1/2, V1 = (1 + b pi^4/5)^2/2,
    V2 = a^2/8, V3 = 0, V13 = 8 b^2 pi^8/225 (Saltelli et al. 2010)."""
    v = A**2 / 8 + B * math.pi**4 / 5 + B**2 * math.pi**8 / 18 + 0.5
    v1 = 0.5 * (1 + B * math.pi**4 / 5) ** 2
    v13 = 8 * B**2 * math.pi**8 / 225
    return np.array([v1, A**2 / 8, 0.0]) / v, np.array([v1 + v13, A**2 / 8, v13]) / v


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_ishigami_indices_within_0_02(seed):
    params = [UncertainParam(f"x{i}", "uniform", lo=-math.pi, hi=math.pi) for i in range(3)]
    res = sobol_sensitivity(ishigami, params, 4096, np.random.default_rng(seed))
    s1, st = analytic()
    assert np.max(np.abs(res.first_order - s1)) < 0.02
    assert np.max(np.abs(res.total - st)) < 0.02
    assert res.names == ("x0", "x1", "x2") and res.evaluations == 4096 * 5
    assert [r["parameter"] for r in res.rows()] == ["x0", "x1", "x2"]


def test_a_normal_input_is_seen_through_its_clipped_distribution():
    # f = x: all variance from x; a second parameter that does nothing has index 0
    params = [
        UncertainParam("x", "normal", mean=1.0, sd=0.2, valid=ParamRange(0.0, math.inf)),
        UncertainParam("y", "uniform", lo=0.0, hi=1.0),
    ]
    res = sobol_sensitivity(lambda v: v[:, 0] ** 2, params, 1024, np.random.default_rng(5))
    assert res.first_order[0] == pytest.approx(1.0, abs=0.02)
    assert res.total[0] == pytest.approx(1.0, abs=0.02)
    assert abs(res.first_order[1]) < 0.02 and abs(res.total[1]) < 0.02
