"""Pure random search (Brooks 1958; Rastrigin 1963): every candidate uniform in the box.

The floor of every comparison: it uses no information from the costs, so an optimizer that does
not beat it at equal evaluations has learnt nothing about the problem. One iteration is `pop_size`
independent uniform points; the best point ever sampled is the result.

Draw order per iteration: `uniform(pop_size)` (one `random((N, D))` draw).
"""

from __future__ import annotations

from chassistune.optimizers.base import Hyperparameters, Optimizer, Steps


class RandomSearch(Optimizer):
    """Uniform random sampling of the box."""

    name = "random-search"
    description = "Pure random search, uniform in the box (Brooks 1958): the floor"
    min_pop = 2
    defaults = Hyperparameters()

    def _steps(self) -> Steps:
        for _ in self.iterations():
            yield self.uniform(self.pop_size)
