"""The tuned gains of each optimizer: best run, median over seeds and every seed, with a flag on
each gain that ends within 1 % of its bound (the search box may be cutting the optimum off)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from chassistune.reports.tables import StudyData

NEAR_BOUND = 0.01
"""A gain within this fraction of its bound's range from the bound is flagged."""

LOWER, UPPER = "lower", "upper"


def bound_flag(value: float, lo: float, hi: float) -> str:
    """'lower' or 'upper' when `value` lies within NEAR_BOUND of (hi - lo) of that bound."""
    if not math.isfinite(value):
        return ""
    tol = NEAR_BOUND * (hi - lo)
    if value <= lo + tol:
        return LOWER
    if value >= hi - tol:
        return UPPER
    return ""


def gains_table(data: StudyData, scenario: str) -> pd.DataFrame:
    """Rows per optimizer: `best` (its lowest-cost run), `median` (per gain over seeds), then
    `seed N` for each completed run; columns: optimizer, row, cost, each gain and, per gain,
    `<gain> at bound` ('lower', 'upper' or '')."""
    runs = data.runs(scenario)
    if not runs:
        return pd.DataFrame()
    bounds = runs[0].spec.bounds
    rows = []
    for opt in data.optimizers:
        mine = data.runs(scenario, opt)
        if not mine:
            continue
        best = min(mine, key=lambda r: (r.best_cost, r.spec.seed))
        picked = [("best", best.best_cost, best.best_gains)]
        median = {g: float(np.median([r.best_gains[g] for r in mine])) for g in bounds}
        picked.append(("median", float(np.median([r.best_cost for r in mine])), median))
        picked += [(f"seed {r.spec.seed}", r.best_cost, r.best_gains) for r in mine]
        for label, cost, gains in picked:
            row: dict[str, object] = {"optimizer": opt, "row": label, "cost": cost}
            row.update({g: gains[g] for g in bounds})
            row.update({f"{g} at bound": bound_flag(gains[g], *bounds[g]) for g in bounds})
            rows.append(row)
    return pd.DataFrame(rows)
