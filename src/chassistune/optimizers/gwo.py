"""Grey wolf optimizer (Mirjalili, Mirjalili & Lewis 2014).

a = 2 - 2 t/T; for each leader L in (alpha, beta, delta): A = 2 a r1 - a, C = 2 r2 (per wolf and
dimension), X_L = L - A |C L - X|; the wolf moves to the mean of the three (eqs. 3.1-3.7). No greedy
selection. The leaders are the three best points found so far: after each batch the three best of
(leaders + batch) (the reference code updates alpha, beta and delta without demoting an old alpha
to beta: we keep the plain "three best so far").

Draw order per iteration: for alpha, beta, delta in turn: r1 `random((N, D))`, r2 `random((N, D))`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from chassistune.optimizers.base import Hyperparameters, Optimizer, Steps


@dataclass(frozen=True)
class GWOHyper(Hyperparameters):
    """GWO hyperparameters."""

    a0: float = 2.0  # a decreases linearly from a0 to 0

    def __post_init__(self) -> None:
        self.check(self.a0 > 0, "a0", f"expected > 0, got {self.a0}")


class GWO(Optimizer):
    """Grey wolf optimizer."""

    name = "gwo"
    description = "Grey wolf optimizer, a = 2 - 2t/T (Mirjalili 2014)"
    min_pop = 3
    defaults = GWOHyper()
    hyper: GWOHyper

    def _steps(self) -> Steps:
        rng, n, d = self.rng, self.pop_size, self.dim
        x = self.uniform(n)
        f = yield x
        top = np.argsort(f, kind="stable")[:3]
        lead_x, lead_f = x[top].copy(), f[top].copy()
        for t in self.iterations():
            a = self.hyper.a0 * (1.0 - t / self.T)
            new = np.zeros((n, d))
            for leader in lead_x:  # three leaders: a fixed loop, vectorized over the pack
                big_a = 2.0 * a * rng.random((n, d)) - a
                big_c = 2.0 * rng.random((n, d))
                new += leader - big_a * np.abs(big_c * leader - x)
            x = new / 3.0
            f = yield x
            pool_x = np.concatenate([lead_x, x])
            pool_f = np.concatenate([lead_f, f])
            top = np.argsort(pool_f, kind="stable")[:3]
            lead_x, lead_f = pool_x[top].copy(), pool_f[top].copy()
