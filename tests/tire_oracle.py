"""A scalar oracle of the tire law mu(S) of `plants.tires` (design.md 3.2) for the tests: `tire_mu`
evaluates any family from the arrays of `TireCurve.kernel_data` with plain branches; the kernels'
branch-free `sim.abs_wheel_tires.tire_law_mu` must give bitwise the same numbers.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from chassistune.plants.tires import KIND_BILINEAR, KIND_BURCKHARDT


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def tire_mu(kind: int, coef: np.ndarray, xs: np.ndarray, ys: np.ndarray, s: float) -> float:
    """Friction coefficient at slip s in [0, 1].

    kind 0: linear table (xs, ys); 1: Burckhardt, coef = (c1, c2, c3); 2: bilinear in closed form,
    coef = (S_T, mu_h / S_T, (mu_h - mu_g S_T)/(1 - S_T), (mu_h - mu_g)/(1 - S_T)).
    """
    if kind == KIND_BILINEAR:
        rising = coef[1] * s
        falling = coef[2] - coef[3] * s
        return rising if s <= coef[0] else falling
    if kind == KIND_BURCKHARDT:
        return coef[0] * (1.0 - math.exp(-coef[1] * s)) - coef[2] * s
    n = xs.shape[0]
    j = 1
    while j < n - 1 and s > xs[j]:
        j += 1
    return ys[j - 1] + (ys[j] - ys[j - 1]) * (s - xs[j - 1]) / (xs[j] - xs[j - 1])
