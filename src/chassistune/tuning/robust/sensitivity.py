"""First-order and total Sobol indices of a function of the uncertain parameters.

Saltelli's scheme as `scipy.stats.sobol_indices` implements it (Saltelli et al. 2010, "Variance
based sensitivity analysis of model output", Computer Physics Communications 181): n (d + 2)
evaluations, n a power of two. The function is evaluated at points of the parameters' own
distributions: the indices are computed over unit-cube inputs mapped by `sampling.from_unit`, so
a normal parameter is the clipped normal the training and validation sets use.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import stats

from chassistune.errors import InputError
from chassistune.tuning.robust.sampling import from_unit
from chassistune.tuning.robust.spec import UncertainParam


@dataclass(frozen=True)
class SensitivityResult:
    """Indices by parameter: `first_order[i]` and `total[i]` belong to `names[i]`."""

    names: tuple[str, ...]
    first_order: np.ndarray
    total: np.ndarray
    n: int

    @property
    def evaluations(self) -> int:
        return self.n * (len(self.names) + 2)

    def rows(self) -> list[dict[str, Any]]:
        """Table rows: parameter, first-order index, total index."""
        return [
            {"parameter": name, "first_order": float(s1), "total": float(st)}
            for name, s1, st in zip(self.names, self.first_order, self.total, strict=True)
        ]


def sobol_sensitivity(
    func: Callable[[np.ndarray], np.ndarray],
    params: Sequence[UncertainParam],
    n: int,
    rng: np.random.Generator,
) -> SensitivityResult:
    """Indices of `func(values) -> (m,)`, values (m, d) in parameter units, over `params`."""
    if isinstance(n, bool) or not isinstance(n, int) or n < 1 or n & (n - 1):
        raise InputError("sobol_n", f"must be a power of two, got {n!r}")
    unit = stats.uniform(0.0, 1.0)

    def on_unit_cube(u: np.ndarray) -> np.ndarray:
        return np.asarray(func(from_unit(params, np.asarray(u).T)), dtype=float).reshape(1, -1)

    res = stats.sobol_indices(func=on_unit_cube, n=n, dists=[unit] * len(params), rng=rng)
    return SensitivityResult(
        tuple(p.name for p in params),
        np.asarray(res.first_order, dtype=float).reshape(-1),
        np.asarray(res.total_order, dtype=float).reshape(-1),
        n,
    )
