"""The rule-base data model: variables with fuzzy sets, and Mamdani rules as rows of set names.

A rule base is data. Its dictionary form (`RuleBase.as_dict`) is the `fuzzy show --json` output of
design.md 7 and has the structure of the TOML files (`schema.rulebase_from_dict` reads it back):
`inputs` and `outputs` each a list of {name, universe [lo, hi], sets [{name, shape, params}]},
`rules` each a list of the input set names in input order then the output set names in output
order, and `operators` {and: min, aggregate: max, defuzzify: centroid}.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike, NDArray

from chassistune.fuzzy.sets import FuzzySet

OPERATORS: dict[str, str] = {"and": "min", "aggregate": "max", "defuzzify": "centroid"}
"""The only operator set implemented: Mamdani min/max with min implication and centroid."""


@dataclass(frozen=True)
class Variable:
    """A linguistic variable: a name, a universe [lo, hi] and its fuzzy sets."""

    name: str
    universe: tuple[float, float]
    sets: tuple[FuzzySet, ...]

    @property
    def set_names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.sets)

    @property
    def span(self) -> float:
        return self.universe[1] - self.universe[0]

    def clip(self, x: ArrayLike) -> NDArray[np.float64]:
        """Clip crisp values to the universe, as scikit-fuzzy does with `clip_to_bounds`."""
        return np.clip(np.asarray(x, dtype=np.float64), self.universe[0], self.universe[1])

    def memberships(self, x: ArrayLike) -> NDArray[np.float64]:
        """Membership of the clipped values in every set: shape x.shape + (n_sets,)."""
        xc = self.clip(x)
        return np.stack([s.mf(xc) for s in self.sets], axis=-1)

    def crossings(self) -> list[float]:
        """Abscissae where two sets cross (bracketed on a dense grid, then bisected)."""
        x = np.linspace(self.universe[0], self.universe[1], 20001)
        out: list[float] = []
        for i, si in enumerate(self.sets):
            for sj in self.sets[i + 1 :]:
                diff = si.mf(x) - sj.mf(x)
                nz = np.flatnonzero(diff)
                for f in np.flatnonzero(np.sign(diff[nz[:-1]]) != np.sign(diff[nz[1:]])):
                    left, right = float(x[nz[f]]), float(x[nz[f + 1]])
                    positive_left = diff[nz[f]] > 0
                    for _ in range(100):
                        mid = 0.5 * (left + right)
                        if mid in (left, right):
                            break
                        if (float(si.mf(mid) - sj.mf(mid)) > 0) == positive_left:
                            left = mid
                        else:
                            right = mid
                    out.append(0.5 * (left + right))
        return out

    def as_dict(self) -> dict[str, object]:
        return {
            "name": self.name,
            "universe": list(self.universe),
            "sets": [s.as_dict() for s in self.sets],
        }


@dataclass(frozen=True)
class RuleBase:
    """A Mamdani rule base. Build it with `load_rulebase` or `rulebase_from_dict` (validated)."""

    name: str
    inputs: tuple[Variable, ...]
    outputs: tuple[Variable, ...]
    rules: tuple[tuple[str, ...], ...]
    description: str = field(default="", compare=False)

    @property
    def input_names(self) -> tuple[str, ...]:
        return tuple(v.name for v in self.inputs)

    @property
    def output_names(self) -> tuple[str, ...]:
        return tuple(v.name for v in self.outputs)

    @cached_property
    def rule_indices(self) -> NDArray[np.intp]:
        """Rules as set indices, shape (n_rules, n_inputs + n_outputs)."""
        variables = self.inputs + self.outputs
        return np.array(
            [
                [v.set_names.index(s) for v, s in zip(variables, rule, strict=True)]
                for rule in self.rules
            ],
            dtype=np.intp,
        )

    def as_dict(self) -> dict[str, object]:
        """The `fuzzy show --json` description (design.md 7)."""
        return {
            "inputs": [v.as_dict() for v in self.inputs],
            "outputs": [v.as_dict() for v in self.outputs],
            "rules": [list(r) for r in self.rules],
            "operators": dict(OPERATORS),
        }
