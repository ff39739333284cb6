"""The sections of a study report, shared by the static page and the interactive one.

Tables are built here from the store's records; figures are asked of a `Figures` maker (PNG
figures for `report.html`, plotly figures for `report_interactive.html`), so both pages show the
same tables, in the same order, and figures of the same data.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Protocol

import numpy as np
import pandas as pd

from chassistune._io import FileSet
from chassistune.reports import study_setup, tables
from chassistune.reports.baseline import LABEL as BASELINE_LABEL
from chassistune.reports.baseline import Baseline, default_baseline
from chassistune.reports.gains import gains_table
from chassistune.reports.generalization import generalization_table, matrix, robustness_table
from chassistune.reports.html import FLAG, CodeView, Download, Item, Section, TableView
from chassistune.reports.plant_view import plant_view
from chassistune.reports.responses import ResponseSet, response_sets
from chassistune.reports.versus import (
    BETTER,
    SAME,
    WORSE,
    claimed,
    metrics_by_optimizer,
    verdict_of_sign,
)
from chassistune.studies.store import RunRecord
from chassistune.tuning.functions import FUNCTION_KIND

ASSETS = "report"


def slug(text: str) -> str:
    """A file-name-safe version of a scenario or group name."""
    return re.sub(r"[^A-Za-z0-9._-]+", "-", text).strip("-") or "x"


class Assets:
    """Writes the CSV tables under DIR/report/tables (each also embedded in the page) into the
    report's set of files `staged`, and hands out page ids."""

    def __init__(self, study_dir: Path, staged: FileSet) -> None:
        self.root = study_dir
        self.staged = staged
        self.tables_dir = study_dir / ASSETS / "tables"
        self.tables_dir.mkdir(parents=True, exist_ok=True)
        self.tables: list[Path] = []
        self._ids = 0

    def next_id(self, kind: str) -> str:
        self._ids += 1
        return f"{kind}-{self._ids}"

    def csv(self, df: pd.DataFrame, name: str) -> Download:
        path = self.tables_dir / f"{name}.csv"
        with self.staged.path(path) as tmp:
            tables.write_table(df, tmp, "csv")
        if path not in self.tables:
            self.tables.append(path)
        return Download.from_csv(path, self.root, Path(tmp))

    def table(
        self, df: pd.DataFrame, title: str, caption: str = "", *sources: Download
    ) -> TableView:
        return TableView.from_frame(df, self.next_id("table"), title, caption, sources)


class Figures(Protocol):
    """Draws the report's figures as page items (PNG or plotly)."""

    def convergence(
        self, scenario: str, runs: Mapping[str, Sequence[RunRecord]], name: str
    ) -> Item: ...

    def final_costs(self, scenario: str, costs: Mapping[str, np.ndarray], name: str) -> Item: ...

    def responses(self, rs: ResponseSet, name: str) -> Item: ...


# -- at a glance ---------------------------------------------------------------------------------

VERDICT_NOTE = (
    f"{BETTER} / {SAME} / {WORSE}: the column's optimizer against the reference, "
    "Wilcoxon rank-sum at alpha 0.05 over the seeds (lower is better)."
)


def glance_section(data: tables.StudyData, reference: str, a: Assets) -> Section:
    """Per scenario: final cost and key metrics, optimizers as columns, with verdicts."""
    unequal = " ".join(f"Warning: {w}." for w in tables.budget_warnings(data))
    section = Section(
        "Results at a glance",
        f"Medians over the completed runs of each optimizer; reference optimizer "
        f"{reference}. {VERDICT_NOTE}" + (f" {unequal}" if unequal else ""),
    )
    wide = {sc: metrics_by_optimizer(data, sc, reference) for sc in data.scenarios}
    source = a.csv(
        pd.concat([w.assign(scenario=sc) for sc, w in wide.items()], ignore_index=True),
        "key_results",
    )
    section.items += [
        a.table(w, f"Key results, {sc}", _glance_caption(data, sc), source)
        for sc, w in wide.items()
    ]
    return section


