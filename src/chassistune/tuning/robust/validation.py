"""Validation of a tuned controller on N fresh Monte Carlo draws, and its certificate.

The bound (zero-failure binomial bound; Tempo, Bai & Dabbene, "Probabilistic robustness
analysis: explicit bounds for the minimum number of samples", Systems & Control Letters 30,
1997; Tempo, Calafiore & Dabbene, "Randomized Algorithms for Analysis and Control of Uncertain
Systems", Springer 2005; its beta = 0.05 case is the "rule of three", 3/N): draws are
i.i.d. from the uncertainty distribution and independent of the controller (a fresh set, its own
seed, drawn after tuning). If the failure probability p exceeded eps, then

    P(no failure in N draws) = (1 - p)^N < (1 - eps)^N <= exp(-eps N) <= beta
    whenever N >= ln(1/beta) / eps.

So N draws without a failure certify "p <= eps = ln(1/beta)/N with confidence 1 - beta"
(300 draws: 1 % at 95 %). The exact zero-failure bound 1 - beta^(1/N) (Clopper-Pearson) is a
little smaller and is reported beside it; with failures, the Clopper-Pearson upper bound at
confidence 1 - beta is reported and no certificate is given.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import stats

from chassistune.errors import InputError
from chassistune.tuning.robust.spec import PassCriterion


def certified_eps(n: int, beta: float) -> float:
    """eps = ln(1/beta) / N: what N failure-free draws certify at confidence 1 - beta."""
    return math.log(1.0 / beta) / n


def required_draws(eps: float, beta: float) -> int:
    """The smallest N with N >= ln(1/beta) / eps (300 for eps = 0.01, beta = 0.05)."""
    return math.ceil(math.log(1.0 / beta) / eps * (1.0 - 1e-12))


def failure_upper_bound(n: int, failures: int, beta: float) -> float:
    """One-sided Clopper-Pearson upper bound on p at confidence 1 - beta (1 - beta^(1/N) when
    no draw failed)."""
    if failures >= n:
        return 1.0
    return float(stats.beta.ppf(1.0 - beta, failures + 1, n - failures))


@dataclass(frozen=True)
class Certificate:
    """The certificate "failure probability <= eps with confidence 1 - beta" from n failure-free
    draws."""

    n: int
    eps: float
    beta: float

    def __str__(self) -> str:
        return (
            f"failure probability <= {100 * self.eps:.3g} % with confidence "
            f"{100 * (1 - self.beta):.3g} % ({self.n} draws, none failed)"
        )


@dataclass(frozen=True)
class ValidationResult:
    """Pass/fail of each draw, the pass rate, and the certificate when no draw failed."""

    passed: np.ndarray
    beta: float
    distance_ratio: np.ndarray | None = None
    cost: np.ndarray | None = None
    """The objective of each draw, when the criterion tests it (`max_cost`)."""

    @property
    def n(self) -> int:
        return int(self.passed.size)

    @property
    def failures(self) -> int:
        return int(self.n - np.count_nonzero(self.passed))

    @property
    def pass_rate(self) -> float:
        return float(np.count_nonzero(self.passed) / self.n)

    @property
    def certificate(self) -> Certificate | None:
        if self.failures:
            return None
        return Certificate(self.n, certified_eps(self.n, self.beta), self.beta)

    def as_dict(self) -> dict[str, Any]:
        """The `validation` object of `tune --json` and the study store."""
        cert = self.certificate
        out: dict[str, Any] = {
            "n": self.n,
            "failures": self.failures,
            "pass_rate": self.pass_rate,
            "beta": self.beta,
            "failure_upper_bound": failure_upper_bound(self.n, self.failures, self.beta),
            "certificate": None if cert is None else {"eps": cert.eps, "beta": cert.beta},
        }
        if self.distance_ratio is not None:
            out["worst_distance_ratio"] = float(np.max(self.distance_ratio))
            out["mean_distance_ratio"] = float(np.mean(self.distance_ratio))
        if self.cost is not None:
            out["worst_cost"] = float(np.max(self.cost))
            out["mean_cost"] = float(np.mean(self.cost))
        return out


def _metric(metrics: Mapping[str, np.ndarray], name: str, test: str) -> np.ndarray:
    if name not in metrics:
        raise InputError(
            f"pass.{test}", f"the plant reports no {name!r} metric: switch this test off"
        )
    return np.asarray(metrics[name])


def passes(
    metrics: Mapping[str, np.ndarray], cost: np.ndarray, criterion: PassCriterion
) -> np.ndarray:
    """Boolean pass mask of N draws from their metrics (arrays of length N) and costs."""
    ok = np.ones(np.asarray(cost).shape[0], dtype=bool)
    if criterion.require_stop:
        ok &= _metric(metrics, "stopped", "require_stop").astype(bool)
    if not criterion.allow_lock:  # the lock time is NaN when the wheel never locked above v_stop
        ok &= np.isnan(_metric(metrics, "wheel_lock_time_s", "allow_lock").astype(float))
    if criterion.max_distance_ratio > 0.0:
        ratio = _metric(metrics, "distance_ratio", "max_distance_ratio")
        ok &= ratio <= criterion.max_distance_ratio
    if criterion.max_cost > 0.0:
        ok &= np.asarray(cost) <= criterion.max_cost
    return ok


def validate_draws(
    metrics: Mapping[str, np.ndarray], cost: np.ndarray, criterion: PassCriterion, beta: float
) -> ValidationResult:
    """The validation result of N draws of one controller."""
    ratio = metrics.get("distance_ratio")
    return ValidationResult(
        passes(metrics, cost, criterion),
        beta,
        None if ratio is None else np.asarray(ratio, dtype=float),
        np.asarray(cost, dtype=float) if criterion.max_cost > 0 else None,
    )
