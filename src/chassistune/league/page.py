"""The league's page (docs/league.md, "The page"): per plant, the laws ranked by their median
league score over seeds (the mean stop distance over the adhesion bound on the held-out cases),
one figure of every law on every case, and each law's traces on the plant's hardest case."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from chassistune._io import write_text
from chassistune.league.cases import OBJECTIVE, PLANTS
from chassistune.league.plan import Setting, knowledge
from chassistune.league.score import SCORES, Tuned
from chassistune.plots.league_cases import CaseGrid, plot_league_cases
from chassistune.plots.overlay import Line, plot_overlay
from chassistune.scenarios.registry import get_plant
from chassistune.stats import median_ci

SCORES_CSV = "league_scores.csv"
PAGE = "league.md"
HEATMAP = "league_cases.png"

TRACE_PANELS = {
    "abs-wheel": (
        ("slip", "slip [-]"),
        ("vehicle_speed_m_s", "speed [m/s]"),
        ("pressure", "pressure [unit]"),
        ("distance_m", "distance [m]"),
    ),
    "abs-vehicle": (
        ("slip_fl", "front-left slip [-]"),
        ("speed_m_s", "speed [m/s]"),
        ("yaw_rate_rad_s", "yaw rate [rad/s]"),
        ("distance_m", "distance [m]"),
    ),
}
"""The panels of a plant's trace figure."""

KNOWING = {
    "fixed": "Road knowledge (column `target slip`): a law that regulates a target slip tunes one "
    "target for every road (and all four wheels) with its gains (`fixed`: no vehicle knows its "
    "road's peak).",
    "oracle": "Road knowledge (column `target slip`): every law that regulates a target slip is "
    "handed the road's optimal slip (`oracle`, the papers' setting).",
}
"""What the page says of the laws' road knowledge, per league setting."""


def league_scores(scores: pd.DataFrame) -> pd.DataFrame:
    """Per (plant, law, seed): the mean distance ratio over the held-out cases (`league`) and
    how many cases did not end in a stop (`failed`)."""
    g = scores.groupby(["plant", "law", "seed"], sort=False)[OBJECTIVE]
    return pd.DataFrame({"league": g.mean(), "failed": g.apply(lambda v: int(v.isna().sum()))})


def ranking(scores: pd.DataFrame, plant: str) -> pd.DataFrame:
    """The plant's laws ranked: fewest failed cases, then the lowest median league score; with
    the score's median over seeds and its 95 % percentile-bootstrap interval (`stats.median_ci`;
    none for a law scored once) and each case's median distance ratio."""
    per_seed = league_scores(scores[scores.plant == plant]).reset_index()
    rows = []
    for law, s in per_seed.groupby("law", sort=False):
        ok = s.league.dropna()
        lo, hi = median_ci(ok.to_numpy()) if len(ok) else (math.nan, math.nan)
        rows.append(
            {
                "law": law,
                "seeds": len(s) if s.seed.max() >= 0 else 0,
                "failed": int(s.failed.sum()),
                "median": float(ok.median()) if len(ok) else math.nan,
                "ci_low": lo,
                "ci_high": hi,
            }
        )
    table = pd.DataFrame(rows).sort_values(["failed", "median"], na_position="last")
    cases = scores[scores.plant == plant].pivot_table(
        index="law", columns="case", values=OBJECTIVE, aggfunc="median", sort=False
    )
    table = table.join(cases, on="law")
    table.insert(0, "rank", range(1, len(table) + 1))
    return table.reset_index(drop=True)


def hardest_case(scores: pd.DataFrame, plant: str) -> str:
    """The plant's case with the largest median distance ratio over its laws and seeds."""
    s = scores[scores.plant == plant]
    return str(s.groupby("case", sort=False)[OBJECTIVE].median().idxmax())


def _fmt(x: float, digits: int = 3) -> str:
    return "-" if not np.isfinite(x) else f"{x:.{digits}f}"


def _table_md(table: pd.DataFrame, cases: list[str], setting: Setting) -> str:
    head = [
        "rank",
        "law",
        "target slip",
        "seeds",
        "league score: median [95 % CI]",
        "failed",
        *cases,
    ]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for _, r in table.iterrows():
        cells = [
            str(r["rank"]),
            str(r["law"]),
            knowledge(str(r["law"]), setting),
            str(r["seeds"]) if r["seeds"] else "untuned",
            f"{_fmt(r['median'])} [{_fmt(r['ci_low'])}, {_fmt(r['ci_high'])}]",
            str(r["failed"]),
            *(_fmt(float(r[c])) for c in cases),
        ]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _other_scores_md(scores: pd.DataFrame, plant: str, order: list[str]) -> str:
    s = scores[scores.plant == plant]
    names = [n for n in SCORES if n != OBJECTIVE and s[n].notna().any()]
    med = s.groupby(["law", "case"], sort=False)[names].median()
    head = ["law", "case", *names]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for law in order:
        for case in dict.fromkeys(s.case):
            row = med.loc[(law, case)]
            lines.append(
                "| " + " | ".join([law, case, *(_fmt(float(row[n])) for n in names)]) + " |"
            )
    return "\n".join(lines)


