"""`study report DIR`: read the store, compute the tables, draw the figures, write the page.

Output: DIR/report.html (self-contained), DIR/report/tables/*.csv, DIR/report/figures/*.png.
The store is only read; best responses are re-simulated from the stored specs and gains.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from chassistune._io import atomic_path
from chassistune.errors import InputError
from chassistune.reports import figures, tables
from chassistune.reports.html import FigureView, Section, TableView, render
from chassistune.studies.store import open_study

REPORT_NAME = "report.html"
ASSETS = "report"


@dataclass(frozen=True)
class ReportFiles:
    """What `build_report` wrote."""

    html: Path
    folder: Path
    tables: list[Path]
    figures: list[Path]


def slug(text: str) -> str:
    """A file-name-safe version of a scenario or group name."""
    return re.sub(r"[^A-Za-z0-9._-]+", "-", text).strip("-") or "x"


class _Writer:
    """Writes CSVs and PNGs under DIR/report and hands out page ids."""

    def __init__(self, study_dir: Path) -> None:
        self.root = study_dir
        self.tables_dir = study_dir / ASSETS / "tables"
        self.figures_dir = study_dir / ASSETS / "figures"
        for d, suffix in ((self.tables_dir, ".csv"), (self.figures_dir, ".png")):
            d.mkdir(parents=True, exist_ok=True)
            for old in d.glob(f"*{suffix}"):  # a previous report's files
                old.unlink()
        self.tables: list[Path] = []
        self.figures: list[Path] = []
        self._ids = 0

    def next_id(self, kind: str) -> str:
        self._ids += 1
        return f"{kind}-{self._ids}"

    def rel(self, path: Path) -> str:
        return path.relative_to(self.root).as_posix()

    def csv(self, df: pd.DataFrame, name: str) -> str:
        path = self.tables_dir / f"{name}.csv"
        tables.write_table(df, str(path), "csv")
        self.tables.append(path)
        return self.rel(path)

    def png(self, name: str) -> Path:
        path = self.figures_dir / f"{name}.png"
        self.figures.append(path)
        return path

    def figure(self, path: Path, title: str, caption: str) -> FigureView:
        return FigureView.from_png(path, self.next_id("figure"), title, caption, self.rel(path))

    def table(self, df: pd.DataFrame, title: str, caption: str = "",
              source: str = "") -> TableView:
        return TableView.from_frame(df, self.next_id("table"), title, caption, source)


def _overview(data: tables.StudyData, config: dict[str, Any], w: _Writer) -> Section:
    n_ok = sum(r.completed for r in data.records)
    budget = config.get("budget", {})
    spent = ", ".join(f"{k} {v}" for k, v in budget.items() if v is not None)
    study = config.get("study", {})
    opts = []
    for o in config.get("optimizers", []):
        hyper = ", ".join(f"{k}={v}" for k, v in o.get("hyperparameters", {}).items())
        label = o.get("label") or o["name"]
        detail = ", ".join(x for x in (o["name"] if label != o["name"] else "", hyper) if x)
        opts.append(f"{label} ({detail})" if detail else label)
    versions = data.records[0].versions if data.records else {}
    rows = [
        ("runs finished", f"{len(data.records)} ({n_ok} completed, {len(data.failed)} failed)"),
        ("scenarios", ", ".join(data.scenarios)),
        ("optimizers", "; ".join(opts) or ", ".join(data.optimizers)),
        ("seeds", f"indices {_span(study.get('seeds', []))}, root seed {study.get('seed', 0)}"),
        ("budget", spent),
        ("versions", ", ".join(f"{k} {v}" for k, v in sorted(versions.items()))),
    ]
    df = pd.DataFrame(rows, columns=["item", "value"])
    return Section("Study", items=[w.table(df, "Study settings")])


def _span(seeds: list[int]) -> str:
    if seeds and seeds == list(range(seeds[0], seeds[0] + len(seeds))):
        return f"{seeds[0]}..{seeds[-1]}" if len(seeds) > 1 else str(seeds[0])
    return ", ".join(map(str, seeds))


def _scenario_section(data: tables.StudyData, sc: str, index: int, reference: str,
                      summary: pd.DataFrame, ranks: pd.DataFrame, sources: dict[str, str],
                      w: _Writer) -> Section:
    section = Section(f"Scenario {sc}")
    runs = data.runs(sc, completed=False)
    spec = runs[0].spec
    section.intro = (f"{spec.plant} ({spec.preset}), controller {spec.controller}, objective "
                     f"{spec.objective}" + (f" ({spec.aggregate} over roads)"
                                            if len(spec.roads) > 1 else "")
                     + f", tuned on {', '.join(spec.roads)}.")
    mine = summary[summary["scenario"] == sc]
    cost = mine[mine["quantity"] == "best_cost"].drop(columns=["scenario", "quantity"])
    rs = ranks[ranks["scenario"] == sc][["optimizer", "sign", "p_value"]]
    cost = cost.merge(rs.rename(columns={"sign": f"vs {reference}", "p_value": "p"}),
                      on="optimizer", how="left")
    cost.loc[cost["optimizer"] == reference, f"vs {reference}"] = "(ref)"
    section.items.append(w.table(
        cost, f"Final cost, {sc}",
        f"Best cost found per run over the completed runs. Rank-sum column: Wilcoxon rank-sum "
        f"(alpha 0.05) of {reference} against each optimizer, read from {reference}'s side: "
        f"+ {reference} significantly better, - significantly worse, = no significant "
        f"difference.", sources["summary"]))
    metrics = mine[mine["quantity"] != "best_cost"].drop(columns=["scenario", "failed"])
    order = {q: i for i, q in enumerate(dict.fromkeys(metrics["quantity"]))}
    metrics = metrics.sort_values("quantity", key=lambda q: q.map(order), kind="stable")
    if not metrics.empty:
        section.items.append(w.table(
            metrics.rename(columns={"quantity": "metric"}), f"Key metrics, {sc}",
            "Metrics of each run's best gains (lower is better; best = lowest).",
            sources["summary"]))
    name = f"{index:02d}-{slug(sc)}"
    done = {o: data.runs(sc, o) for o in data.optimizers}
    path = w.png(f"convergence-{name}")
    figures.convergence_figure(done, str(path), sc)
    section.items.append(w.figure(path, f"Convergence, {sc}",
                                  "Best cost so far against evaluations: median over seeds "
                                  "(line) and interquartile band."))
    path = w.png(f"boxplot-{name}")
    figures.boxplot_figure({o: data.costs(sc, o) for o in data.optimizers}, str(path),
                           f"{sc}: final best cost")
    section.items.append(w.figure(path, f"Final cost distribution, {sc}",
                                  "Box plot of the final best cost per optimizer; points are "
                                  "runs."))
    best = tables.best_run(data, sc)
    if best is not None:
        paths = {road: w.png(f"response-{name}-{slug(road)}") for road in best.spec.roads}
        figures.response_figures(best, {r: str(p) for r, p in paths.items()})
        gains = ", ".join(f"{k}={v:.5g}" for k, v in best.best_gains.items())
        for road, path in paths.items():
            section.items.append(w.figure(
                path, f"Best controller, {sc}, on {road}",
                f"Response of the best run ({best.spec.optimizer}, seed {best.spec.seed}, cost "
                f"{best.best_cost:.6g}; gains {gains})."))
    return section


def _comparison_section(data: tables.StudyData, reference: str, w: _Writer) -> Section | None:
    if len(data.optimizers) < 2:
        return None
    section = Section("Comparison across scenarios",
                      f"Reference optimizer: {reference}. Scores are mean final costs.")
    counts = tables.rank_sum_counts_table(data, reference)
    section.items.append(w.table(
        counts, f"Wilcoxon rank-sum +/=/- of {reference}",
        f"Over the scenarios: + {reference} significantly better, = no significant difference, "
        f"- significantly worse (alpha 0.05).", w.csv(counts, "rank_sum_counts")))
    fr, res = tables.friedman_table(data)
    if res is not None:
        test = (f" Friedman chi-square {res.statistic:.4g}, p = {res.p_value:.3g}."
                if res.statistic == res.statistic else
                " (Friedman's test needs 3 or more optimizers and 2 or more scenarios.)")
        section.items.append(w.table(
            fr, "Friedman mean ranks",
            f"Mean rank of each optimizer's mean final cost over {res.n_problems} scenarios "
            f"(1 = best).{test}", w.csv(fr, "friedman")))
    ph = tables.posthoc_table(data, reference)
    if not ph.empty:
        section.items.append(w.table(
            ph, f"Post-hoc tests against {reference}",
            "z tests on mean-rank differences with Holm's correction (alpha 0.05).",
            w.csv(ph, "posthoc")))
    return section


def _generalization_section(data: tables.StudyData, w: _Writer) -> Section | None:
    gen = tables.generalization_table(data)
    if gen.empty:
        return None
    source = w.csv(gen, "generalization")
    section = Section("Generalization across roads",
                      "Tuned on road X (rows), tested on road Y (columns): median over seeds "
                      "of the cost of each run's best gains on Y.")
    for (group, opt), cell in gen.groupby(["group", "optimizer"], sort=False):
        matrix = cell.pivot(index="tuned_on", columns="tested_on", values="median_cost")
        matrix = matrix.reindex(index=list(dict.fromkeys(cell["tuned_on"])),
                                columns=list(dict.fromkeys(cell["tested_on"])))
        matrix = matrix.reset_index().rename(columns={"tuned_on": "tuned on \\ tested on"})
        matrix.columns.name = None
        section.items.append(w.table(matrix, f"Generalization, {group}, {opt}",
                                     "Median cost over seeds.", source))
    return section


def build_report(study_dir: str | Path, reference: str | None = None) -> ReportFiles:
    """Write DIR/report.html, its CSV tables and PNG figures; InputError for a bad DIR."""
    from importlib.metadata import version

    root = Path(study_dir)
    with open_study(root) as store:
        data = tables.load_study(store)
        config = json.loads(store.meta().get("config", "{}"))
    if not data.records:
        raise InputError("DIR", f"{str(root)!r} holds no finished runs yet")
    reference = tables.check_reference(data, reference)
    w = _Writer(root)
    summary = tables.summary_table(data)
    ranks = tables.rank_sum_table(data, reference)
    sources = {"summary": w.csv(summary, "summary"), "rank_sum": w.csv(ranks, "rank_sum")}
    sections = [_overview(data, config, w)]
    for i, sc in enumerate(data.scenarios, start=1):
        sections.append(_scenario_section(data, sc, i, reference, summary, ranks, sources, w))
    for extra in (_comparison_section(data, reference, w), _generalization_section(data, w)):
        if extra is not None:
            sections.append(extra)
    if data.failed:
        fails = tables.failures_table(data)
        sections.append(Section("Failed runs", items=[w.table(
            fails, "Failed runs", "Runs recorded as failed, with their errors.",
            w.csv(fails, "failures"))]))
    n_ok = sum(r.completed for r in data.records)
    summary_line = (f"{len(data.records)} runs ({n_ok} completed, {len(data.failed)} failed), "
                    f"{len(data.scenarios)} scenarios, {len(data.optimizers)} optimizers; "
                    f"reference {reference}.")
    page = render(data.name, summary_line, config.get("study", {}).get("description", ""),
                  sections, version("chassistune"))
    html = root / REPORT_NAME
    with atomic_path(html) as tmp:
        Path(tmp).write_text(page, encoding="utf-8")
    return ReportFiles(html, root / ASSETS, w.tables, w.figures)
