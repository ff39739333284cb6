"""What every paper's reproduction produces: a section (setting, budgets, tables, figures) and a
verdict per claim; and the helpers the four share (median run, ranking verdicts, slip settling).

Verdict words: `holds`, `holds in ranking only` (the order the paper claims, without
a significant difference or with a much smaller effect), `does not hold`, `cannot be checked`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from chassistune import stats
from chassistune.reports.tables import StudyData
from chassistune.studies.spec import StudyConfig
from chassistune.studies.store import RunRecord

if TYPE_CHECKING:
    from chassistune.scenarios.base import Trace

HOLDS = "holds"
RANKING_ONLY = "holds in ranking only"
FAILS = "does not hold"
UNCHECKED = "cannot be checked"
VERDICTS = (HOLDS, RANKING_ONLY, FAILS, UNCHECKED)
VERDICT_MARKS = {HOLDS: "✔", RANKING_ONLY: "≈", FAILS: "✘", UNCHECKED: "?"}
"""Shown before each verdict on the page (the same symbols as the study report's better /
same / worse), so a verdict cannot be taken for a blank or misread."""
BOUND_RATIOS = ("paper / bound", "published / bound")
"""Columns of a published distance over its adhesion bound: below 1 is flagged on the page."""

NEVER_SETTLES = "never settles"
"""Stands for a settling time `settle_time_s` did not find (NaN), in tables and evidence."""
SLIP_BAND = 0.05
"""A slip has settled once it stays within this of its target (absolute slip)."""
SETTLE_MIN_SPEED_M_S = 2.0
"""Samples below this vehicle speed are ignored by the settling time (slip is singular near
standstill and the ABS cuts out)."""


@dataclass(frozen=True)
class Verdict:
    """One claim of a paper, our verdict and the evidence (numbers, test, p-value)."""

    paper: str
    claim: str
    verdict: str
    evidence: str

    def __post_init__(self) -> None:
        if self.verdict not in VERDICTS:
            raise ValueError(f"unknown verdict {self.verdict!r}")


@dataclass(frozen=True)
class Table:
    """A report table: `name` is its CSV file's stem; `quoted` names the columns holding a
    paper's published numbers (shown on the page in full, exactly as published)."""

    name: str
    title: str
    frame: pd.DataFrame
    caption: str = ""
    quoted: tuple[str, ...] = ()
    missing: Mapping[str, str] = field(default_factory=dict)
    """Column -> why its empty cells are empty (shown on the page in place of a blank)."""


@dataclass(frozen=True)
class Figure:
    """A report figure drawn from our runs (a PNG file)."""

    name: str
    title: str
    path: Path
    caption: str = ""


@dataclass
class PaperSection:
    """One paper's part of the report."""

    key: str
    title: str
    setting: list[tuple[str, str]]
    tables: list[Table] = field(default_factory=list)
    figures: list[Figure] = field(default_factory=list)
    verdicts: list[Verdict] = field(default_factory=list)
    bounds: list[BoundCheck] = field(default_factory=list)


@dataclass(frozen=True)
class Context:
    """Where a paper writes its figures, its studies' data and configs, and the run kind."""

    figures_dir: Path
    studies: Mapping[str, StudyData]
    configs: Mapping[str, tuple[StudyConfig, StudyConfig]]
    quick: bool

    def figure(self, paper: str, name: str) -> Path:
        """The PNG path of figure `name` of `paper` (its folder created)."""
        self.figures_dir.mkdir(parents=True, exist_ok=True)
        return self.figures_dir / f"{paper}_{name}.png"


def budget_tables(ctx: Context, names: Sequence[str]) -> list[Table]:
    """The budgets asked of the studies `names` (full and quick) and what this report's runs
    spent."""
    return [budget_table(ctx, names), spent_table(ctx, names)]


def budget_table(ctx: Context, names: Sequence[str]) -> Table:
    """Population, iterations and seeds of each study's scenarios, full and quick."""
    rows = []
    for name in names:
        full, quick = ctx.configs[name]
        for kind, cfg in (("full", full), ("quick", quick)):
            for sc in cfg.scenarios:
                b = sc.budget or cfg.budget
                rows.append(
                    {
                        "study": name,
                        "scenario": sc.name or "",
                        "run": kind,
                        "population": b.pop_size,
                        "iterations": b.iterations,
                        "evaluations cap": b.evaluations or "none",
                        "seeds": len(cfg.study.seeds),
                        "this report": "yes" if (kind == "quick") == ctx.quick else "",
                    }
                )
    return Table(
        "budgets",
        "Budgets of the studies (full run and --quick)",
        pd.DataFrame(rows),
        "Each run is one optimizer on one scenario with one seed; the report shows the "
        "run marked 'this report'. What each optimizer actually spent: the next table.",
    )


def spent_table(ctx: Context, names: Sequence[str]) -> Table:
    """Per study and optimizer: the evaluations and iterations its completed runs of this report
    actually spent, and the median spent against population x iterations (an optimizer that
    evaluates twice per iteration, as DERLSP-AO's strategies do, shows about 2)."""
    from chassistune.reports.study_setup import optimizer_table

    frames = []
    for name in names:
        if name not in ctx.studies:
            continue
        data = ctx.studies[name]
        table = optimizer_table(data).drop(columns=["hyperparameters"])
        ratios = []
        for opt in table["optimizer"]:
            done = [
                r
                for r in data.records
                if r.spec.optimizer == opt and r.completed and r.nfev is not None
            ]
            spec = done[0].spec if done else None
            nominal = (
                spec.pop_size * spec.max_iter
                if spec is not None and spec.max_iter is not None
                else None
            )
            ratios.append(
                float(np.median([r.nfev for r in done])) / nominal if nominal else float("nan")
            )
        table.insert(0, "study", name)
        table["spent / (population x iterations)"] = ratios
        frames.append(table)
    frame = pd.concat(frames, ignore_index=True) if frames else pd.DataFrame()
    return Table(
        "evaluations_spent",
        "Evaluations actually spent (this report's runs)",
        frame,
        "Objective evaluations and iterations over the completed runs (min / median / "
        "max); the last column: median evaluations spent over population x iterations "
        "asked, so optimizers given the same iterations can be compared at equal cost.",
        missing={"spent / (population x iterations)": "no iteration budget"},
    )


