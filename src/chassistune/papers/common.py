"""What every paper's reproduction produces: a section (setting, budgets, tables, figures) and a
verdict per declared claim (`papers.claims`); and the judging rules the four share (rankings over
tuned runs against tuned runs or fixed baselines, slip settling, equal evaluations, the physical
bounds of distance and time).

Verdict words: `holds`, `holds in ranking only` (the order the paper claims, without a
significant difference), `does not hold`, `undecided at this budget` (the run's seeds cannot make
the claim's test significant, whatever the numbers), `cannot be checked`.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
from scipy import stats as _st

from chassistune import stats
from chassistune.papers.claims import Claim
from chassistune.reports.tables import StudyData
from chassistune.studies.spec import StudyConfig
from chassistune.studies.store import RunRecord

if TYPE_CHECKING:
    from chassistune.scenarios.base import Trace

HOLDS = "holds"
RANKING_ONLY = "holds in ranking only"
FAILS = "does not hold"
UNDECIDED = "undecided at this budget"
UNCHECKED = "cannot be checked"
ORACLE_SETTING = (
    "road knowledge",
    "oracle, the papers' setting: every slip controller is handed the road's optimal slip (the "
    "peak of its mu-slip curve) as its target, which no vehicle knows (docs/abs_laws.md, 'Road "
    "knowledge'; `chassistune league` tunes a fixed target instead).",
)
"""The setting row every ABS paper's section states."""

VERDICTS = (HOLDS, RANKING_ONLY, FAILS, UNDECIDED, UNCHECKED)
VERDICT_MARKS = {HOLDS: "✔", RANKING_ONLY: "≈", FAILS: "✘", UNDECIDED: "⋯", UNCHECKED: "?"}
"""Shown before each verdict on the page (the same symbols as the study report's better /
same / worse), so a verdict cannot be taken for a blank or misread."""
BOUND_RATIOS = (
    "paper / bound",
    "published / bound",
    "ours / bound",
    "paper time / time bound",
    "ours time / time bound",
    "published / strict bound",
)
"""Columns of a distance or time over its physical bound: below 1 is flagged on the page."""

NEVER_SETTLES = "never settles"
"""Stands for a settling time `settle_time_s` did not find (NaN), in tables and evidence."""
SLIP_BAND = 0.05
"""A slip has settled once it stays within this of its target (absolute slip)."""
SETTLE_MIN_SPEED_M_S = 2.0
"""Samples below this vehicle speed are ignored by the settling time (slip is singular near
standstill and the ABS cuts out)."""


@dataclass(frozen=True)
class Verdict:
    """Our verdict on a declared claim and its evidence (numbers, test, p-value)."""

    claim: Claim
    verdict: str
    evidence: str

    def __post_init__(self) -> None:
        if self.verdict not in VERDICTS:
            raise ValueError(f"unknown verdict {self.verdict!r}")

    @property
    def paper(self) -> str:
        return self.claim.paper


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


@dataclass(frozen=True)
class PairTest:
    """One claimed entry against one rival (lower is better): the test used, its p-value, its
    sign ('+': the claimed entry significantly lower, '=': no significant difference, '-':
    significantly higher) and `floor_p`, the smallest p-value the sample sizes allow."""

    test: str
    p_value: float
    sign: str
    floor_p: float

    @property
    def decidable(self) -> bool:
        """Could this test have been significant at these sample sizes?"""
        return self.floor_p < stats.ALPHA

    def text(self) -> str:
        if self.test == "values":
            return "fixed values"
        return f"{self.test} {self.sign} (p = {self.p_value:.2g})"


