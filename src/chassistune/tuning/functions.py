"""The benchmark-function scenario kind of studies: minimize F1-F23 (an optimizer comparison).

A study scenario with `functions = ["F4", ...]` has one cell per function; each run minimizes
that function over its usual box. A noisy function (F7) draws its noise from the run's scenario
seed, so every optimizer at one seed index sees the same noise stream.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from chassistune import benchmarks
from chassistune._rng import make_rng

FUNCTION_KIND = "function"
"""The `plant` field of a benchmark-function run spec."""


@dataclass
class FunctionProblem:
    """A benchmark function as a batch objective: (n, d) points in, n values out."""

    function: benchmarks.BenchmarkFunction
    noise: np.random.Generator | None
    objective: str = "value"

    @property
    def bounds(self) -> list[tuple[float, float]]:
        return [(float(lo), float(hi)) for lo, hi in self.function.bounds()]

    @property
    def gain_names(self) -> tuple[str, ...]:
        return tuple(f"x{i + 1}" for i in range(self.function.dim))

    def __call__(self, x: np.ndarray) -> np.ndarray:
        return np.asarray(self.function(x, self.noise), dtype=float)


def build_function_problem(name: str, seed: int) -> FunctionProblem:
    """Function `name` (InputError if unknown) with its noise generator seeded from `seed`."""
    fn = benchmarks.get(name)
    return FunctionProblem(fn, make_rng(seed) if fn.noisy else None)