def final_costs(runs: Sequence[RunRecord]) -> np.ndarray:
    """Final best cost of each completed run (NaN where none was recorded)."""
    return np.array([np.nan if r.best_cost is None else r.best_cost for r in runs])


def median_run(runs: Sequence[RunRecord]) -> RunRecord:
    """The run whose final cost is the (lower) median: its optimizer's representative."""
    order = np.argsort(final_costs(runs), kind="stable")
    return runs[int(order[(len(runs) - 1) // 2])]


def order_verdict(values: Mapping[str, np.ndarray], claimed_best: str) -> tuple[str, str]:
    """Is `claimed_best` lowest? holds: lowest median and significantly lower (rank-sum) than
    each other entry with several runs; ranking only: lowest median; else does not hold."""
    medians = {k: float(np.median(v)) for k, v in values.items()}
    best = min(medians, key=lambda k: medians[k])
    tests = {
        k: stats.rank_sum(values[claimed_best], v)
        for k, v in values.items()
        if k != claimed_best and len(v) > 1 and len(values[claimed_best]) > 1
    }
    text = ", ".join(f"{k} {m:.6g}" for k, m in medians.items())
    text += "; rank-sum vs " + (
        ", ".join(f"{k}: {t.sign} (p = {t.p_value:.2g})" for k, t in tests.items())
        or "none (single values)"
    )
    if best != claimed_best and medians[best] < medians[claimed_best]:
        return FAILS, f"lowest is {best}. Medians: {text}"
    if tests and all(t.sign == "+" for t in tests.values()):
        return HOLDS, f"medians: {text}"
    return RANKING_ONLY, f"medians: {text}"


def settle_time_s(trace: Trace) -> float:
    """First time after which |slip - target_slip| <= SLIP_BAND at every sample of an ABS trace
    with vehicle speed above SETTLE_MIN_SPEED_M_S (NaN if it never settles)."""
    s = trace.signals
    time_s = s["time_s"]
    live = s["vehicle_speed_m_s"] > SETTLE_MIN_SPEED_M_S
    off = (np.abs(s["slip"] - s["target_slip"]) > SLIP_BAND) & live
    if not live.any():
        return float("nan")
    last_live = int(np.nonzero(live)[0][-1])
    if off[last_live]:
        return float("nan")
    bad = np.nonzero(off)[0]
    return float(time_s[bad[-1] + 1]) if bad.size else float(time_s[0])


def settle_text(time_s: float) -> str:
    """A settling time for the evidence: '1.23 s', or 'never settles' where `settle_time_s`
    found none (NaN)."""
    return f"{time_s:.3g} s" if np.isfinite(time_s) else NEVER_SETTLES


def percent(a: float, b: float) -> float:
    """Reduction from a to b in percent of a."""
    return 100.0 * (a - b) / a


def graded(ranks: bool, matches: bool) -> str:
    """HOLDS when the claimed order holds and so do the paper's figures, RANKING_ONLY when only
    the order holds, else FAILS."""
    return HOLDS if ranks and matches else RANKING_ONLY if ranks else FAILS


def claim(paper: str, text: str, parts: Sequence[tuple[str, str]]) -> Verdict:
    """The verdict on a claim checked in parts (a verdict word and its evidence per road or
    function): the weakest word, the evidence joined."""
    return Verdict(paper, text, combine([w for w, _ in parts]), "; ".join(e for _, e in parts))


def combine(verdicts: Sequence[str]) -> str:
    """The verdict of a claim made on several roads or functions: the weakest of its parts."""
    for word in (UNCHECKED, FAILS, RANKING_ONLY):
        if word in verdicts:
            return word
    return HOLDS


@dataclass(frozen=True)
class BoundCheck:
    """A published distance beside the adhesion bound for the same speed and road."""

    paper: str
    road: str
    controller: str
    published_m: float
    bound_m: float

    @property
    def ratio(self) -> float:
        return self.published_m / self.bound_m

    @property
    def possible(self) -> bool:
        return self.published_m >= self.bound_m

    def row(self) -> dict[str, object]:
        return {
            "paper": self.paper,
            "road": self.road,
            "controller": self.controller,
            "published (m)": self.published_m,
            "bound (m)": self.bound_m,
            "published / bound": self.ratio,
            "possible": "yes" if self.possible else "no",
        }


def bound_row(paper: str, road: str, label: str, published_m: float, bound_m: float) -> BoundCheck:
    """`BoundCheck` of one published distance."""
    return BoundCheck(paper, road, label, published_m, bound_m)


def bound_verdict(paper: str, checks: Sequence[BoundCheck]) -> Verdict:
    """'The published distances are physically possible': every one at or above its bound."""
    worst = min(checks, key=lambda c: c.ratio)
    below = sum(not c.possible for c in checks)
    return Verdict(
        paper,
        "the published distances are physically possible",
        HOLDS if below == 0 else FAILS,
        f"{below} of {len(checks)} published distances are below the adhesion bound; "
        f"lowest: {worst.controller} on {worst.road}, {worst.published_m:g} m against "
        f"at least {worst.bound_m:.4g} m ({worst.ratio:.2f} x the bound)",
    )
