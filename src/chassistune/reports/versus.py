"""Better / same / worse than the reference, as symbols a reader cannot take for a blank.

A verdict is read from the compared optimizer's side (lower is better): Wilcoxon rank-sum
(`stats.rank_sum`, alpha 0.05) of the reference's sample against the optimizer's. "Better" is
not claimed where both medians are worse than the default gains' value (`reports.baseline`):
beating a reference that lost to the untuned controller is no result.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from chassistune import stats
from chassistune.reports.baseline import LABEL, default_baseline
from chassistune.reports.tables import StudyData, quantities, values

BETTER = "✔ better"
SAME = "≈ same"
WORSE = "✘ worse"
BOTH_WORSE = "✘ both worse than the default gains"
REFERENCE = "reference"
_FROM_REFERENCE_SIGN = {"-": BETTER, "=": SAME, "+": WORSE}
VERDICTS = (BETTER, SAME, WORSE, BOTH_WORSE)


def verdict(reference: np.ndarray, other: np.ndarray) -> str:
    """BETTER, SAME or WORSE for `other` against `reference`; '' when a sample is empty."""
    if not (reference.size and other.size):
        return ""
    return _FROM_REFERENCE_SIGN[stats.rank_sum(reference, other).sign]


def verdict_of_sign(sign: str) -> str:
    """The verdict of a rank-sum sign read from the reference's side ('+': reference better)."""
    return _FROM_REFERENCE_SIGN.get(sign, "")


def claimed(word: str, reference_median: float, median: float, default: float) -> str:
    """`word`, except that BETTER becomes BOTH_WORSE where both medians are above the default
    gains' value (NaN `default`: no baseline, `word` unchanged)."""
    if word == BETTER and reference_median > default and median > default:
        return BOTH_WORSE
    return word


def metrics_by_optimizer(data: StudyData, scenario: str, reference: str) -> pd.DataFrame:
    """Rows: final cost and the key metrics; columns: the default gains' value (`default
    gains`, where the scenario has a controller), the reference's median (`<reference>
    (reference)`), then per other optimizer its median and its verdict (`<optimizer> vs
    reference`; BOTH_WORSE instead of BETTER where both medians are above the default gains')."""
    base = default_baseline(data, scenario)
    rows = []
    for q in quantities(data, scenario):
        ref = values(data.runs(scenario, reference), q)
        label = {"best_cost": "final cost", "nfev": "evaluations (nfev)"}.get(q, q)
        row: dict[str, object] = {"quantity": label}
        default = base.values[q] if base is not None else math.nan
        if base is not None:
            row[LABEL] = default
        ref_median = float(np.median(ref)) if ref.size else math.nan
        row[f"{reference} ({REFERENCE})"] = ref_median
        for opt in data.optimizers:
            if opt != reference:
                v = values(data.runs(scenario, opt), q)
                median = float(np.median(v)) if v.size else math.nan
                row[opt] = median
                row[f"{opt} vs {REFERENCE}"] = claimed(verdict(ref, v), ref_median, median, default)
        rows.append(row)
    return pd.DataFrame(rows)
