"""Scenario sets: the training set (scrambled Sobol or Latin hypercube) and Monte Carlo sets.

Points are drawn in the unit cube [0, 1)^d and mapped parameter by parameter: uniform
lo + u (hi - lo); normal by the inverse CDF, mean + sd Phi^-1(u), clipped to the valid range.
Common random numbers: a run draws its training set once, from its own stream, and every
candidate of the run is scored on those same K scenarios.

Streams: `scenario_stream(seed, TRAINING | VALIDATION | SENSITIVITY)` gives each purpose its own
Generator, a child of the run's seed (a SeedSequence spawn key), independent of the others and of
the optimizer's stream (which stays `default_rng(seed)`, so a nominal run is unchanged). The same
seed gives the same sets in any process, on any executor.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import stats
from scipy.stats import qmc

from chassistune._rng import child_seed, make_rng
from chassistune.tuning.robust.spec import UncertainParam, check_sampler

SeedLike = int | np.random.SeedSequence | np.random.Generator
TRAINING, VALIDATION, SENSITIVITY = 0, 1, 2
"""Spawn keys of the scenario streams below the run's seed."""


@dataclass(frozen=True)
class ScenarioSet:
    """K parameter draws: `values[j, i]` is parameter `names[i]` in scenario j."""

    names: tuple[str, ...]
    values: np.ndarray

    def __len__(self) -> int:
        return int(self.values.shape[0])

    def rows(self) -> list[dict[str, float]]:
        """One {name: value} mapping per scenario (plain floats, ready as `--param` overrides)."""
        return [dict(zip(self.names, map(float, row), strict=True)) for row in self.values]


def scenario_stream(seed: SeedLike, key: int) -> np.random.Generator:
    """The Generator of one purpose (TRAINING, VALIDATION, SENSITIVITY): a child of the run's
    seed (spawn key appended), independent of the other purposes and of the optimizer's stream."""
    if isinstance(seed, np.random.Generator):
        parent = seed.bit_generator.seed_seq
        if not isinstance(parent, np.random.SeedSequence):
            raise TypeError("the run's Generator must be seeded from a SeedSequence")
        return make_rng(child_seed(parent, key))
    return make_rng(child_seed(seed, key))


def from_unit(params: Sequence[UncertainParam], u: np.ndarray) -> np.ndarray:
    """Map unit-cube points u (m, d) to parameter values (m, d), column i for params[i]."""
    u = np.asarray(u, dtype=np.float64)
    out = np.empty_like(u)
    for i, p in enumerate(params):
        if p.dist == "uniform":
            out[:, i] = p.lo + u[:, i] * (p.hi - p.lo)
        else:
            lo, hi = p.valid.clip_bounds()
            out[:, i] = np.clip(stats.norm.ppf(u[:, i], loc=p.mean, scale=p.sd), lo, hi)
    return out


def unit_points(d: int, k: int, sampler: str, rng: np.random.Generator) -> np.ndarray:
    """k points in [0, 1)^d: scrambled Sobol (k a power of two) or Latin hypercube."""
    check_sampler(sampler, k)
    if sampler == "sobol":
        return np.asarray(qmc.Sobol(d, scramble=True, rng=rng).random_base2(k.bit_length() - 1))
    return np.asarray(qmc.LatinHypercube(d, scramble=True, rng=rng).random(k))


def training_set(
    params: Sequence[UncertainParam], k: int, sampler: str, rng: np.random.Generator
) -> ScenarioSet:
    """The K training scenarios of a run (drawn once; every candidate sees them all); K = 0 is
    an empty set (tuning on the nominal plant)."""
    u = unit_points(len(params), k, sampler, rng) if k else np.zeros((0, len(params)))
    return ScenarioSet(tuple(p.name for p in params), from_unit(params, u))


def monte_carlo_set(
    params: Sequence[UncertainParam], n: int, rng: np.random.Generator
) -> ScenarioSet:
    """N independent draws (plain Monte Carlo: what the validation certificate assumes)."""
    u = rng.random((n, len(params)))
    return ScenarioSet(tuple(p.name for p in params), from_unit(params, u))
