"""Aggregates over K scenarios (x R roads): mean, max, CVaR."""

from __future__ import annotations

import math

import numpy as np
import pytest

from chassistune.tuning.robust.aggregate import Aggregate


def test_cvar_is_the_mean_of_the_worst_ceil_alpha_k():
    costs = np.array([[5.0, 1.0, 4.0, 2.0, 3.0], [1.0, 1.0, 1.0, 1.0, 9.0]])
    # ceil(0.3 * 5) = 2 worst: (5 + 4) / 2 and (9 + 1) / 2
    np.testing.assert_array_equal(Aggregate("cvar", 0.3)(costs), [4.5, 5.0])
    np.testing.assert_array_equal(Aggregate("cvar", 0.4)(costs), [4.5, 5.0])
    np.testing.assert_array_equal(Aggregate("cvar", 0.41)(costs), [4.0, 11.0 / 3.0])


@pytest.mark.parametrize("m", [1, 3, 10, 16, 30, 100])
def test_cvar_tail_counts_are_ceil_alpha_m(m):
    for alpha in (0.05, 0.1, 0.2, 0.25, 0.3, 0.5, 1.0):
        expected = max(1, math.ceil(round(alpha * m, 9)))
        assert Aggregate("cvar", alpha).tail_count(m) == expected


def test_cvar_limits_are_the_mean_and_the_max():
    rng = np.random.default_rng(3)
    costs = rng.lognormal(size=(7, 16))
    np.testing.assert_allclose(Aggregate("cvar", 1.0)(costs), Aggregate("mean")(costs), rtol=1e-15)
    np.testing.assert_array_equal(Aggregate("cvar", 1 / 16)(costs), Aggregate("max")(costs))
    assert np.all(Aggregate("cvar", 0.25)(costs) <= Aggregate("max")(costs))
    assert np.all(Aggregate("cvar", 0.25)(costs) >= Aggregate("mean")(costs))


def test_roads_are_more_scenarios():
    rng = np.random.default_rng(4)
    costs = rng.random((5, 8, 3))
    for agg in (Aggregate("mean"), Aggregate("max"), Aggregate("cvar", 0.2)):
        np.testing.assert_array_equal(agg(costs), agg(costs.reshape(5, 24)))
    np.testing.assert_array_equal(Aggregate("max")(costs), costs.max(axis=(1, 2)))
