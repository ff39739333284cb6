"""Particle swarm optimization, global best (Kennedy & Eberhart 1995; Clerc's constriction values).

v = w v + c1 r1 (pbest - x) + c2 r2 (gbest - x), w = 0.729, c1 = c2 = 1.49445, each velocity
component limited to `vmax_fraction` (20 %) of its range; x = x + v, repaired by the base (the
velocity is kept); personal and global bests updated on strict improvement. Velocities start at 0.

Draw order per iteration: r1 `random((N, D))`, r2 `random((N, D))`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from chassistune.optimizers.base import Hyperparameters, Optimizer, Steps


@dataclass(frozen=True)
class PSOHyper(Hyperparameters):
    """PSO hyperparameters."""

    w: float = 0.729
    c1: float = 1.49445
    c2: float = 1.49445
    vmax_fraction: float = 0.2

    def __post_init__(self) -> None:
        self.check(self.w >= 0, "w", f"expected >= 0, got {self.w}")
        self.check(
            self.c1 >= 0 and self.c2 >= 0, "c1/c2", f"expected >= 0, got {self.c1}, {self.c2}"
        )
        self.check(
            self.vmax_fraction > 0, "vmax_fraction", f"expected > 0, got {self.vmax_fraction}"
        )


class PSO(Optimizer):
    """Global-best PSO with inertia weight and velocity clamping."""

    name = "pso"
    description = "Particle swarm, w = 0.729, c1 = c2 = 1.49445, vmax 20 % of the range"
    min_pop = 2
    defaults = PSOHyper()
    hyper: PSOHyper

    def _steps(self) -> Steps:
        h, rng = self.hyper, self.rng
        n, d = self.pop_size, self.dim
        vmax = h.vmax_fraction * (self.hi - self.lo)
        x = self.uniform(n)
        f = (yield x).copy()
        pbest, pf = x.copy(), f.copy()
        v = np.zeros((n, d))
        for _ in self.iterations():
            g = pbest[int(np.argmin(pf))]
            r1 = rng.random((n, d))
            r2 = rng.random((n, d))
            v = h.w * v + h.c1 * r1 * (pbest - x) + h.c2 * r2 * (g - x)
            np.clip(v, -vmax, vmax, out=v)
            x = x + v
            f = yield x
            better = f < pf
            pbest[better], pf[better] = x[better], f[better]