def compare(
    claimed: np.ndarray, rival: np.ndarray, claimed_fixed: bool = False, rival_fixed: bool = False
) -> PairTest:
    """`claimed` against `rival`, lower better; a `fixed` side is one value that no seed
    changes (an untuned baseline), the other side's values are runs over seeds. Runs against
    runs: two-sided Wilcoxon rank-sum (smallest p 2 / C(n + m, n)); runs against a fixed value:
    two-sided Wilcoxon signed-rank of the runs about it (smallest p 2 / 2^n); fixed against
    fixed: decided by the numbers."""
    a, b = np.asarray(claimed, dtype=float), np.asarray(rival, dtype=float)
    if claimed_fixed and rival_fixed:
        sign = "+" if a[0] < b[0] else "-" if a[0] > b[0] else "="
        return PairTest("values", 0.0 if sign != "=" else 1.0, sign, 0.0)
    if not claimed_fixed and not rival_fixed:
        r = stats.rank_sum(a, b)
        return PairTest("rank-sum", r.p_value, r.sign, 2.0 / math.comb(a.size + b.size, a.size))
    runs, fixed = (b, a[0]) if claimed_fixed else (a, b[0])
    d = runs - fixed
    floor = min(1.0, 2.0 / 2.0**runs.size)
    if not np.any(d):
        return PairTest("signed-rank", 1.0, "=", floor)
    p = float(_st.wilcoxon(d).pvalue)
    runs_lower = float(np.median(d)) < 0.0
    sign = "=" if p >= stats.ALPHA else "+" if runs_lower != claimed_fixed else "-"
    return PairTest("signed-rank", p, sign, floor)


def order_verdict(
    values: Mapping[str, np.ndarray],
    claimed: str,
    lowest: bool = True,
    fixed: Collection[str] = (),
) -> tuple[str, str]:
    """Is `claimed` the lowest (`lowest` False: the highest) of `values` (runs over seeds, or
    one value each for the entries named in `fixed`)? See `ranking_verdict`."""
    sgn = 1.0 if lowest else -1.0
    tests = {
        k: compare(
            sgn * np.asarray(values[claimed]), sgn * np.asarray(v), claimed in fixed, k in fixed
        )
        for k, v in values.items()
        if k != claimed
    }
    medians = {k: float(np.median(v)) for k, v in values.items()}
    return ranking_verdict(tests, medians, claimed, lowest)


def ranking_verdict(
    tests: Mapping[str, PairTest], medians: Mapping[str, float], claimed: str, lowest: bool = True
) -> tuple[str, str]:
    """The verdict on '`claimed` is the lowest (highest)' from its test against each rival:
    holds: every test significant the claimed way; does not hold: a rival significantly the
    other way, or (tests able to decide) a rival's median beyond the claimed one's; undecided
    at this budget: a test that could not have been significant at these sample sizes; else
    holds in ranking only."""
    sgn = 1.0 if lowest else -1.0
    extreme = min(medians, key=lambda k: sgn * medians[k])
    text = ", ".join(f"{k} {m:.6g}" for k, m in medians.items())
    text += "; vs " + ", ".join(f"{k}: {t.text()}" for k, t in tests.items())
    word = "lowest" if lowest else "highest"
    beaten = [k for k, t in tests.items() if t.sign == "-"]
    if beaten:
        side = "lower" if lowest else "higher"
        return FAILS, f"{', '.join(beaten)} {side} than {claimed}. Medians: {text}"
    if all(t.sign == "+" for t in tests.values()):
        return HOLDS, f"medians: {text}"
    if not all(t.decidable for t in tests.values()):
        floor = max(t.floor_p for t in tests.values())
        return UNDECIDED, (
            f"{word} median: {extreme}; these sample sizes cannot reach p < {stats.ALPHA} "
            f"(smallest attainable p = {floor:.2g}). Medians: {text}"
        )
    if medians[extreme] == medians[claimed]:
        return RANKING_ONLY, f"medians: {text}"
    return FAILS, f"{word} is {extreme}. Medians: {text}"


