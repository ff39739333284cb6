"""A candidate's cost over K scenarios (x R roads): mean, max or CVaR.

`cvar:ALPHA` is the mean of the worst ceil(ALPHA M) of the M = K R costs of a candidate (the
empirical conditional value at risk of the upper ALPHA tail; Rockafellar & Uryasev 2000): ALPHA = 1
gives the mean, ALPHA M <= 1 the max. Ties and penalties count like any other cost.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from chassistune.errors import InputError
from chassistune.params import to_float


@dataclass(frozen=True)
class Aggregate:
    """`kind` mean | max | cvar; `alpha` in (0, 1] for cvar."""

    kind: str = "mean"
    alpha: float = 1.0

    def __str__(self) -> str:
        return f"cvar:{self.alpha:g}" if self.kind == "cvar" else self.kind

    def tail_count(self, m: int) -> int:
        """How many of m costs the aggregate averages (cvar: ceil(alpha m); mean: m; max: 1)."""
        if self.kind == "max":
            return 1
        if self.kind == "mean":
            return m
        # a relative guard keeps ALPHA = 0.1, M = 30 at 3 (0.1 * 30 = 3.0000000000000004)
        return max(1, min(m, math.ceil(self.alpha * m * (1.0 - 1e-12))))

    def __call__(self, costs: np.ndarray) -> np.ndarray:
        """Costs of shape (n, K) or (n, K, R) -> (n,): every column of a row is one scenario."""
        c = np.asarray(costs, dtype=np.float64)
        if c.ndim < 2:
            raise ValueError(f"costs need a scenario axis: shape (n, K[, R]), got {c.shape}")
        c = c.reshape(c.shape[0], -1)
        if self.kind == "max":
            return np.asarray(c.max(axis=1))
        if self.kind == "mean":
            return np.asarray(c.mean(axis=1))
        m = self.tail_count(c.shape[1])
        return np.asarray(np.sort(c, axis=1)[:, c.shape[1] - m :].mean(axis=1))


def parse_aggregate(text: str, field: str = "aggregate") -> Aggregate:
    """'mean', 'max' or 'cvar:ALPHA' with 0 < ALPHA <= 1."""
    kind, sep, rest = text.strip().partition(":")
    kind = kind.lower()
    if kind in ("mean", "max") and not sep:
        return Aggregate(kind)
    if kind == "cvar" and sep:
        alpha = to_float(rest, field)
        if not 0.0 < alpha <= 1.0:
            raise InputError(field, f"cvar ALPHA must be in (0, 1], got {alpha:g}")
        return Aggregate("cvar", alpha)
    raise InputError(field, f"must be mean, max or cvar:ALPHA, got {text!r}")
