"""Pelican optimization algorithm (Trojovsky & Dehghani 2022).

Phase 1 (exploration, eq. 4): one prey per iteration, a random member (as the authors' code does;
the paper's text calls it a random point of the space); pelican i moves towards it,
x + rand (p - I x) with I in {1, 2}, when the prey is better, else away, x + rand (x - p);
greedy (ties accepted, as in the authors' code). Phase 2 (exploitation, eq. 6): local search
x + R (1 - t/T) (2 rand - 1) x with R = 0.2, rand per dimension; greedy.
2N evaluations per iteration.

Draw order per iteration: prey `integers(0, N)`, I `integers(1, 3, N)`, rand `random(N)`;
phase 2: `random((N, D))`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from chassistune.optimizers._operators import greedy
from chassistune.optimizers.base import Hyperparameters, Optimizer, Steps


@dataclass(frozen=True)
class POAHyper(Hyperparameters):
    """POA hyperparameters."""

    R: float = 0.2

    def __post_init__(self) -> None:
        self.check(self.R > 0, "R", f"expected > 0, got {self.R}")


class POA(Optimizer):
    """Pelican optimization algorithm."""

    name = "poa"
    description = "Pelican optimization, R = 0.2 (Trojovsky & Dehghani 2022)"
    min_pop = 2
    defaults = POAHyper()
    hyper: POAHyper

    def evals_per_iteration(self) -> int:
        return 2 * self.pop_size

    def _steps(self) -> Steps:
        rng, n, d = self.rng, self.pop_size, self.dim
        x = self.uniform(n)
        f = (yield x).copy()
        for t in self.iterations():
            k = int(rng.integers(0, n))
            prey, f_prey = x[k].copy(), f[k]
            big_i = rng.integers(1, 3, size=n)[:, None]
            r = rng.random(n)[:, None]
            towards = (f_prey < f)[:, None]
            trial = np.where(towards, x + r * (prey - big_i * x), x + r * (x - prey))  # eq. 4
            f_trial = yield trial
            greedy(x, f, trial, f_trial, ties=True)  # eq. 5
            scale = self.hyper.R * (1.0 - t / self.T)
            trial = x + scale * (2.0 * rng.random((n, d)) - 1.0) * x  # eq. 6
            f_trial = yield trial
            greedy(x, f, trial, f_trial, ties=True)  # eq. 7