@dataclass(frozen=True)
class Curve:
    """One run's convergence: best-so-far cost after each iteration and the evaluations spent
    by then."""

    cost: np.ndarray
    evaluations: np.ndarray

    @classmethod
    def of(cls, run: RunRecord) -> Curve:
        return cls(np.asarray(run.history, dtype=float), np.asarray(run.history_nfev))

    def at_evaluations(self, evaluations: float) -> float:
        """Best-so-far cost once `evaluations` were spent (the last point within them)."""
        within = np.nonzero(self.evaluations <= evaluations)[0]
        return float(self.cost[within[-1]]) if within.size else math.inf

    def reaches(self, target: float, by_evaluations: bool) -> float:
        """Iterations (or evaluations) until the best-so-far first is <= target (inf: never)."""
        hit = np.nonzero(self.cost <= target)[0]
        if not hit.size:
            return math.inf
        return float(self.evaluations[hit[0]]) if by_evaluations else hit[0] + 1.0


def equal_evaluations(curves: Mapping[str, Sequence[Curve]]) -> float:
    """The evaluations every entry spent: the smallest of the entries' median final spends."""
    return float(min(np.median([c.evaluations[-1] for c in cs]) for cs in curves.values()))


def finals_at(
    curves: Mapping[str, Sequence[Curve]], evaluations: float | None
) -> dict[str, np.ndarray]:
    """Final costs per entry at equal iterations (`evaluations` None: each run's last point)
    or at `evaluations` spent."""
    return {
        k: np.array(
            [c.cost[-1] if evaluations is None else c.at_evaluations(evaluations) for c in cs]
        )
        for k, cs in curves.items()
    }


