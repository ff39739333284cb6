"""The centre-bias test (Kudela 2022): each optimizer on F1-F23 as published and with the optimum
moved to a random point of the box (`benchmarks.shifted`), at equal evaluations.

The quality of a run is its gap to the known minimum, floored at `GAP_FLOOR` (COCO's final
target, 1e-8: below it a run has solved the problem and further digits say nothing). The loss of
an optimizer on a function is log10(median shifted gap) - log10(median plain gap), in orders of
magnitude: > 0 when moving the optimum off its published place hurts. Seed s runs the optimizer
with seed s, draws F7's noise from child 0 of s and the moved optimum from child 1 of s, as
`chassistune optimize --seed s [--shift]` does.

Verdict per optimizer, from the median loss over the functions whose published optimum is the
centre of the box (F1-F4, F6, F7, F9-F11): "centre-biased" at 1 order of magnitude or more,
"no centre bias" below 0.5, "mild" between.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from chassistune._rng import child_seed, make_rng
from chassistune.benchmarks.functions import get
from chassistune.benchmarks.shifted import shifted
from chassistune.optimizers.minimize import minimize

GAP_FLOOR = 1e-8
CENTRED = ("F1", "F2", "F3", "F4", "F6", "F7", "F9", "F10", "F11")
"""Functions whose published minimizer is the centre of the box."""
BIASED, MILD = 1.0, 0.5


@dataclass(frozen=True)
class LossRow:
    """One optimizer on one function: median gaps (floored) and the loss in orders."""

    optimizer: str
    function: str
    plain_gap: float
    shifted_gap: float

    @property
    def loss(self) -> float:
        return math.log10(self.shifted_gap) - math.log10(self.plain_gap)


def gap(
    optimizer: str, function: str, dim: int | None, seed: int, evals: int, pop: int, shift: bool
) -> float:
    """One run's gap to the minimum, floored at `GAP_FLOOR`."""
    fn = get(function)
    target = shifted(function, dim, child_seed(seed, 1)) if shift else fn
    noise = make_rng(child_seed(seed, 0)) if fn.noisy else None
    res = minimize(
        lambda x: target(x, noise),
        fn.bounds(dim),
        method=optimizer,
        pop_size=pop,
        max_evals=evals,
        seed=seed,
    )
    return max(res.fun - fn.f_min(dim), GAP_FLOOR)


def loss_table(
    optimizers: Sequence[str],
    functions: Sequence[str],
    seeds: int,
    evals: int,
    pop: int = 30,
    dim: int = 10,
) -> list[LossRow]:
    """Every optimizer on every function, plain and shifted, `seeds` runs each; scalable
    functions (F1-F13) in dimension `dim`, the others in their own."""
    rows = []
    for opt in optimizers:
        for name in functions:
            d = dim if get(name).scalable else None
            medians = [
                float(np.median([gap(opt, name, d, s, evals, pop, shift) for s in range(seeds)]))
                for shift in (False, True)
            ]
            rows.append(LossRow(opt.lower(), get(name).name, *medians))
    return rows


def verdict(rows: Sequence[LossRow], optimizer: str) -> tuple[float, str]:
    """The optimizer's median loss over the centred functions and its verdict."""
    losses = [r.loss for r in rows if r.optimizer == optimizer and r.function in CENTRED]
    if not losses:
        return math.nan, "no centred function run"
    median = float(np.median(losses))
    if median >= BIASED:
        return median, "centre-biased"
    return median, "no centre bias" if median < MILD else "mild"


def markdown(rows: Sequence[LossRow]) -> str:
    """The loss table (optimizers x functions, orders of magnitude) and the verdicts."""
    optimizers = list(dict.fromkeys(r.optimizer for r in rows))
    functions = list(dict.fromkeys(r.function for r in rows))
    cell = {(r.optimizer, r.function): r.loss for r in rows}
    lines = [
        "| optimizer | " + " | ".join(functions) + " | median (centred) | verdict |",
        "| --- |" + " --- |" * (len(functions) + 2),
    ]
    for opt in optimizers:
        median, word = verdict(rows, opt)
        losses = " | ".join(f"{cell[(opt, f)]:+.1f}" if (opt, f) in cell else "" for f in functions)
        lines.append(f"| {opt} | {losses} | {median:+.1f} | {word} |")
    return "\n".join(lines)
