"""Artificial bee colony: ABC (Karaboga 2005) and IABC (iabc-suspension eqs. 5-9) as configurations.

`pop_size` is the number of food sources SN; a cycle has an employed phase (SN evaluations), an
onlooker phase (SN evaluations) and at most one scout (one evaluation), so about 2 SN evaluations.

- Employed bees (iabc-suspension eq. 6): v_ij = x_ij + phi (x_ij - x_kj) on one random dimension
  j, k a random other source, phi ~ U(-a, a); greedy; a failed try adds one to the source's trial
  count.
- Onlookers choose sources from the fitness of the costs Q: Karaboga's fit = 1/(1 + Q) for Q >= 0,
  1 + |Q| for Q < 0 (benchmark functions go negative), or iabc-suspension's fit = 1/Q (eq. 11,
  `fitness="reciprocal"`, for positive objectives; Q <= 0 is treated as 1e-300).
  ABC (`selection="roulette"`): p_i = fit_i / sum fit (eq. 7), SN sources sampled with replacement.
  IABC (`selection="iabc"`): p_i = 0.1 fit_i / max fit + 0.9 (eq. 9), used as Karaboga's reference
  code uses its probabilities (they do not sum to 1): visit the sources in turn from the first and
  send an onlooker to source i when rand < p_i, until SN onlookers are sent.
- Scout: at most one per cycle, the source with the largest trial count if it exceeds `limit`
  (default SN * D) is replaced by a uniform random point (eq. 5), evaluated, unconditionally.
  `diagnostics["scouts"]` counts them. With iabc-suspension's setting (100 sources, 3 gains, 100
  cycles, limit 300) IABC practically never sends one (every p_i >= 0.9, so a source gets one or
  two onlookers per cycle: about 2 to 3 trials per cycle at most); ABC's roulette can pile
  onlookers on a dominant source, and then a scout can fire (3 on F5, d = 3, seed 0; none on F1,
  F9, F19).
- IABC's nudge (eq. 8): where the new coordinate equals the old one (x_ij == x_kj), it is moved by
  epsilon * (hi_j - lo_j) * phi (`epsilon` > 0; 0 switches the nudge off, as in ABC).

Batch semantics (ours): every employed bee and every onlooker of a phase works from the state at
the start of that phase (the reference code updates sources one bee at a time). Several onlookers
on one source: the best of their trials competes with the source; the source's trial count is
reset if it improved, else increased by the number of its onlookers.

Draw order per cycle: employed j `integers(0, D, SN)`, k (`_operators.partners`), phi `random(SN)`;
onlookers: ABC `random(SN)` for the roulette, IABC `random(2 SN)` chunks until SN are sent; then
j, k, phi as above; scout (only when one fires): `random((1, D))`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from chassistune.optimizers._operators import IntArray, partners
from chassistune.optimizers.base import FloatArray, Hyperparameters, Optimizer, Steps


@dataclass(frozen=True)
class BeeColonyHyper(Hyperparameters):
    """ABC / IABC hyperparameters (Karaboga 2005; iabc-suspension eqs. 6-9)."""

    limit: int | None = None  # None: SN * D
    phi_range: float = 1.0  # a: phi ~ U(-a, a), eq. 6
    fitness: str = "karaboga"  # or "reciprocal" (iabc-suspension eq. 11)
    selection: str = "roulette"  # eq. 7; "iabc" for eq. 9
    epsilon: float = 0.0  # eq. 8 nudge, relative to the range; 0: off

    def __post_init__(self) -> None:
        self.check(
            self.limit is None or self.limit >= 1, "limit", f"expected >= 1, got {self.limit}"
        )
        self.check(self.phi_range > 0, "phi_range", f"expected > 0, got {self.phi_range}")
        self.check(
            self.fitness in ("karaboga", "reciprocal"),
            "fitness",
            f"expected 'karaboga' or 'reciprocal', got {self.fitness!r}",
        )
        self.check(
            self.selection in ("roulette", "iabc"),
            "selection",
            f"expected 'roulette' or 'iabc', got {self.selection!r}",
        )
        self.check(self.epsilon >= 0, "epsilon", f"expected >= 0, got {self.epsilon}")


class BeeColony(Optimizer):
    """ABC engine; `ABC` and `IABC` are its registered configurations."""

    name = "bee-colony"
    min_pop = 2
    defaults = BeeColonyHyper()
    hyper: BeeColonyHyper

    def evals_per_iteration(self) -> int:
        return 2 * self.pop_size

    def _fit(self, cost: FloatArray) -> FloatArray:
        """Fitness of costs for the onlooker probabilities (larger is better, 0 for +inf)."""
        if self.hyper.fitness == "reciprocal":
            out: FloatArray = 1.0 / np.maximum(cost, 1e-300)
            return out
        return np.where(cost >= 0, 1.0 / (1.0 + cost), 1.0 + np.abs(cost))

    def _onlooker_sources(self, cost: FloatArray) -> IntArray:
        rng, sn = self.rng, self.pop_size
        fit = self._fit(cost)
        if self.hyper.selection == "roulette":  # eq. 7
            total = fit.sum()
            u = rng.random(sn)
            if not np.isfinite(total) or total <= 0:
                return np.minimum((u * sn).astype(np.intp), sn - 1)
            cum = np.cumsum(fit / total)
            return np.minimum(np.searchsorted(cum, u, side="right"), sn - 1).astype(np.intp)
        top = fit.max()
        p = 0.1 * fit / top + 0.9 if np.isfinite(top) and top > 0 else np.full(sn, 0.9)  # eq. 9
        chosen: list[IntArray] = []
        count, start = 0, 0
        while count < sn:
            r = rng.random(2 * sn)
            idx = (start + np.arange(2 * sn)) % sn
            hit = idx[r < p[idx]]
            chosen.append(hit[: sn - count])
            count += min(hit.size, sn - count)
            start = (start + 2 * sn) % sn
        return np.concatenate(chosen).astype(np.intp)

    def _neighbour_moves(self, x: FloatArray, rows: IntArray) -> FloatArray:
        """Eq. 6 (and eq. 8's nudge) for the sources `rows`: one random dimension each."""
        rng, h = self.rng, self.hyper
        m = rows.size
        j = rng.integers(0, self.dim, size=m)
        k = partners(rng, self.pop_size, 1, rows=rows)[:, 0]
        phi = (2.0 * rng.random(m) - 1.0) * h.phi_range
        v = x[rows].copy()
        old = x[rows, j]
        new = old + phi * (old - x[k, j])
        if h.epsilon > 0:  # eq. 8: only where the move left the coordinate unchanged
            same = new == old
            new = np.where(same, old + h.epsilon * (self.hi[j] - self.lo[j]) * phi, new)
        v[np.arange(m), j] = new
        return v

    def _steps(self) -> Steps:
        sn, d = self.pop_size, self.dim
        limit = self.hyper.limit if self.hyper.limit is not None else sn * d
        all_rows = np.arange(sn)
        x = self.uniform(sn)  # eq. 5
        f = (yield x).copy()
        trial = np.zeros(sn, dtype=np.int64)
        self.diagnostics["scouts"] = 0  # scouts sent (iabc-suspension's setting sends none)
        for _ in self.iterations():
            # employed bees
            v = self._neighbour_moves(x, all_rows)
            fv = yield v
            better = fv < f
            x[better], f[better] = v[better], fv[better]
            trial = np.where(better, 0, trial + 1)
            # onlooker bees
            src = self._onlooker_sources(f)
            v = self._neighbour_moves(x, src)
            fv = yield v
            order = np.lexsort((fv, src))  # by source, best trial first
            first = np.ones(order.size, dtype=bool)
            first[1:] = src[order][1:] != src[order][:-1]
            best_rows = order[first]
            s = src[best_rows]
            improved = fv[best_rows] < f[s]
            x[s[improved]], f[s[improved]] = v[best_rows[improved]], fv[best_rows[improved]]
            visits = np.bincount(src, minlength=sn)
            trial = trial + visits
            trial[s[improved]] = 0
            # scout: at most one per cycle
            i = int(np.argmax(trial))
            if trial[i] > limit:
                self.diagnostics["scouts"] += 1
                fresh = self.uniform(1)
                f_fresh = yield fresh
                x[i], f[i], trial[i] = fresh[0], f_fresh[0], 0


class ABC(BeeColony):
    """Artificial bee colony (Karaboga 2005), roulette onlookers (iabc-suspension eqs. 5-7)."""

    name = "abc"
    description = "Artificial bee colony (Karaboga 2005; iabc-suspension eqs. 5-7)"
    defaults = BeeColonyHyper()


class IABC(BeeColony):
    """Improved ABC (iabc-suspension): epsilon nudge (eq. 8), p = 0.1 f / max f + 0.9 (eq. 9)."""

    name = "iabc"
    description = "Improved ABC: epsilon nudge and p = 0.1 f/max f + 0.9 (iabc-suspension eqs. 8-9)"
    defaults = BeeColonyHyper(selection="iabc", epsilon=1e-6)
