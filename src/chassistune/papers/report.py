"""The reproduction's report: one self-contained HTML page (figures and CSV tables embedded),
the CSV tables under OUT/tables/, the PNG figures under OUT/figures/ and OUT/verdicts.csv.

The first section holds the verdict table of every paper reproduced and what the physical bounds
say about the papers' distances; then one section per paper: its setting, every table (the
paper's numbers beside ours), every figure redrawn from our runs, and its verdicts.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import pandas as pd

from chassistune._io import write_text
from chassistune.papers.common import PaperSection, Table, Verdict
from chassistune.reports.html import Download, FigureView, Section, TableView, render
from chassistune.reports.tables import write_table


@dataclass(frozen=True)
class ReportFiles:
    """The files a reproduction wrote."""

    html: Path
    verdicts: Path
    tables: tuple[Path, ...]
    figures: tuple[Path, ...]


def verdict_frame(verdicts: Sequence[Verdict]) -> pd.DataFrame:
    """One row per claim: paper, claim, verdict, evidence."""
    return pd.DataFrame([{"paper": v.paper, "claim": v.claim, "verdict": v.verdict,
                          "evidence": v.evidence} for v in verdicts],
                        columns=["paper", "claim", "verdict", "evidence"])


class _Writer:
    """Writes each table's CSV once and turns tables and figures into page items."""

    def __init__(self, out: Path) -> None:
        self.tables_dir = out / "tables"
        self.tables_dir.mkdir(parents=True, exist_ok=True)
        self.written: list[Path] = []
        self.count = 0

    def table(self, t: Table, prefix: str) -> TableView:
        path = self.tables_dir / f"{prefix}{t.name}.csv"
        write_table(t.frame, str(path))
        self.written.append(path)
        self.count += 1
        return TableView.from_frame(t.frame, f"t{self.count}", t.title, t.caption,
                                    (Download.from_csv(path),))


def _first_section(w: _Writer, sections: Sequence[PaperSection]) -> Section:
    verdicts = [v for s in sections for v in s.verdicts]
    bounds = [b for s in sections for b in s.bounds]
    items: list[TableView | FigureView] = [w.table(Table(
        "verdicts", "Verdict per claim, all papers", verdict_frame(verdicts),
        "holds / holds in ranking only / does not hold / cannot be checked; the evidence gives "
        "the numbers and tests (rank-sum p-values at alpha 0.05)."), "")]
    below = [b for b in bounds if not b.possible]
    intro = (f"{len(verdicts)} claims judged. Physical bounds: {len(below)} of {len(bounds)} "
             "published stopping distances are shorter than the adhesion bound "
             "v0^2/(2 mu_peak g) of their own speed and road"
             + (f" (papers {', '.join(sorted({b.paper for b in below}))})" if below else "")
             + "; no run of ours beats its bound (each table lists ours / bound).")
    if bounds:
        items.append(w.table(Table("bounds", "Published distances against the physical bound",
                                   pd.DataFrame([b.row() for b in bounds])), ""))
    return Section("Verdicts and physical bounds", intro, list(items), id="verdicts")


def _paper_section(w: _Writer, s: PaperSection) -> Section:
    prefix = f"{s.key}_"
    items: list[TableView | FigureView] = [w.table(Table(
        "setting", "Setting: our reading, assumptions, the paper's defects",
        pd.DataFrame(s.setting, columns=["topic", "text"])), prefix)]
    items += [w.table(t, prefix) for t in s.tables]
    for f in s.figures:
        w.count += 1
        items.append(FigureView.from_png(f.path, f"f{w.count}", f.title, f.caption,
                                         file=f"figures/{f.path.name}"))
    items.append(w.table(Table("verdicts", "Verdicts", verdict_frame(s.verdicts)), prefix))
    return Section(s.title, f"Paper key: {s.key}.", list(items), id=s.key)


def write_report(out: Path, sections: Sequence[PaperSection], quick: bool,
                 wall_time_s: float) -> ReportFiles:
    """Write report.html, tables/*.csv and verdicts.csv into `out` (figures are there already)."""
    w = _Writer(out)
    page = [_first_section(w, sections)] + [_paper_section(w, s) for s in sections]
    verdicts = out / "verdicts.csv"
    write_table(verdict_frame([v for s in sections for v in s.verdicts]), str(verdicts))
    try:
        ver = version("chassistune")
    except PackageNotFoundError:  # pragma: no cover - source tree without metadata
        ver = "unknown"
    kind = "quick run (reduced budgets and seeds)" if quick else "full run"
    html = out / "report.html"
    write_text(html, render(
        f"reproduction of {len(sections)} paper(s)",
        f"chassistune reproduce, {kind}; wall time {wall_time_s:.1f} s.",
        "Each paper's tables put its published numbers beside ours; figures are redrawn from "
        "our runs; the stores under studies/ hold every run.", page, ver))
    figures = tuple(f.path for s in sections for f in s.figures)
    return ReportFiles(html, verdicts, tuple(w.written), figures)
