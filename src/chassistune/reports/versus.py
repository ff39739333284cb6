"""Better / same / worse than the reference, as symbols a reader cannot take for a blank.

A verdict is read from the compared optimizer's side (lower is better): Wilcoxon rank-sum
(`stats.rank_sum`, alpha 0.05) of the reference's sample against the optimizer's.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from chassistune import stats
from chassistune.reports.tables import StudyData, quantities, values

BETTER = "✔ better"
SAME = "≈ same"
WORSE = "✘ worse"
REFERENCE = "reference"
_FROM_REFERENCE_SIGN = {"-": BETTER, "=": SAME, "+": WORSE}
VERDICTS = (BETTER, SAME, WORSE)


def verdict(reference: np.ndarray, other: np.ndarray) -> str:
    """BETTER, SAME or WORSE for `other` against `reference`; '' when a sample is empty."""
    if not (reference.size and other.size):
        return ""
    return _FROM_REFERENCE_SIGN[stats.rank_sum(reference, other).sign]


def verdict_of_sign(sign: str) -> str:
    """The verdict of a rank-sum sign read from the reference's side ('+': reference better)."""
    return _FROM_REFERENCE_SIGN.get(sign, "")


def metrics_by_optimizer(data: StudyData, scenario: str, reference: str) -> pd.DataFrame:
    """Rows: final cost and the key metrics; columns: the reference's median
    (`<reference> (reference)`), then per other optimizer its median and its verdict
    (`<optimizer> vs reference`)."""
    rows = []
    for q in quantities(data, scenario):
        ref = values(data.runs(scenario, reference), q)
        label = {"best_cost": "final cost", "nfev": "evaluations (nfev)"}.get(q, q)
        row: dict[str, object] = {"quantity": label}
        row[f"{reference} ({REFERENCE})"] = float(np.median(ref)) if ref.size else math.nan
        for opt in data.optimizers:
            if opt != reference:
                v = values(data.runs(scenario, opt), q)
                row[opt] = float(np.median(v)) if v.size else math.nan
                row[f"{opt} vs {REFERENCE}"] = verdict(ref, v)
        rows.append(row)
    return pd.DataFrame(rows)
