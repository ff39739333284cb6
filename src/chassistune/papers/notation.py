"""How to read the reproduction page: its marks, its test notation and the words that stand in
empty cells, explained once (the first section's last table)."""

from __future__ import annotations

import pandas as pd

from chassistune.papers.common import NEVER_SETTLES, VERDICT_MARKS, Table
from chassistune.reports.html import FLAG

NOT_PRINTED = "not printed"
"""An empty cell of a paper's column: the paper prints no value there."""
NO_VALUE = "–"
"""An empty cell whose table names no reason (the table's caption says why)."""

NOTATION = (
    (
        " / ".join(f"{m} {w}" for w, m in VERDICT_MARKS.items()),
        "the verdict on a claim; the evidence column gives the numbers and tests behind it",
    ),
    (
        "rank-sum + / - / = (p = 0.33)",
        "Wilcoxon rank-sum test of the claimed entry's runs against another entry's runs over the "
        "seeds: + significantly lower (better), - significantly higher, = no significant "
        "difference at alpha 0.05; p is the two-sided p-value",
    ),
    (
        "signed-rank + / - / = (p = 0.0078)",
        "tuned runs against a fixed value (an untuned baseline): Wilcoxon signed-rank test of the "
        "runs about it, signs as above",
    ),
    (
        "fixed values (single values)",
        "no test was possible: both entries are one value each (an untuned default is one "
        "simulation); the order is that of the values alone",
    ),
    (
        "smallest attainable p",
        "the smallest p-value the sample sizes allow: at or above 0.05 no difference can be "
        "significant, and the claim is undecided at this budget",
    ),
    ("median run", "of an optimizer's seeds, the one whose final cost is the (lower) median"),
    (
        FLAG,
        "after a distance or time: it is shorter than the physical adhesion bound of its speed "
        "and road",
    ),
    ("paper / bound, ours / bound", "a stopping distance over that bound (below 1: impossible)"),
    (
        "paper time / time bound, ours time / time bound",
        "a braking time over the time bound (v0 - v_stop)/(mu_peak g)",
    ),
    (NOT_PRINTED, "an empty cell of a paper's column: the paper prints no value there"),
    ("untuned", "the catalogue defaults: no seed, no tuning cost"),
    (
        NEVER_SETTLES,
        "the slip never stays within 0.05 of its target above 2 m/s (counted as infinite, inf, "
        "by the settling verdicts)",
    ),
    (NO_VALUE, "no value; the table's caption says why"),
)
"""(notation, meaning) of every mark and abbreviation the page uses."""


def notation_table() -> Table:
    """The page's notation, one row per mark."""
    return Table(
        "notation",
        "How to read the tables",
        pd.DataFrame(NOTATION, columns=["notation", "meaning"]),
        "Explained once here for every table of the page.",
    )
