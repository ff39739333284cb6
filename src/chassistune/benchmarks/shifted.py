"""F1-F23 with the optimum moved to a random point of the box: the centre-bias test (Kudela
2022, "A critical problem in benchmarking and analysis of evolutionary computation methods",
Nature Machine Intelligence 4).

The box and the minimum value are those of the original function; only the minimizer moves, to
a point drawn uniformly in the box. Two ways, by function:

- **shift** (F1-F7, F9-F13): g(x) = f(x - s), s = p - x*. These formulas are defined on all of
  R^d and their known minimum is global there, so no value below it enters the box.
- **wrap** (F8 and the fixed-domain F14-F23): g(x) = f(lo + ((x - s - lo) mod (hi - lo))),
  s = p - x*. Schwefel 2.26 falls below its box minimum outside the box, and the fixed-domain
  functions are known only on their box; wrapping periodically evaluates f on its own box only,
  so g's minimum over the box is f's, at p. g is discontinuous at the seam.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from chassistune._rng import SeedLike, make_rng
from chassistune.benchmarks.functions import BenchmarkFunction, FloatArray, get

WRAPPED = ("F8", "F14", "F15", "F16", "F17", "F18", "F19", "F20", "F21", "F22", "F23")
"""Functions moved by periodic wrapping; the others are shifted."""


@dataclass(frozen=True)
class ShiftedFunction:
    """`function` in dimension `dim` with its minimizer moved to `optimum` (inside the box)."""

    function: BenchmarkFunction
    dim: int
    optimum: FloatArray

    @property
    def name(self) -> str:
        return f"{self.function.name}+shift"

    @property
    def wrapped(self) -> bool:
        return self.function.name in WRAPPED

    @property
    def noisy(self) -> bool:
        return self.function.noisy

    def bounds(self) -> FloatArray:
        """The original box, shape `(dim, 2)`."""
        return self.function.bounds(self.dim)

    def minimizer(self) -> FloatArray:
        return self.optimum.copy()

    def f_min(self) -> float:
        return self.function.f_min(self.dim)

    def original_point(self, x: ArrayLike) -> FloatArray:
        """The point of the original function that `x` maps to."""
        b = self.bounds()
        lo, width = b[:, 0], b[:, 1] - b[:, 0]
        y = np.asarray(x, dtype=float) - (self.optimum - self.function.minimizer(self.dim))
        if self.wrapped:
            y = lo + np.mod(y - lo, width)
        out: FloatArray = y
        return out

    def noise_free(self, x: ArrayLike) -> FloatArray:
        """The value without F7's noise, for `(n, d)` points."""
        return self.function.formula(self.original_point(np.atleast_2d(x)))

    def __call__(self, x: ArrayLike, rng: np.random.Generator | None = None) -> FloatArray:
        return self.function(self.original_point(x), rng)


def shifted(name: str, dim: int | None = None, seed: SeedLike = 0) -> ShiftedFunction:
    """Function `name` with its minimizer moved to a point drawn uniformly in its box from
    `seed` (one `random(d)` draw)."""
    fn = get(name)
    d = fn.check_dim(dim)
    b = fn.bounds(d)
    optimum = b[:, 0] + make_rng(seed).random(d) * (b[:, 1] - b[:, 0])
    optimum = np.clip(optimum, b[:, 0], b[:, 1])  # lo + r (hi - lo) may round past hi
    return ShiftedFunction(fn, d, optimum)
