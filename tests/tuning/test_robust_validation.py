"""Validation pass rate and the zero-failure certificate."""

from __future__ import annotations

import math

import numpy as np
import pytest

from chassistune.tuning.robust.spec import PassCriterion
from chassistune.tuning.robust.validation import (
    certified_eps,
    failure_upper_bound,
    required_draws,
    validate_draws,
)


@pytest.mark.parametrize(
    ("eps", "beta", "n"),
    [
        (0.01, 0.05, 300),
        (0.05, 0.05, 60),
        (0.01, 0.01, 461),
        (0.001, 0.05, 2996),
        (0.1, 0.1, 24),
    ],
)
def test_required_draws_is_the_smallest_n_with_n_eps_at_least_ln_1_over_beta(eps, beta, n):
    assert required_draws(eps, beta) == n
    assert n * eps >= math.log(1 / beta) > (n - 1) * eps
    # the certificate of n failure-free draws is at least as strong as asked
    assert certified_eps(n, beta) <= eps
    # and what it guarantees: (1 - eps)^n <= exp(-eps n) <= beta
    assert (1 - eps) ** n <= math.exp(-eps * n) <= beta


def test_certified_eps_formula_and_the_exact_zero_failure_bound():
    assert certified_eps(300, 0.05) == pytest.approx(math.log(20) / 300, rel=1e-15)
    assert certified_eps(300, 0.05) < 0.01
    for n in (10, 300, 5000):
        exact = failure_upper_bound(n, 0, 0.05)
        assert exact == pytest.approx(1 - 0.05 ** (1 / n), rel=1e-9)
        assert exact <= certified_eps(n, 0.05)  # 1 - beta^(1/N) <= ln(1/beta)/N
        assert (1 - exact) ** n == pytest.approx(0.05, rel=1e-9)


def _metrics(n, ratio, stopped=True, lock=np.nan):
    return {
        "stopped": np.full(n, stopped),
        "wheel_lock_time_s": np.full(n, lock),
        "distance_ratio": np.asarray(ratio, dtype=float),
    }


def test_all_pass_gives_the_certificate():
    res = validate_draws(_metrics(300, np.full(300, 1.05)), np.zeros(300), PassCriterion(), 0.05)
    assert (res.n, res.failures, res.pass_rate) == (300, 0, 1.0)
    assert res.certificate is not None
    assert res.certificate.eps == certified_eps(300, 0.05)
    d = res.as_dict()
    assert d["certificate"] == {"eps": certified_eps(300, 0.05), "beta": 0.05}
    assert d["worst_distance_ratio"] == 1.05
    assert str(res.certificate) == (
        "failure probability <= 0.999 % with confidence 95 % (300 draws, none failed)"
    )


def test_failures_give_a_pass_rate_and_no_certificate():
    ratio = np.full(300, 1.05)
    ratio[[3, 70]] = 1.2  # too long
    m = _metrics(300, ratio)
    m["stopped"][5] = False
    m["wheel_lock_time_s"][9] = 0.7
    res = validate_draws(m, np.zeros(300), PassCriterion(), 0.05)
    assert res.failures == 4
    assert res.pass_rate == 296 / 300
    assert res.certificate is None
    d = res.as_dict()
    assert d["certificate"] is None and d["failures"] == 4
    assert d["failure_upper_bound"] > 4 / 300
    # the criterion is configurable: allowing locks and 1.25 x the bound leaves one failure
    loose = PassCriterion(allow_lock=True, max_distance_ratio=1.25)
    assert validate_draws(m, np.zeros(300), loose, 0.05).failures == 1


def test_the_cost_test_serves_plants_without_a_stop():
    crit = PassCriterion(require_stop=False, allow_lock=True, max_distance_ratio=0.0, max_cost=1.0)
    res = validate_draws({}, np.array([0.9, 0.99, 1.01, 1e9]), crit, 0.05)
    assert res.failures == 2
    assert res.as_dict()["worst_cost"] == 1e9 and "worst_distance_ratio" not in res.as_dict()