def case_grid(scores: pd.DataFrame, plant: str) -> CaseGrid:
    """The plant's laws (ranked) by cases, each cell the median distance ratio."""
    table = ranking(scores, plant)
    cases = list(dict.fromkeys(scores[scores.plant == plant].case))
    return CaseGrid(list(table.law), cases, table[cases].to_numpy(dtype=float))


def median_seed(scores: pd.DataFrame, plant: str, law: str) -> int:
    """The seed whose league score is the median one of the law's seeds (lower middle)."""
    per_seed = league_scores(scores[(scores.plant == plant) & (scores.law == law)]).reset_index()
    ordered = per_seed.sort_values(["failed", "league"], na_position="last").reset_index()
    return int(ordered.seed[(len(ordered) - 1) // 2])


def plot_hardest(
    scores: pd.DataFrame,
    tuned: list[Tuned],
    setting: Setting,
    plant: str,
    case_name: str,
    path: Path,
) -> None:
    """Every law of the plant (its median seed) on the hardest case, overlaid."""
    from chassistune.league.score import case_params

    lp = PLANTS[plant]
    case = next(c for c in lp.held_out if c.name == case_name)
    lines = []
    for law in ranking(scores, plant).law:
        seed = median_seed(scores, plant, law)
        t = next(t for t in tuned if t.plant == plant and t.law == law and t.seed == seed)
        sc = get_plant(plant).scenario(
            lp.preset, case.road, law, case_params(lp, case, law, setting)
        )
        gains = np.array([[float(t.gains[n]) for n in sc.gain_names]]).reshape(1, -1)
        tr = sc.trace(gains)
        lines.append(
            Line(law, np.asarray(tr.signals["time_s"]), tr.signals, baseline=law == "none")
        )
    plot_overlay(
        TRACE_PANELS[plant], lines, str(path), f"{plant}, {case_name}: each law's median seed"
    )


def write_page(
    out_dir: Path, setting: Setting, scores: pd.DataFrame, tuned: list[Tuned], run_time_s: float
) -> Path:
    """Write the scores (CSV), the figures and the page; returns the page's path."""
    scores.to_csv(out_dir / SCORES_CSV, index=False)
    plot_league_cases({p: case_grid(scores, p) for p in setting.plants}, str(out_dir / HEATMAP))
    b = setting.budget
    parts = [
        "# League: the ABS laws tuned alike, scored on cases they were not tuned on",
        "",
        f"Optimizer {setting.optimizer}, {b.evaluations} evaluations (population {b.pop_size}) "
        f"per tuning run, {b.seeds} seeds per law (root seed {setting.seed}); objective: the "
        "mean over the training roads of the stop distance over its adhesion bound plus the "
        f"lock penalty. {KNOWING[setting.road_knowledge]} The tuning runs took "
        f"{run_time_s:.0f} s together (each run's wall time, summed).",
        "",
        f"![every law on every case]({HEATMAP})",
    ]
    for plant in setting.plants:
        lp = PLANTS[plant]
        table = ranking(scores, plant)
        cases = [c.name for c in lp.held_out]
        hard = hardest_case(scores, plant)
        fig = f"league_traces_{plant}.png"
        plot_hardest(scores, tuned, setting, plant, hard, out_dir / fig)
        parts += [
            "",
            f"## {plant}",
            "",
            f"Mode: {lp.mode}. Preset {lp.preset}. Trained on {', '.join(lp.training)}.",
            "League score: the mean over the held-out cases of the stop distance over the "
            "adhesion bound (1 is the bound; lower is better), per seed; a case without a "
            "stop counts as failed and ranks the law below those with fewer failures.",
            "",
            _table_md(table, cases, setting),
            "",
            "Other scores (median over seeds; - where the plant or mode has none):",
            "",
            _other_scores_md(scores, plant, list(table.law)),
            "",
            f"Hardest case: **{hard}** (largest median distance ratio).",
            "",
            f"![traces on {hard}]({fig})",
        ]
    path = out_dir / PAGE
    write_text(path, "\n".join(parts) + "\n")
    return path