def _glance_caption(data: tables.StudyData, scenario: str) -> str:
    runs = data.runs(scenario, completed=False)
    s = runs[0].spec
    n = {o: len(data.runs(scenario, o)) for o in data.optimizers}
    seeds = ", ".join(f"{o} {k}" for o, k in n.items())
    return (
        f"{s.plant} ({s.preset}), {s.controller} tuned for {s.objective} on "
        f"{', '.join(s.roads)}. Completed runs: {seeds}."
    )


# -- setup ---------------------------------------------------------------------------------------


def setup_section(
    data: tables.StudyData, config: Mapping[str, Any], store_file: Path, a: Assets
) -> Section:
    """Study, optimizers, each config scenario with every parameter value, and the config."""
    section = Section("Setup", "Everything needed to run this study again.")
    section.items.append(a.table(study_setup.study_table(data, config, store_file), "Study"))
    opts = study_setup.optimizer_table(data)
    section.items.append(
        a.table(
            opts,
            "Optimizers and budgets",
            "Hyperparameters with their defaults filled in; evaluations and iterations actually "
            "spent over the completed runs.",
            a.csv(opts, "optimizers"),
        )
    )
    for group, spec in study_setup.scenario_specs(data).items():
        section.items.append(a.table(study_setup.scenario_table(data, group), f"Scenario {group}"))
        if spec.plant == FUNCTION_KIND:  # a benchmark function has no parameters
            continue
        params = study_setup.parameter_table(spec)
        section.items.append(
            a.table(
                params,
                f"Parameters, {group}",
                "Every plant, road, controller and scoring value the runs used (SI units), per "
                "road.",
                a.csv(params, f"parameters-{slug(group)}"),
            )
        )
    section.items.append(
        CodeView(
            a.next_id("code"),
            "Study config (TOML)",
            study_setup.config_toml(config),
            "The validated config, defaults filled in: save it as a .toml "
            "file and `chassistune study run` it to redo this study.",
        )
    )
    return section


# -- per scenario --------------------------------------------------------------------------------


def scenario_section(
    data: tables.StudyData,
    sc: str,
    index: int,
    reference: str,
    summary: pd.DataFrame,
    ranks: pd.DataFrame,
    sources: Mapping[str, Download],
    a: Assets,
    figures: Figures,
) -> Section:
    """Final cost, best responses against the baseline, tuned gains, convergence, cost spread."""
    section = Section(f"Scenario {sc}")
    spec = data.runs(sc, completed=False)[0].spec
    section.intro = (
        f"{spec.plant} ({spec.preset}), controller {spec.controller}, objective "
        f"{spec.objective}"
        + (f" ({spec.aggregate} over roads)" if len(spec.roads) > 1 else "")
        + f", tuned on {', '.join(spec.roads)}."
    )
    mine = summary[(summary["scenario"] == sc) & (summary["quantity"] == "best_cost")]
    cost = mine.drop(columns=["scenario", "quantity", "unit"])
    rs = ranks[ranks["scenario"] == sc][["optimizer", "sign", "p_value"]]
    cost = cost.merge(rs.rename(columns={"p_value": "rank-sum p"}), on="optimizer", how="left")
    cost.insert(len(cost.columns) - 1, "vs reference", cost.pop("sign").map(verdict_of_sign))
    cost.loc[cost["optimizer"] == reference, "vs reference"] = "reference"
    base = default_baseline(data, sc)
    if base is not None:
        default, ref_median = base.values["best_cost"], cost.set_index("optimizer")["median"]
        cost["vs reference"] = [
            claimed(word, ref_median[reference], median, default)
            for word, median in zip(cost["vs reference"], cost["median"], strict=True)
        ]
    cost = _with_baseline(cost, base)
    section.items.append(
        a.table(
            cost,
            f"Final cost, {sc}",
            f"Best cost found per run over the completed runs; reference {reference}; "
            f"the row {BASELINE_LABEL}: the registry's default gains on the same problem, the "
            f"cost a tune must beat. {VERDICT_NOTE}",
            sources["summary"],
            sources["rank_sum"],
        )
    )
    name = f"{index:02d}-{slug(sc)}"
    section.items += response_items(data, sc, name, figures)
    gains = gains_table(data, sc)
    if not gains.empty and spec.bounds:
        section.items.append(
            a.table(
                _gains_view(gains, list(spec.bounds)),
                f"Tuned gains, {sc}",
                f"Each optimizer's best run, the median of each gain over its runs (median cost), "
                f"and every run. {FLAG} lower / {FLAG} upper: the gain ended within 1 % of the "
                f"bound's range from that bound (at an upper bound, or a lower bound other than "
                f"0, the box may cut the optimum off; a gain at 0 has its term off). Bounds: "
                + ", ".join(f"{g} [{lo:g}, {hi:g}]" for g, (lo, hi) in spec.bounds.items())
                + ".",
                a.csv(gains.assign(scenario=sc), f"gains-{name}"),
            )
        )
    section.items += cost_figures(data, sc, name, figures)
    return section


