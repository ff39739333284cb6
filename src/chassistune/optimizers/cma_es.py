"""IPOP-CMA-ES on the `cmaes` package (Hansen 2016 tutorial; IPOP: Auger & Hansen 2005).

The reference optimizer of the field: the covariance-matrix-adapting evolution strategy of the
`cmaes` package (`cmaes.CMA`), restarted with a population multiplied by `inc_popsize` whenever
the package's own stopping test (`should_stop`) fires. One iteration is one generation of
lambda candidates; the first generation has lambda = `pop_size`.

Each (re)start draws, in this order, an integer seed for the package's legacy
`numpy.random.RandomState` (`rng.integers(2**32)`: the package takes nothing else, and it is the
one draw of the project not made from a Generator) and the mean, uniform in the box
(`self.uniform(1)`). The initial covariance is sigma0^2 diag((hi - lo)^2), sigma0 = `sigma0`:
every coordinate starts with a spread of the same fraction of its range.

Bounds are the package's: a candidate outside the box is resampled (up to 100 times) and then
clipped by the package, so every candidate is inside the box as sampled and the base's bounds
repair is bypassed (`_accept`): the points evaluated are exactly those the package proposed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from cmaes import CMA

from chassistune.optimizers.base import FloatArray, Hyperparameters, Optimizer, Steps

SEED_RANGE = 2**32
"""`numpy.random.RandomState` takes seeds in [0, 2**32)."""


@dataclass(frozen=True)
class CMAESHyper(Hyperparameters):
    """IPOP-CMA-ES hyperparameters."""

    sigma0: float = 0.2  # initial step size as a fraction of each coordinate's range
    inc_popsize: int = 2  # population factor at each restart (IPOP)

    def __post_init__(self) -> None:
        self.check(0 < self.sigma0 <= 1, "sigma0", f"expected 0 < sigma0 <= 1, got {self.sigma0}")
        self.check(
            isinstance(self.inc_popsize, int) and self.inc_popsize >= 1,
            "inc_popsize",
            f"expected an integer >= 1, got {self.inc_popsize!r}",
        )


class CMAES(Optimizer):
    """IPOP-CMA-ES, one `cmaes.CMA` per (re)start."""

    name = "cma-es"
    description = (
        "IPOP-CMA-ES on the cmaes package, sigma0 0.2 of the range, population x2 per restart "
        "(Hansen 2016; Auger & Hansen 2005)"
    )
    min_pop = 4  # below 4 the package's rank-mu rate is 0 and its weights divide by it
    defaults = CMAESHyper()
    hyper: CMAESHyper

    def _accept(self, batch: FloatArray) -> None:
        self._pending = batch  # the package keeps its candidates in the box

    def _start(self, popsize: int) -> CMA:
        seed = int(self.rng.integers(SEED_RANGE))
        mean = np.clip(self.uniform(1)[0], self.lo, self.hi)  # lo + r (hi - lo) may round past hi
        width = self.hi - self.lo
        return CMA(
            mean=mean,
            sigma=self.hyper.sigma0,
            bounds=np.stack([self.lo, self.hi], axis=1),
            seed=seed,
            population_size=popsize,
            cov=np.diag(width * width),
        )

    def _steps(self) -> Steps:
        popsize = self.pop_size
        es = self._start(popsize)
        restarts = 0
        self.diagnostics.update(restarts=0, final_popsize=popsize)
        for _ in self.iterations():
            x = np.array([es.ask() for _ in range(popsize)])
            f = yield x
            es.tell(list(zip(x, f.tolist(), strict=True)))
            if es.should_stop():
                popsize *= self.hyper.inc_popsize
                restarts += 1
                es = self._start(popsize)
                self.diagnostics.update(restarts=restarts, final_popsize=popsize)
