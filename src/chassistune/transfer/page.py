"""The transfer study's page (docs/transfer.md): per source, a table of its cells (how far the
paper's gains stop over the adhesion bound there, how much that loses against the paper's own
plant, how much re-tuning on the cell recovers; R13-H utilisation, locked time, split-mu yaw)
and a heatmap of every cell and road."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from chassistune._io import write_text
from chassistune.plots.league_cases import CaseGrid, plot_league_cases
from chassistune.transfer.cells import RELAXATION_LENGTH_M, Cell, Source
from chassistune.transfer.plan import Setting
from chassistune.transfer.score import GAINS, NOT_AVAILABLE

SCORES_CSV = "transfer_scores.csv"
PAGE = "transfer.md"

TIRE_TEXT = {
    "road": "road",
    "mf": "MF",
    "mf+lag": f"MF + lag {RELAXATION_LENGTH_M:g} m",
}
"""A tire's name in the tables."""


def figure_name(source: Source) -> str:
    """The heatmap file of a source."""
    return f"transfer_{source.study}_{source.cell}.png"


def summary(rows: pd.DataFrame) -> dict[str, float]:
    """One cell's scores with one gain set: the mean distance ratio over its roads (NaN when a
    road ends without a stop), the mean R13-H utilisation, the locked time summed over the roads
    and the split-mu peak yaw rate."""
    split = rows[rows.road == "split-mu"].yaw_rate_peak_1s_rad_s
    return {
        "distance_ratio": float(rows.distance_ratio.mean(skipna=False)),
        "r13h_epsilon": float(rows.r13h_epsilon.mean(skipna=False)),
        "locked_time_s": float(rows.locked_time_s.sum(min_count=1)),
        "yaw": float(split.iloc[0]) if len(split) else math.nan,
    }


def _of(scores: pd.DataFrame, cell: Cell, gains: str) -> pd.DataFrame:
    s = scores[(scores.source == cell.source.key) & (scores.target == cell.target)]
    return s[(s.tire == cell.tire) & (s.ecu == cell.ecu) & (s.gains == gains)]


def _fmt(x: float, digits: int = 3) -> str:
    return "-" if not np.isfinite(x) else f"{x:.{digits}f}"


def source_table(scores: pd.DataFrame, setting: Setting, source: Source) -> pd.DataFrame:
    """Per cell: the paper's gains' and the re-tuned gains' summaries, the loss (the paper's
    gains' distance ratio there minus on the home plant) and the recovery (minus the re-tuned
    gains'); `status` the cell's `not available` line or empty."""
    cells = setting.cells(source)
    home = next(c for c in cells if c.is_home)
    base = summary(_of(scores, home, "paper"))["distance_ratio"]
    out = []
    for c in cells:
        paper_rows = _of(scores, c, "paper")
        status = str(paper_rows.status.iloc[0]) if len(paper_rows) else ""
        row: dict[str, object] = {
            "target": c.target,
            "tire": c.tire,
            "ecu": c.ecu,
            "status": status if status.startswith(NOT_AVAILABLE) else "",
        }
        sums: dict[str, float] = {}
        for g in GAINS:
            rows = _of(scores, c, g)
            s = summary(rows) if len(rows) else dict.fromkeys(summary(paper_rows), math.nan)
            sums |= {f"{k} {g}": v for k, v in s.items()}
        sums["loss"] = sums["distance_ratio paper"] - base
        sums["recovered"] = sums["distance_ratio paper"] - sums["distance_ratio re-tuned"]
        row |= sums
        out.append(row)
    return pd.DataFrame(out)


