"""Dung beetle optimizer (Xue & Shen 2022), following the authors' MATLAB code.

Four groups by index: ball-rolling beetles (20 %), brood balls (20 %), small beetles (23 %) and
thieves (the rest): the reference code's 6/6/7/11 of 30 (group sizes rounded half up).
Each beetle keeps its personal best pX (the code's pX) and the previous one (XX).

- Rolling (eq. 1): x = pX + b |pX - X_worst| + alpha k XX, alpha = -1 with probability 0.1 else 1,
  k = 0.1, b = 0.3; with probability 0.1 per iteration (one draw for the group, as in the code)
  the group dances instead (eq. 2): x = pX + tan(theta) |pX - XX|, theta a random whole degree in
  1..180; at 90 and 180 degrees the beetle stays (the paper's rule; the code's check is dead).
- Brood balls (eqs. 3-4): inside [Lb*, Ub*] = the box of X*(1 - R) and X*(1 + R) (taken
  coordinate-wise as min and max, so a negative X* gives a valid box; the code can invert it),
  X* the current best position, R = 1 - t/T: x = X* + b1 (pX - Lb*) + b2 (pX - Ub*).
- Small beetles (eqs. 5-6): x = pX + C1 (pX - Lb^b) + C2 (pX - Ub^b) with the box of the global
  best X^b, C1 ~ N(0, 1) per beetle, C2 ~ U(0, 1)^D.
- Thieves (eq. 7): x = X^b + S g (|pX - X*| + |pX - X^b|), S = 0.5, g ~ N(0, 1)^D.

Two batches per iteration, as the code evaluates the rollers before it picks X*: the rollers, then
the others. N evaluations per iteration.

Draw order per iteration: the dance test `random()`; rolling: `random(n_roll)` for alpha, or
dancing: `integers(1, 181, n_roll)`; brood b1, b2 `random((n_brood, D))` twice; small C1
`standard_normal(n_small)`, C2 `random((n_small, D))`; thieves g `standard_normal((n_thief, D))`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from chassistune.optimizers.base import FloatArray, Hyperparameters, Optimizer, Steps


@dataclass(frozen=True)
class DBOHyper(Hyperparameters):
    """DBO hyperparameters (the reference code's values)."""

    k: float = 0.1
    b: float = 0.3
    deflect_prob: float = 0.1  # lambda: probability of alpha = -1
    dance_prob: float = 0.1
    S: float = 0.5
    roll_fraction: float = 0.2
    brood_fraction: float = 0.2
    small_fraction: float = 0.23

    def __post_init__(self) -> None:
        for name in (
            "deflect_prob",
            "dance_prob",
            "roll_fraction",
            "brood_fraction",
            "small_fraction",
        ):
            value = getattr(self, name)
            self.check(0 <= value <= 1, name, f"expected [0, 1], got {value}")
        self.check(
            self.roll_fraction + self.brood_fraction + self.small_fraction < 1,
            "fractions",
            "roll + brood + small fractions must leave room for thieves",
        )


def _round_half_up(v: float) -> int:
    return math.floor(v + 0.5)


def _box(
    centre: FloatArray, r: float, lo: FloatArray, hi: FloatArray
) -> tuple[FloatArray, FloatArray]:
    a, b = centre * (1.0 - r), centre * (1.0 + r)
    return np.clip(np.minimum(a, b), lo, hi), np.clip(np.maximum(a, b), lo, hi)


def group_sizes(h: DBOHyper, n: int) -> tuple[int, int, int, int]:
    """Rolling, brood, small and thief group sizes of a population of n."""
    roll = max(1, _round_half_up(h.roll_fraction * n))
    brood = max(1, _round_half_up(h.brood_fraction * n))
    small = max(1, _round_half_up(h.small_fraction * n))
    return roll, brood, small, n - roll - brood - small


class DBO(Optimizer):
    """Dung beetle optimizer."""

    name = "dbo"
    description = "Dung beetle optimizer, groups 20/20/23/rest % (Xue & Shen 2022)"
    min_pop = 4
    defaults = DBOHyper()
    hyper: DBOHyper

    def groups(self) -> tuple[int, int, int, int]:
        """Sizes of the rolling, brood, small and thief groups."""
        return group_sizes(self.hyper, self.pop_size)

    def required_pop(self) -> int:
        n = 4
        while group_sizes(self.hyper, n)[3] < 1:  # the smallest population with every group
            n += 1
        return n

    def _steps(self) -> Steps:
        h, rng, d = self.hyper, self.rng, self.dim
        lo, hi = self.lo, self.hi
        n_roll, n_brood, n_small, _ = self.groups()
        s_brood = slice(n_roll, n_roll + n_brood)
        s_small = slice(n_roll + n_brood, n_roll + n_brood + n_small)
        s_thief = slice(n_roll + n_brood + n_small, self.pop_size)
        x = self.uniform(self.pop_size)
        fx = (yield x).copy()
        px, pf = x.copy(), fx.copy()  # personal bests
        xx = px.copy()  # previous personal bests
        for t in self.iterations():
            gbest = px[int(np.argmin(pf))].copy()
            worst = x[int(np.argmax(fx))].copy()
            p_roll, xx_roll = px[:n_roll], xx[:n_roll]
            if rng.random() < 1.0 - h.dance_prob:  # eq. 1
                alpha = np.where(rng.random(n_roll) > h.deflect_prob, 1.0, -1.0)[:, None]
                roll = p_roll + h.b * np.abs(p_roll - worst) + alpha * h.k * xx_roll
            else:  # eq. 2
                deg = rng.integers(1, 181, size=n_roll)
                stay = (deg == 90) | (deg == 180)
                tan = np.where(stay, 0.0, np.tan(np.where(stay, 0, deg) * np.pi / 180.0))[:, None]
                roll = p_roll + tan * np.abs(p_roll - xx_roll)
            f_roll = yield roll
            x[:n_roll], fx[:n_roll] = roll, f_roll
            local = x[int(np.argmin(fx))].copy()  # X*
            r = 1.0 - t / self.T
            lb_s, ub_s = _box(local, r, lo, hi)  # eq. 3
            lb_b, ub_b = _box(gbest, r, lo, hi)  # eq. 5
            pb = px[s_brood]
            b1 = rng.random((n_brood, d))
            b2 = rng.random((n_brood, d))
            brood = np.clip(local + b1 * (pb - lb_s) + b2 * (pb - ub_s), lb_s, ub_s)  # eq. 4
            ps = px[s_small]
            c1 = rng.standard_normal(n_small)[:, None]
            c2 = rng.random((n_small, d))
            small = ps + c1 * (ps - lb_b) + c2 * (ps - ub_b)  # eq. 6
            pt = px[s_thief]
            g = rng.standard_normal((pt.shape[0], d))
            thief = gbest + h.S * g * (np.abs(pt - local) + np.abs(pt - gbest))  # eq. 7
            rest = np.concatenate([brood, small, thief])
            f_rest = yield rest
            x[n_roll:], fx[n_roll:] = rest, f_rest
            xx = px.copy()
            better = fx < pf
            px[better], pf[better] = x[better], fx[better]