def _with_baseline(cost: pd.DataFrame, base: Baseline | None) -> pd.DataFrame:
    """The final-cost table with the default gains' row first (its cost in each statistic's
    column; no run counts, no verdict)."""
    if base is None:
        return cost
    value = base.values["best_cost"]
    row: dict[str, object] = {
        c: value for c in ("mean", "best", "worst", "median") if c in cost.columns
    }
    row.update({"optimizer": BASELINE_LABEL, "vs reference": "baseline"})
    return pd.concat([pd.DataFrame([row]), cost], ignore_index=True)[list(cost.columns)]


def response_items(data: tables.StudyData, sc: str, name: str, figures: Figures) -> list[Item]:
    """Each optimizer's best controller over the plant's baseline, one figure per tuned road
    (none for a benchmark function or a plant without a response view)."""
    if data.runs(sc, completed=False)[0].spec.plant == FUNCTION_KIND:
        return []
    return [
        figures.responses(rs, f"responses-{name}-{slug(rs.road)}") for rs in response_sets(data, sc)
    ]


def cost_figures(data: tables.StudyData, sc: str, name: str, figures: Figures) -> list[Item]:
    """Convergence (median and interquartile band) and final-cost spread of the optimizers that
    completed runs of scenario `sc`."""
    done = {o: runs for o in data.optimizers if (runs := data.runs(sc, o))}
    return [
        figures.convergence(sc, done, f"convergence-{name}"),
        figures.final_costs(sc, {o: data.costs(sc, o) for o in done}, f"final-cost-{name}"),
    ]


def _gains_view(gains: pd.DataFrame, names: list[str]) -> pd.DataFrame:
    """Gains with their bound flags written into the cell ('4999 ⚑ upper')."""
    out = gains[["optimizer", "row", "cost", *names]].astype(object)
    for g in names:
        flags = gains[f"{g} at bound"]
        out[g] = [
            f"{v:.5g} {FLAG} {f}" if f else f"{v:.5g}" for v, f in zip(gains[g], flags, strict=True)
        ]
    out["cost"] = [f"{c:.4g}" for c in gains["cost"]]
    return out


# -- across scenarios ----------------------------------------------------------------------------