def _table_md(table: pd.DataFrame, vehicle: bool) -> str:
    head = [
        "target",
        "tire",
        "ECU",
        "distance / bound: paper gains",
        "re-tuned",
        "loss",
        "recovered",
        "R13-H eps: paper / re-tuned" if not vehicle else "split-mu yaw [rad/s]: paper / re-tuned",
        "locked [s]: paper / re-tuned",
    ]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for _, r in table.iterrows():
        first = [str(r.target), TIRE_TEXT[str(r.tire)], str(r.ecu)]
        if r.status:
            cells = [*first, str(r.status), *([""] * (len(head) - 4))]
        else:
            third = "yaw" if vehicle else "r13h_epsilon"
            cells = [
                *first,
                _fmt(r["distance_ratio paper"]),
                _fmt(r["distance_ratio re-tuned"]),
                _fmt(r["loss"]),
                _fmt(r["recovered"]),
                f"{_fmt(r[f'{third} paper'])} / {_fmt(r[f'{third} re-tuned'])}",
                f"{_fmt(r['locked_time_s paper'])} / {_fmt(r['locked_time_s re-tuned'])}",
            ]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def source_grid(scores: pd.DataFrame, setting: Setting, source: Source) -> CaseGrid:
    """The source's runnable cells (rows) by road and gain set (columns): distance ratios."""
    runnable = [
        c for c in setting.cells(source) if len(_of(scores, c, "paper").distance_ratio.dropna())
    ]
    columns = [(road, g) for road in source.roads for g in GAINS]
    values = np.full((len(runnable), len(columns)), np.nan)
    for i, c in enumerate(runnable):
        for j, (road, g) in enumerate(columns):
            r = _of(scores, c, g)
            r = r[r.road == road]
            if len(r):
                values[i, j] = float(r.distance_ratio.iloc[0])
    return CaseGrid(
        [f"{c.target}, {TIRE_TEXT[c.tire]}, {c.ecu}" for c in runnable],
        [f"{road} {g}" for road, g in columns],
        values,
    )


def write_page(
    out_dir: Path, setting: Setting, scores: pd.DataFrame, budget_text: str, run_text: str
) -> Path:
    """Write the scores (CSV), a heatmap per source and the page; returns the page's path."""
    scores.to_csv(out_dir / SCORES_CSV, index=False)
    parts = [
        "# Transfer: the papers' tuned ABS controllers on real cars",
        "",
        "Each controller as its paper's reproduction tuned it (the median run of the paper's "
        "optimizer), run unchanged on its paper plant and on each real car (the road it was "
        "tuned on; CommonRoad's PAC2002 Magic Formula tire scaled to that road, on the vehicle "
        "Project Chrono's 185/80 R14 PAC2002 file at a 0.5 ms step (CommonRoad's set has no "
        "lateral load law, PKY2); the same with "
        f"the lagged slip, sigma = {RELAXATION_LENGTH_M:g} m; the ideal and the realistic ECU), "
        f"then re-tuned on each car and variant. {budget_text} {run_text}",
        "",
        "Distance / bound: the stop distance over the road's adhesion bound, the mean over the "
        "source's roads (1 is the bound; lower is better; - where a road ends without a stop). "
        "Loss: the paper's gains' ratio there minus on the paper plant; recovered: minus the "
        "re-tuned gains'. R13-H eps: UN R13-H adhesion utilisation, the mean over the roads; "
        "locked: a wheel's locked time summed over the roads (vehicle: the four wheels'); "
        "split-mu yaw: the peak yaw rate in the first second on split-mu.",
    ]
    for source in setting.sources:
        table = source_table(scores, setting, source)
        fig = figure_name(source)
        plot_league_cases(
            {source.key: source_grid(scores, setting, source)},
            str(out_dir / fig),
            "each gain set's run",
        )
        parts += [
            "",
            f"## {source.key}: {source.controller} on {source.plant}",
            "",
            f"Tuned on {source.preset}, roads {', '.join(source.roads)}, by {source.optimizer}.",
            "",
            _table_md(table, source.plant == "abs-vehicle"),
            "",
            f"![{source.key}: every cell and road]({fig})",
        ]
    path = out_dir / PAGE
    write_text(path, "\n".join(parts) + "\n")
    return path
