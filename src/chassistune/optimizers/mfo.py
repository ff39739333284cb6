"""Moth-flame optimization (Mirjalili 2015).

Flames are the N best points found so far, sorted (the best N of previous flames and current
moths). Moth i spirals around flame min(i, flame_no) (moths beyond the flame count follow the last
flame): x = |F - x| e^(b s) cos(2 pi s) + F with s = (a - 1) rand + 1, a = -1 - t/T, b = 1
(eq. 3.12); flame_no = round(N - t (N - 1)/T) (eq. 3.14, rounded half up as MATLAB does).
No greedy selection: the moths move, the flames remember.

Draw order per iteration: s's rand `random((N, D))`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from chassistune.optimizers.base import Hyperparameters, Optimizer, Steps


@dataclass(frozen=True)
class MFOHyper(Hyperparameters):
    """MFO hyperparameters."""

    b: float = 1.0  # spiral shape

    def __post_init__(self) -> None:
        self.check(self.b > 0, "b", f"expected > 0, got {self.b}")


class MFO(Optimizer):
    """Moth-flame optimization."""

    name = "mfo"
    description = "Moth-flame optimization, b = 1 (Mirjalili 2015)"
    min_pop = 2
    defaults = MFOHyper()
    hyper: MFOHyper

    def _steps(self) -> Steps:
        rng, n, d, b = self.rng, self.pop_size, self.dim, self.hyper.b
        x = self.uniform(n)
        f = yield x
        order = np.argsort(f, kind="stable")
        flames, flame_f = x[order].copy(), f[order].copy()
        rows = np.arange(n)
        for t in self.iterations():
            flame_no = math.floor(n - t * (n - 1) / self.T + 0.5)
            a = -1.0 - t / self.T
            s = (a - 1.0) * rng.random((n, d)) + 1.0
            target = flames[np.minimum(rows, flame_no - 1)]
            x = np.abs(target - x) * np.exp(b * s) * np.cos(2.0 * np.pi * s) + target
            f = yield x
            pool_x = np.concatenate([flames, x])
            pool_f = np.concatenate([flame_f, f])
            order = np.argsort(pool_f, kind="stable")[:n]
            flames, flame_f = pool_x[order], pool_f[order]