def comparison_section(data: tables.StudyData, reference: str, a: Assets) -> Section | None:
    """Verdict counts over scenarios; Friedman ranks and post-hoc tests only over two or more
    scenarios (a rank over one scenario says nothing)."""
    kept, _ = tables.score_matrix(data)
    if len(data.optimizers) < 2 or len(data.scenarios) < 2:
        return None
    section = Section(
        "Comparison across scenarios",
        f"Reference optimizer: {reference}. Scores are mean final costs.",
    )
    counts = tables.rank_sum_counts_table(data, reference)
    shown = counts.rename(
        columns={
            "-": f"{BETTER} (scenarios)",
            "=": f"{SAME} (scenarios)",
            "+": f"{WORSE} (scenarios)",
        }
    )
    shown = shown[
        ["optimizer", f"{BETTER} (scenarios)", f"{SAME} (scenarios)", f"{WORSE} (scenarios)"]
    ]
    section.items.append(
        a.table(
            shown,
            f"Against {reference}, scenario by scenario",
            "In how many scenarios each optimizer's final costs are significantly better than, "
            "not "
            f"significantly different from, or worse than {reference}'s (Wilcoxon rank-sum, alpha "
            f"0.05).",
            a.csv(counts, "rank_sum_counts"),
        )
    )
    if len(kept) >= 2:
        fr, res = tables.friedman_table(data)
        if res is not None:
            test = (
                f" Friedman chi-square {res.statistic:.4g}, p = {res.p_value:.3g}."
                if res.statistic == res.statistic
                else " (Friedman's test itself needs 3 or more optimizers.)"
            )
            section.items.append(
                a.table(
                    fr,
                    "Friedman mean ranks",
                    f"Mean rank of each optimizer's mean final cost over {res.n_problems} "
                    f"scenarios (1 = best).{test}",
                    a.csv(fr, "friedman"),
                )
            )
        ph = tables.posthoc_table(data, reference)
        if not ph.empty:
            section.items.append(
                a.table(
                    ph,
                    f"Post-hoc tests against {reference}",
                    "z tests on mean-rank differences with Holm's correction (alpha 0.05).",
                    a.csv(ph, "posthoc"),
                )
            )
    return section


def generalization_section(data: tables.StudyData, a: Assets) -> Section | None:
    """Per group and optimizer: tuned on X (rows), tested on Y (column groups): cost beside the
    plant's generalization metrics."""
    gen, rob = generalization_table(data), robustness_table(data)
    if gen.empty and rob.empty:
        return None
    section = Section(
        "Generalization across roads",
        "Tuned on road X (rows), tested on road Y (column groups): medians over "
        "seeds of each run's best gains tested on Y. Robust versus nominal: "
        "tuned on K scenarios of the uncertainty (nominal: K = 0), validated on "
        "the same fresh draws.",
    )
    if not rob.empty:
        section.items.append(
            a.table(
                rob,
                "Robust versus nominal",
                "Medians over seeds; draws and failures summed.",
                a.csv(rob, "robustness"),
            )
        )
    if gen.empty:
        return section
    source = a.csv(gen, "generalization")
    for (group, opt), cell in gen.groupby(["group", "optimizer"], sort=False):
        spec = next(r.spec for r in data.records if r.spec.group == group)
        labels = [("median_cost", spec.objective)] + [
            (f"median_{k}", label) for k, label in plant_view(spec.plant).generalization_metrics
        ]
        section.items.append(
            a.table(
                matrix(cell, labels),
                f"Generalization, {group}, {opt}",
                "Median over seeds.",
                source,
            )
        )
    return section


def failures_section(data: tables.StudyData, a: Assets) -> Section | None:
    if not data.failed:
        return None
    fails = tables.failures_table(data)
    return Section(
        "Failed runs",
        items=[
            a.table(
                fails,
                "Failed runs",
                "Runs recorded as failed, with their errors.",
                a.csv(fails, "failures"),
            )
        ],
    )


def summary_line(data: tables.StudyData, reference: str) -> str:
    n_ok = sum(r.completed for r in data.records)
    return (
        f"{len(data.records)} runs ({n_ok} completed, {len(data.failed)} failed), "
        f"{len(data.scenarios)} scenarios, {len(data.optimizers)} optimizers; "
        f"reference {reference}."
    )


def study_sections(
    data: tables.StudyData,
    config: Mapping[str, Any],
    reference: str,
    store_file: Path,
    a: Assets,
    figures: Figures,
) -> list[Section]:
    """Every section of the report, in page order."""
    summary = tables.summary_table(data)
    ranks = tables.rank_sum_table(data, reference)
    sources = {"summary": a.csv(summary, "summary"), "rank_sum": a.csv(ranks, "rank_sum")}
    sections = [glance_section(data, reference, a)]
    for i, sc in enumerate(data.scenarios, start=1):
        sections.append(
            scenario_section(data, sc, i, reference, summary, ranks, sources, a, figures)
        )
    for extra in (
        comparison_section(data, reference, a),
        generalization_section(data, a),
        failures_section(data, a),
    ):
        if extra is not None:
            sections.append(extra)
    sections.append(setup_section(data, config, store_file, a))
    return sections
