"""Operators shared by several algorithm families (one copy each, vectorized over the population).

Every function takes the optimizer's Generator and documents the draws it makes, in order, so that
the algorithms that call it can state their full per-iteration draw order.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]


def mantegna_sigma(beta: float) -> float:
    """sigma_u of Mantegna's Levy step (derlsp-ao-abs eq. 17)."""
    num = math.gamma(1.0 + beta) * math.sin(math.pi * beta / 2.0)
    den = math.gamma((1.0 + beta) / 2.0) * beta * 2.0 ** ((beta - 1.0) / 2.0)
    return float((num / den) ** (1.0 / beta))


def levy(rng: np.random.Generator, shape: tuple[int, ...], beta: float, scale: float) -> FloatArray:
    """Levy(D) steps, derlsp-ao-abs eqs. 16-17, with Mantegna's draws.

    Levy = scale * u / |v|^(1/beta), u ~ N(0, sigma^2), v ~ N(0, 1). derlsp-ao-abs prints u1 in
    (0, 1): a slip (a uniform u gives no symmetric heavy-tailed step); we use the normal u of
    Mantegna and of the authors' code.
    Draws: `standard_normal(shape)` for u, then `standard_normal(shape)` for v.
    """
    u = rng.standard_normal(shape) * mantegna_sigma(beta)
    v = rng.standard_normal(shape)
    out: FloatArray = scale * u / np.abs(v) ** (1.0 / beta)
    return out


def partners(rng: np.random.Generator, n: int, k: int, rows: IntArray | None = None) -> IntArray:
    """For each row index r in `rows` (default 0..n-1), k distinct indices of 0..n-1, all != r.

    Vectorized sampling without replacement: the c-th partner is drawn uniformly among the
    n - 1 - c indices not yet excluded and mapped past the excluded ones in ascending order.
    Draws: for c = 0..k-1, `integers(0, n - 1 - c, size=len(rows))`. Needs n >= k + 1.
    """
    if rows is None:
        rows = np.arange(n)
    m = rows.size
    out = np.empty((m, k), dtype=np.intp)
    excluded = rows.reshape(m, 1).astype(np.intp)
    for c in range(k):
        v = rng.integers(0, n - 1 - c, size=m)
        ex = np.sort(excluded, axis=1)
        for j in range(ex.shape[1]):
            v += v >= ex[:, j]
        out[:, c] = v
        excluded = np.concatenate([excluded, v.reshape(m, 1)], axis=1)
    return out


def binomial_crossover(
    rng: np.random.Generator, x: FloatArray, v: FloatArray, cr: float
) -> FloatArray:
    """DE binomial crossover with a forced gene j_rand (derlsp-ao-abs eq. 33).

    Draws: `random(x.shape)` for the CR test, then `integers(0, d, size=n)` for j_rand.
    """
    n, d = x.shape
    take = rng.random((n, d)) < cr
    take[np.arange(n), rng.integers(0, d, size=n)] = True
    out: FloatArray = np.where(take, v, x)
    return out


def greedy(
    x: FloatArray,
    f: FloatArray,
    trial: FloatArray,
    f_trial: FloatArray,
    *,
    ties: bool = False,
    rows: IntArray | None = None,
) -> NDArray[np.bool_]:
    """One-to-one greedy selection in place (derlsp-ao-abs eq. 34): keep the trial where better.

    `ties=True` also accepts equal costs (`<=`, as POA's reference code does). With `rows`, trial i
    competes with member `rows[i]`. Returns the mask of accepted trials.
    """
    target = f if rows is None else f[rows]
    better = f_trial <= target if ties else f_trial < target
    if rows is None:
        x[better] = trial[better]
        f[better] = f_trial[better]
    else:
        x[rows[better]] = trial[better]
        f[rows[better]] = f_trial[better]
    return better
