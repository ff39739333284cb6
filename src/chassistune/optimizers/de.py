"""Differential evolution DE/rand/1/bin (Storn & Price 1997).

v = x_r0 + F (x_r1 - x_r2) with r0, r1, r2 distinct and != i, binomial crossover with a forced gene
j_rand, greedy selection accepting ties (Storn & Price's `<=`). F = 0.5, CR = 0.9.
The same operators serve DERLSP-AO's DE step (derlsp-ao-abs eqs. 32-34), see `_operators`.

Draw order per generation: partners (`_operators.partners`, k = 3), then `binomial_crossover`.
"""

from __future__ import annotations

from dataclasses import dataclass

from chassistune.optimizers._operators import binomial_crossover, greedy, partners
from chassistune.optimizers.base import Hyperparameters, Optimizer, Steps


@dataclass(frozen=True)
class DEHyper(Hyperparameters):
    """DE/rand/1/bin hyperparameters."""

    F: float = 0.5
    CR: float = 0.9

    def __post_init__(self) -> None:
        check_rates(self, "F", "CR")


def check_rates(hyper: Hyperparameters, f_field: str, cr_field: str) -> None:
    """Refuse a DE scale factor F outside (0, 2] or a crossover rate CR outside [0, 1], held in
    the fields `f_field` and `cr_field` of `hyper` (the errors name those fields)."""
    f, cr = getattr(hyper, f_field), getattr(hyper, cr_field)
    hyper.check(0 < f <= 2, f_field, f"expected 0 < F <= 2, got {f}")
    hyper.check(0 <= cr <= 1, cr_field, f"expected 0 <= CR <= 1, got {cr}")


class DE(Optimizer):
    """DE/rand/1/bin."""

    name = "de"
    description = "Differential evolution DE/rand/1/bin, F = 0.5, CR = 0.9 (Storn & Price 1997)"
    min_pop = 4
    defaults = DEHyper()
    hyper: DEHyper

    def _steps(self) -> Steps:
        h, rng, n = self.hyper, self.rng, self.pop_size
        x = self.uniform(n)
        f = (yield x).copy()
        for _ in self.iterations():
            p = partners(rng, n, 3)
            v = x[p[:, 0]] + h.F * (x[p[:, 1]] - x[p[:, 2]])
            u = binomial_crossover(rng, x, v, h.CR)
            f_u = yield u
            greedy(x, f, u, f_u, ties=True)