def speed_verdict(
    curves: Mapping[str, Sequence[Curve]], claimed: str, by_evaluations: bool
) -> tuple[str, str]:
    """'`claimed` converges fastest': against each rival, the iterations (or evaluations) each
    run needs to reach the level every run of both reaches (the largest final cost of the
    pair's runs), compared by rank-sum; see `ranking_verdict`."""
    unit = "evaluations" if by_evaluations else "iterations"
    tests, medians, targets = {}, {claimed: 0.0}, []
    for rival in curves:
        if rival == claimed:
            continue
        pair = (claimed, rival)
        target = max(c.cost[-1] for k in pair for c in curves[k])
        mine, theirs = (
            np.array([c.reaches(target, by_evaluations) for c in curves[k]]) for k in pair
        )
        tests[rival] = compare(mine, theirs)
        medians[rival] = float(np.median(theirs)) - float(np.median(mine))
        targets.append(f"{rival} {target:.6g}")
    word, evidence = ranking_verdict(tests, medians, claimed)
    return word, (
        f"{unit} to the level every run of both reaches (vs {', '.join(targets)}); "
        f"medians: rival's {unit} minus {claimed}'s. {evidence}"
    )


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
    found none (NaN; infinite in `settle_verdict`)."""
    return f"{time_s:.3g} s" if np.isfinite(time_s) else NEVER_SETTLES


def settle_verdict(
    settle_s: Mapping[str, np.ndarray],
    claimed: str,
    within_s: float | None = None,
    fixed: Collection[str] = (),
) -> tuple[str, str]:
    """'`claimed` settles first' (and, with `within_s`, by `within_s`), from the settling time
    of every run (one value for the entries in `fixed`; never settling counts as infinite):
    `order_verdict` on the times, and a claim that ranks but whose median settles later than
    stated holds in ranking only."""
    times = {k: np.where(np.isnan(v), np.inf, v) for k, v in settle_s.items()}
    word, evidence = order_verdict(times, claimed, fixed=fixed)
    mine = float(np.median(times[claimed]))
    if within_s is not None and word in (HOLDS, RANKING_ONLY) and not mine <= within_s:
        word = RANKING_ONLY
    stated = (
        ""
        if within_s is None
        else f" (stated: by {within_s:g} s; {claimed}'s median: {settle_text(mine)})"
    )
    return word, f"settling times (s){stated}, {evidence}"


def percent(a: float, b: float) -> float:
    """Reduction from a to b in percent of a."""
    return 100.0 * (a - b) / a


def graded(ranks: bool, matches: bool) -> str:
    """HOLDS when the claimed order holds and so do the paper's figures, RANKING_ONLY when only
    the order holds, else FAILS."""
    return HOLDS if ranks and matches else RANKING_ONLY if ranks else FAILS


def judged(claim: Claim, parts: Sequence[tuple[str, str]]) -> Verdict:
    """The verdict on a claim checked in parts (a verdict word and its evidence per road,
    function or metric): the weakest word, the evidence joined."""
    return Verdict(claim, combine([w for w, _ in parts]), "; ".join(e for _, e in parts))


def combine(verdicts: Sequence[str]) -> str:
    """The verdict of a claim made on several roads or functions: the weakest of its parts (a
    part that does not hold decides before an undecided one)."""
    for word in (UNCHECKED, FAILS, UNDECIDED, RANKING_ONLY):
        if word in verdicts:
            return word
    return HOLDS


def most(verdicts: Sequence[str]) -> str:
    """The verdict of a claim made on most of several functions: holds when more than half of
    the parts hold, ranking only when more than half at least hold in ranking; undecided when
    the undecided parts could still make such a majority; else does not hold."""
    half = len(verdicts) / 2.0
    held = sum(v == HOLDS for v in verdicts)
    ranked = held + sum(v == RANKING_ONLY for v in verdicts)
    if held > half:
        return HOLDS
    if ranked > half:
        return RANKING_ONLY
    if ranked + sum(v == UNDECIDED for v in verdicts) > half:
        return UNDECIDED
    return FAILS


TIME_AS_REST = "time to rest: below the bound is impossible"
TIME_AS_WHEEL_STOP = (
    "time until the wheel speed reaches 0 (our reading of this paper): below the bound, the "
    "wheel locked before the vehicle stopped, against the paper's no-lock claim"
)


@dataclass(frozen=True)
class BoundCheck:
    """A published (or measured) stopping distance or time beside the physical bound for the
    same speed and road. `assumption` names the modelling assumption the bound rests on (empty:
    none); `strict` is then the assumption-free bound (peak of the best surface throughout)."""

    paper: str
    road: str
    controller: str
    quantity: str
    unit: str
    published: float
    printed: str
    bound: float
    reading: str = ""
    assumption: str = ""
    strict: float | None = None

    @property
    def ratio(self) -> float:
        return self.published / self.bound

    @property
    def possible(self) -> bool:
        return self.published >= self.bound

    @property
    def strictly_possible(self) -> bool:
        return self.published >= (self.bound if self.strict is None else self.strict)

    def row(self) -> dict[str, object]:
        return {
            "paper": self.paper,
            "road": self.road,
            "controller": self.controller,
            "quantity": self.quantity,
            "published": self.printed,
            "unit": self.unit,
            "bound": self.bound,
            "published / bound": self.ratio,
            "possible": "yes" if self.possible else "no",
            "bound assumes": self.assumption or "nothing beyond the bilinear tire's peak",
            "strict bound": self.bound if self.strict is None else self.strict,
            "published / strict bound": self.published
            / (self.bound if self.strict is None else self.strict),
            "reading": self.reading,
        }


def bound_verdict(claim: Claim, checks: Sequence[BoundCheck]) -> Verdict:
    """'The published distances and times are physically possible': every one at or above its
    bound (those below only a bound that rests on an assumption are named)."""
    parts = []
    for quantity in dict.fromkeys(c.quantity for c in checks):
        cs = [c for c in checks if c.quantity == quantity]
        worst = min(cs, key=lambda c: c.ratio)
        below = [c for c in cs if not c.possible]
        strict_below = [c for c in cs if not c.strictly_possible]
        text = (
            f"{len(below)} of {len(cs)} published {quantity}s are below the bound "
            f"({len(strict_below)} below the strict, assumption-free bound); lowest: "
            f"{worst.controller} on {worst.road}, {worst.printed} {worst.unit} against at least "
            f"{worst.bound:.4g} {worst.unit} ({worst.ratio:.2f} x the bound)"
        )
        if below and below[0].reading:
            text += f"; read as {below[0].reading}"
        parts.append((FAILS if strict_below else HOLDS, text))
    return judged(claim, parts)
