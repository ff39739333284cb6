"""Real-coded genetic algorithm (our GA-PID setting: no canonical one exists; optimizers_design.md).

Generational with `elites` elites (default 1): tournament selection of size `tournament` = 3
(binary tournaments, `tournament=2`, stall between 1e-6 and 4e-5 on F1 at d = 10 and 50,000
evaluations, because polynomial mutation scaled by the range wrecks most children near the optimum
and binary tournaments let them breed; size 3 reaches about 1e-9), simulated binary crossover
(Deb & Agrawal 1995; eta_c = 15, applied to a pair
with probability `crossover_prob` = 0.9 and to each gene of a crossing pair with probability 0.5),
polynomial mutation (Deb & Goyal 1996; eta_m = 20, probability 1/D per gene), in their basic
unbounded forms followed by the base's clipping. An iteration evaluates N - elites children.

Draw order per generation (m = N - elites children, q = ceil(m / 2) pairs): tournament entrants
`integers(0, N, (2 q, tournament))`; SBX: pair test `random(q)`, gene test `random((q, D))`,
u `random((q, D))`; mutation: gene test `random((m, D))`, u `random((m, D))`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from chassistune.optimizers.base import FloatArray, Hyperparameters, Optimizer, Steps


@dataclass(frozen=True)
class GAHyper(Hyperparameters):
    """Real-coded GA hyperparameters."""

    tournament: int = 3
    crossover_prob: float = 0.9
    eta_c: float = 15.0
    mutation_prob: float | None = None  # None: 1 / D
    eta_m: float = 20.0
    elites: int = 1

    def __post_init__(self) -> None:
        self.check(self.tournament >= 1, "tournament", f"expected >= 1, got {self.tournament}")
        self.check(
            0 <= self.crossover_prob <= 1,
            "crossover_prob",
            f"expected [0, 1], got {self.crossover_prob}",
        )
        self.check(self.eta_c >= 0, "eta_c", f"expected >= 0, got {self.eta_c}")
        self.check(
            self.mutation_prob is None or 0 <= self.mutation_prob <= 1,
            "mutation_prob",
            f"expected [0, 1], got {self.mutation_prob}",
        )
        self.check(self.eta_m >= 0, "eta_m", f"expected >= 0, got {self.eta_m}")
        self.check(self.elites >= 0, "elites", f"expected >= 0, got {self.elites}")


class GA(Optimizer):
    """Real-coded GA: tournament, SBX, polynomial mutation, elitism."""

    name = "ga"
    description = "Real-coded GA: tournament 3, SBX 15, polynomial mutation 20, 1 elite"
    min_pop = 2
    defaults = GAHyper()
    hyper: GAHyper

    def required_pop(self) -> int:
        return max(2, self.hyper.elites + 1)

    def evals_per_iteration(self) -> int:
        return self.pop_size - self.hyper.elites

    def _tournament(self, f: FloatArray, m: int) -> NDArray[np.intp]:
        """m winners of tournaments without replacement (Deb's scheme): the population is
        shuffled, cut into groups of `tournament`, the best of each group wins; repeat as needed."""
        n = f.size
        k = min(self.hyper.tournament, n)  # a population smaller than a tournament: one group
        per_round = n // k
        rounds = -(-m // per_round)
        entrants = np.concatenate([self.rng.permutation(n)[: per_round * k] for _ in range(rounds)])
        groups = entrants.reshape(-1, k)
        won: NDArray[np.intp] = groups[np.arange(groups.shape[0]), np.argmin(f[groups], axis=1)]
        return won[:m]

    def _children(self, x: FloatArray, f: FloatArray) -> FloatArray:
        h, rng = self.hyper, self.rng
        n, d = x.shape
        m = n - h.elites
        q = (m + 1) // 2
        winners = self._tournament(f, 2 * q)
        p1, p2 = x[winners[:q]], x[winners[q:]]
        # SBX
        cross = (rng.random(q) < h.crossover_prob)[:, None] & (rng.random((q, d)) < 0.5)
        u = rng.random((q, d))
        e = 1.0 / (h.eta_c + 1.0)
        beta = np.where(u <= 0.5, (2.0 * u) ** e, (1.0 / (2.0 * (1.0 - u))) ** e)
        c1 = np.where(cross, 0.5 * ((1.0 + beta) * p1 + (1.0 - beta) * p2), p1)
        c2 = np.where(cross, 0.5 * ((1.0 - beta) * p1 + (1.0 + beta) * p2), p2)
        kids = np.concatenate([c1, c2])[:m]
        # polynomial mutation
        pm = h.mutation_prob if h.mutation_prob is not None else 1.0 / d
        mutate = rng.random((m, d)) < pm
        u = rng.random((m, d))
        e = 1.0 / (h.eta_m + 1.0)
        delta = np.where(u < 0.5, (2.0 * u) ** e - 1.0, 1.0 - (2.0 * (1.0 - u)) ** e)
        out: FloatArray = np.where(mutate, kids + delta * (self.hi - self.lo), kids)
        return out

    def _steps(self) -> Steps:
        elites = self.hyper.elites
        x = self.uniform(self.pop_size)
        f = (yield x).copy()
        for _ in self.iterations():
            kids = self._children(x, f)
            f_kids = yield kids
            keep = np.argsort(f, kind="stable")[:elites]
            x = np.concatenate([x[keep], kids])
            f = np.concatenate([f[keep], f_kids])
