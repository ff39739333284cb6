"""The Aquila family: AO, DERLSP-AO and DEFFAO as configurations of one engine.

AO (Abualigah et al. 2021), as written in derlsp-ao-abs section 3.1, eqs. 13-27:
exploration while t <= 2T/3 (eq. 13 expanded exploration or eq. 15 contour flight, by a coin flip
per eagle), exploitation after (eq. 23 low flight or eq. 24 walk-and-grab); greedy one-to-one
selection. Where derlsp-ao-abs and the authors' MATLAB code differ we follow derlsp-ao-abs:

- XM is the population mean per dimension (eq. 14; the code takes the scalar mean of one
  individual, a known slip);
- eq. 13 is printed X1 = Xbest (1 - t/T) + (XM - Xbest rand). The authors' code, mealpy and
  every port we know read it as X1 = Xbest (1 - t/T) + (XM - Xbest) rand, and so do we by default
  (`x1_form="grouped"`): it is the reading that contracts towards the best. Taken as printed
  (`x1_form="printed"`) X1 = Xbest (2 - t/T - rand) near convergence, which does not contract: on
  F1 (d = 30, N = 30, 500 iterations) we measured about 1e-7 printed against 1e-68 grouped. This is
  the one place where we depart from derlsp-ao-abs's printed text, and the choice is a parameter;
- the spiral of eqs. 18-22 uses r = r1 + U D1 with r1 a random integer in [1, 20] drawn per eagle
  and U = 0.00565 (the code fixes r1 = 10 and U = 0.0265);
- Levy(D) is a fresh vector per eagle with Mantegna's normal u (the paper's u1 in (0, 1) is a slip),
  see `_operators.levy`;
- eq. 15's partner XR is any member, the eagle itself included ("a random solution in [1, N]").

Draw order of one AO iteration (fixed; N eagles, D dimensions): QF's rand, G1's rand, the coin
flips `random(N)`; exploration: eq. 13's rand `random(N)`, XR `integers(0, N, N)`, r1
`integers(1, 21, N)`, eq. 15's rand `random(N)`, Levy `(N, D)`; exploitation: eq. 23's two rands
`random(N)` twice, eq. 24's two rands `random(N)` twice, Levy `(N, D)`. Every array is drawn for
all N eagles whichever move each one takes.

DERLSP-AO (derlsp-ao-abs section 3.2) adds three strategies, each switched by a hyperparameter:

1. `lens_opposition` (eqs. 28-29): the lens-imaging opposite of the best,
   X' = (a+b)/2 + (a+b)/(2k) - Xbest/k with a, b the current population's per-dimension minimum and
   maximum and k = (1 + (t/T)^0.5)^10 (or the fixed `lens_k`); eq. 29 uses X' in place of Xbest in
   eq. 13, and X' is evaluated once per iteration (the last row of the AO batch) and replaces the
   best member if better.
2. `stagnation` (eqs. 30-31): after `stagnation_iters` iterations without improvement of the best
   cost, eqs. 15 and 24 give X' and the eagle moves to X = Xbest + n1 Levy(D) + n2 (Xbest - X'),
   n1, n2 standard normal scalars per eagle (draws, after the phase's own: Levy `(N, D)`, n1, n2).
3. `de_step` (eqs. 32-34): a DE/rand/1/bin batch after the AO batch, F = `de_f`, CR = `de_cr`,
   three partners distinct from each other and from i, greedy selection.

An iteration costs N + 1 + N evaluations with all three on.

DEFFAO (deffao-vehicle-abs) names three strategies and gives no equations: THE DESIGN BELOW IS OURS.

1. `free_hunting`: each eagle, with probability `free_prob` (a coin per eagle), hunts on its own
   instead of taking its AO move: it picks a random other eagle k and moves towards it if k is
   better, away from it otherwise, X = X_i + r (X_k - X_i) or X_i + r (X_i - X_k), r ~ U(0, 1)^D.
   No term uses Xbest, which keeps diversity (draws after AO's: coin `random(N)`, k, r `(N, D)`).
2. `nonlinear_factor`: AO's linear factor 1 - t/T in eq. 13 and in G2 = 2 (1 - t/T) (eq. 27) becomes
   c(t) = (1 - t/T)^2: it decays faster early (the contraction towards the best starts sooner) and
   flattens near the end (small, slowly shrinking Levy steps for fine exploitation).
3. `de_elimination`: after the AO batch, the worst ceil(`elim_fraction` N) eagles are challenged
   by DE/best/1/bin trials, v = Xbest + F (X_r1 - X_r2) with binomial crossover (F = `de_f`,
   CR = `de_cr`), and replaced when the trial is better (draws: partners, crossover).

An iteration costs N + ceil(`elim_fraction` N) evaluations with all three on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from chassistune.optimizers._operators import binomial_crossover, greedy, levy, partners
from chassistune.optimizers.base import Hyperparameters, Optimizer, Steps
from chassistune.optimizers.de import check_rates


@dataclass(frozen=True)
class AquilaHyper(Hyperparameters):
    """Hyperparameters of the Aquila family (derlsp-ao-abs eqs. 13-34; DEFFAO's: ours)."""

    alpha: float = 0.1  # eq. 23
    delta: float = 0.1  # eq. 23
    levy_beta: float = 1.5  # eqs. 16-17
    levy_scale: float = 0.01  # s of eq. 16
    spiral_u: float = 0.00565  # U of eq. 20
    spiral_omega: float = 0.005  # omega of eq. 21
    spiral_r1_max: int = 20  # r1 ~ U{1, .., r1_max} (eq. 20)
    x1_form: str = "grouped"  # eq. 13: "grouped" (XM - Xbest) rand, or "printed" XM - Xbest rand
    # DERLSP-AO, derlsp-ao-abs section 3.2
    lens_opposition: bool = False  # eqs. 28-29
    lens_k: float | None = None  # None: adaptive k = (1 + (t/T)^0.5)^10
    stagnation: bool = False  # eqs. 30-31
    stagnation_iters: int = 5
    de_step: bool = False  # eqs. 32-34
    # DEFFAO, deffao-vehicle-abs (design ours)
    free_hunting: bool = False
    free_prob: float = 0.2
    nonlinear_factor: bool = False
    de_elimination: bool = False
    elim_fraction: float = 0.3
    # DE constants shared by de_step and de_elimination
    de_f: float = 0.5
    de_cr: float = 0.9

    def __post_init__(self) -> None:
        self.check(
            0.0 <= self.alpha <= 1.0, "alpha", f"expected a value in [0, 1], got {self.alpha}"
        )
        self.check(
            0.0 <= self.delta <= 1.0, "delta", f"expected a value in [0, 1], got {self.delta}"
        )
        self.check(
            0.0 < self.levy_beta < 2.0, "levy_beta", f"expected 0 < beta < 2, got {self.levy_beta}"
        )
        self.check(
            self.levy_scale > 0, "levy_scale", f"expected a positive value, got {self.levy_scale}"
        )
        self.check(
            self.spiral_r1_max >= 1, "spiral_r1_max", f"expected >= 1, got {self.spiral_r1_max}"
        )
        self.check(
            self.x1_form in ("grouped", "printed"),
            "x1_form",
            f"expected 'grouped' or 'printed', got {self.x1_form!r}",
        )
        self.check(
            self.lens_k is None or self.lens_k > 0, "lens_k", f"expected > 0, got {self.lens_k}"
        )
        self.check(
            self.stagnation_iters >= 1,
            "stagnation_iters",
            f"expected >= 1, got {self.stagnation_iters}",
        )
        self.check(
            0.0 <= self.free_prob <= 1.0, "free_prob", f"expected [0, 1], got {self.free_prob}"
        )
        self.check(
            0.0 < self.elim_fraction <= 1.0,
            "elim_fraction",
            f"expected (0, 1], got {self.elim_fraction}",
        )
        check_rates(self, "de_f", "de_cr")


class Aquila(Optimizer):
    """The Aquila engine; the registered variants below differ only in their default strategies."""

    name = "aquila"
    description = "Aquila engine"
    min_pop = 4
    defaults = AquilaHyper()
    hyper: AquilaHyper

    def required_pop(self) -> int:
        """Three distinct DE partners need 4 eagles, DE/best/1 elimination 3, plain AO 2."""
        h = self.hyper
        return 4 if h.de_step else 3 if h.de_elimination else 2

    def _n_elim(self) -> int:
        return max(1, math.ceil(self.hyper.elim_fraction * self.pop_size))

    def evals_per_iteration(self) -> int:
        h = self.hyper
        n = self.pop_size + int(h.lens_opposition)
        if h.de_step:
            n += self.pop_size
        if h.de_elimination:
            n += self._n_elim()
        return n

    def _factor(self, t: int) -> float:
        """1 - t/T (AO) or DEFFAO's nonlinear c(t) = (1 - t/T)^2."""
        lin = 1.0 - t / self.T
        return lin * lin if self.hyper.nonlinear_factor else lin

    def _steps(self) -> Steps:
        h, rng = self.hyper, self.rng
        n, d, T = self.pop_size, self.dim, self.T
        lo, hi = self.lo, self.hi
        dims = np.arange(1.0, d + 1.0)  # D1 = 1..Dim, eqs. 20-21
        theta = -h.spiral_omega * dims + 1.5 * np.pi  # eqs. 21-22
        y_minus_x = np.cos(theta) - np.sin(theta)  # (y - x) / r, eqs. 18-19
        u_dims = h.spiral_u * dims

        x = self.uniform(n)
        f = (yield x).copy()
        stall = 0
        last_best = float(f.min())
        for t in self.iterations():
            b = int(np.argmin(f))
            xbest = x[b].copy()
            xmean = x.mean(axis=0)  # eq. 14
            c = self._factor(t)
            qf = 1.0 if T == 1 else t ** ((2.0 * rng.random() - 1.0) / (1.0 - T) ** 2)  # eq. 25
            g1 = 2.0 * rng.random() - 1.0  # eq. 26
            g2 = 2.0 * c  # eq. 27
            first = (rng.random(n) < 0.5)[:, None]
            stagnating = h.stagnation and stall >= h.stagnation_iters
            if h.lens_opposition:  # eq. 28
                a_j, b_j = x.min(axis=0), x.max(axis=0)
                k = h.lens_k if h.lens_k is not None else (1.0 + (t / T) ** 0.5) ** 10
                mid = 0.5 * (a_j + b_j)
                x_opp = mid + mid / k - xbest / k
                lead = x_opp  # eq. 29
            else:
                lead = xbest
            if t <= 2.0 * T / 3.0:
                r13 = rng.random(n)[:, None]
                xr = x[rng.integers(0, n, size=n)]
                r1 = rng.integers(1, h.spiral_r1_max + 1, size=n).astype(float)
                r15 = rng.random(n)[:, None]
                lev = levy(rng, (n, d), h.levy_beta, h.levy_scale)
                if h.x1_form == "grouped":  # eq. 13 / 29, see the module docstring
                    move_a = lead * c + (xmean - lead) * r13
                else:
                    move_a = lead * c + (xmean - lead * r13)
                spiral = (r1[:, None] + u_dims) * y_minus_x  # (y - x), eqs. 18-20
                move_b = xbest * lev + xr + spiral * r15  # eq. 15
            else:
                r23a = rng.random(n)[:, None]
                r23b = rng.random(n)[:, None]
                r24a = rng.random(n)[:, None]
                r24b = rng.random(n)[:, None]
                lev = levy(rng, (n, d), h.levy_beta, h.levy_scale)
                move_a = (
                    (xbest - xmean) * h.alpha - r23a + ((hi - lo) * r23b + lo) * h.delta
                )  # eq. 23
                move_b = qf * xbest - g1 * x * r24a - g2 * lev + r24b * g1  # eq. 24
            if stagnating:  # eqs. 30-31
                lev2 = levy(rng, (n, d), h.levy_beta, h.levy_scale)
                n1 = rng.standard_normal(n)[:, None]
                n2 = rng.standard_normal(n)[:, None]
                move_b = xbest + n1 * lev2 + n2 * (xbest - move_b)
            trial = np.where(first, move_a, move_b)
            if h.free_hunting:  # DEFFAO strategy 1 (ours)
                free = (rng.random(n) < h.free_prob)[:, None]
                k_idx = partners(rng, n, 1)[:, 0]
                r = rng.random((n, d))
                towards = (f[k_idx] < f)[:, None]
                step = np.where(towards, x[k_idx] - x, x - x[k_idx]) * r
                trial = np.where(free, x + step, trial)
            if h.lens_opposition:
                trial = np.vstack([trial, x_opp[None, :]])
            f_trial = yield trial
            greedy(x, f, trial[:n], f_trial[:n])
            if h.lens_opposition:  # X' replaces the best if better
                b = int(np.argmin(f))
                if f_trial[n] < f[b]:
                    x[b] = trial[n]
                    f[b] = f_trial[n]
            if h.de_step:  # eqs. 32-34, DE/rand/1/bin
                p = partners(rng, n, 3)
                v = x[p[:, 0]] + h.de_f * (x[p[:, 1]] - x[p[:, 2]])  # eq. 32
                u = binomial_crossover(rng, x, v, h.de_cr)  # eq. 33
                f_u = yield u
                greedy(x, f, u, f_u)  # eq. 34
            if h.de_elimination:  # DEFFAO strategy 3 (ours)
                worst = np.argsort(f, kind="stable")[-self._n_elim() :]
                p = partners(rng, n, 2, rows=worst)
                best = x[int(np.argmin(f))]
                v = best + h.de_f * (x[p[:, 0]] - x[p[:, 1]])
                u = binomial_crossover(rng, x[worst], v, h.de_cr)
                f_u = yield u
                greedy(x, f, u, f_u, rows=worst)
            now = float(f.min())
            stall = 0 if now < last_best else stall + 1
            last_best = min(now, last_best)


class AO(Aquila):
    """Aquila Optimizer (Abualigah et al. 2021), derlsp-ao-abs eqs. 13-27."""

    name = "ao"
    description = "Aquila Optimizer (Abualigah 2021; derlsp-ao-abs eqs. 13-27)"
    min_pop = 2
    defaults = AquilaHyper()


class DERLSPAO(Aquila):
    """DERLSP-AO: AO + lens opposition + stagnation perturbation + DE (derlsp-ao-abs eqs. 28-34)."""

    name = "derlsp-ao"
    description = "AO + lens opposition, stagnation perturbation and DE (derlsp-ao-abs eqs. 28-34)"
    min_pop = 4
    defaults = AquilaHyper(lens_opposition=True, stagnation=True, de_step=True)


class DEFFAO(Aquila):
    """DEFFAO: AO + free hunting + nonlinear factor + DE elimination (deffao-vehicle-abs; ours)."""

    name = "deffao"
    description = "AO + free hunting, nonlinear factor, DE elimination (deffao-vehicle-abs; ours)"
    min_pop = 3
    defaults = AquilaHyper(free_hunting=True, nonlinear_factor=True, de_elimination=True)
