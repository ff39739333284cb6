"""Membership functions: `tri` [a, b, c], `trap` [a, b, c, d], `gauss` [mean, sigma].

The shapes follow scikit-fuzzy's `trimf`, `trapmf` and `gaussmf`, including the shoulders
(`tri` with a == b or b == c is a half triangle whose peak is 1). A triangle is the trapezoid
[a, b, b, c], so both share one implementation. The membership functions are numba ufuncs: numpy
code calls them on arrays (broadcasting), compiled code calls them on scalars; one implementation
serves both. Every set is unimodal, so where it crosses a membership level has a closed form
(`crossings`), which the exact centroid uses.

Packed form (for compiled code): a kind code (`TRAP` or `GAUSS`) and four parameters,
[a, b, c, d] for a trapezoid or triangle, [mean, sigma, 0, 0] for a Gaussian.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit, vectorize
from numpy.typing import ArrayLike, NDArray

SHAPES: dict[str, int] = {"tri": 3, "trap": 4, "gauss": 2}
"""Known shapes and their parameter counts."""

TRAP = 0
GAUSS = 1


@vectorize(["float64(float64, float64, float64, float64, float64)"], cache=True)
def trap_mf(
    x: float, a: float, b: float, c: float, d: float
) -> float:  # pragma: no cover - compiled
    """Trapezoid membership (a == b or c == d: a vertical flank, i.e. a shoulder)."""
    if x < b:
        return (x - a) / (b - a) if x > a else 0.0
    if x <= c:
        return 1.0
    return (d - x) / (d - c) if x < d else 0.0


@vectorize(["float64(float64, float64, float64)"], cache=True)
def gauss_mf(x: float, mean: float, sigma: float) -> float:  # pragma: no cover - compiled
    """Gaussian membership exp(-(x - mean)^2 / (2 sigma^2))."""
    z = (x - mean) / sigma
    return math.exp(-0.5 * z * z)


@njit(cache=True, nogil=True)
def packed_mf(kind: int, p: NDArray[np.float64], x: float) -> float:  # pragma: no cover - compiled
    """Membership of a packed set at a scalar `x`."""
    if kind == GAUSS:
        return gauss_mf(x, p[0], p[1])
    return trap_mf(x, p[0], p[1], p[2], p[3])


@njit(cache=True, nogil=True)
def crossings(
    kind: int, p: NDArray[np.float64], level: float
) -> tuple[float, float]:  # pragma: no cover
    """Where the rising and the falling flank of a packed set reach `level` in [0, 1]."""
    if kind == GAUSS:
        if level <= 0.0:
            return -np.inf, np.inf
        half = p[1] * math.sqrt(-2.0 * math.log(min(level, 1.0)))
        return p[0] - half, p[0] + half
    return p[0] + level * (p[1] - p[0]), p[3] - level * (p[3] - p[2])


def params_problem(shape: str, params: tuple[float, ...]) -> str | None:
    """Why `params` are invalid for `shape`, or None when they are valid."""
    if shape not in SHAPES:
        return f"unknown shape {shape!r} (expected one of {', '.join(SHAPES)})"
    if len(params) != SHAPES[shape]:
        return f"shape {shape!r} takes {SHAPES[shape]} parameters, got {len(params)}"
    if not all(math.isfinite(p) for p in params):
        return "parameters must be finite numbers"
    if shape == "gauss":
        return None if params[1] > 0 else "gauss sigma (second parameter) must be > 0"
    if any(params[i] > params[i + 1] for i in range(len(params) - 1)):
        return f"{shape} parameters must be non-decreasing, got {list(params)}"
    if params[0] == params[-1]:
        return f"{shape} set has zero width: {list(params)}"
    return None


@dataclass(frozen=True)
class FuzzySet:
    """A named fuzzy set. Construct through the schema, which validates `params`."""

    name: str
    shape: str
    params: tuple[float, ...]

    @property
    def kind(self) -> int:
        return GAUSS if self.shape == "gauss" else TRAP

    @property
    def packed(self) -> tuple[float, float, float, float]:
        """[a, b, c, d] (a triangle is [a, b, b, c]); [mean, sigma, 0, 0] for gauss."""
        p = self.params
        if self.shape == "gauss":
            return (p[0], p[1], 0.0, 0.0)
        return (p[0], p[1], p[1], p[2]) if self.shape == "tri" else (p[0], p[1], p[2], p[3])

    @property
    def core(self) -> tuple[float, float]:
        """Where the membership is 1: [b, b] for tri, [b, c] for trap, [mean, mean] for gauss."""
        p = self.packed
        return (p[0], p[0]) if self.shape == "gauss" else (p[1], p[2])

    @property
    def knots(self) -> tuple[float, ...]:
        """Abscissae where a piecewise-linear membership changes slope (none for gauss)."""
        return () if self.shape == "gauss" else tuple(sorted(set(self.packed)))

    def mf(self, x: ArrayLike) -> NDArray[np.float64]:
        """Membership degrees at `x` (any shape), in [0, 1]."""
        xs = np.asarray(x, dtype=np.float64)
        if self.shape == "gauss":
            return np.asarray(gauss_mf(xs, self.params[0], self.params[1]))
        return np.asarray(trap_mf(xs, *self.packed))

    def as_dict(self) -> dict[str, object]:
        return {"name": self.name, "shape": self.shape, "params": list(self.params)}
