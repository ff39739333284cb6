"""The reproduction's report: one self-contained HTML page (figures and CSV tables embedded),
the CSV tables under OUT/tables/, the PNG figures under OUT/figures/ and OUT/verdicts.csv; with
`--interactive`, OUT/report_interactive.html beside it.

The first section holds the verdict table of every paper reproduced, the verdict counts per
paper and what the physical bounds say about the papers' distances; then one section per paper:
its setting, the papers' numbers it quotes (source, unit, value exactly as published), budgets
(asked and spent), every table (the paper's numbers beside ours), every figure redrawn from our
runs, and its verdicts. The interactive page has the same sections, its tables sortable, and
adds to each paper's section the study report's plotly figures of the paper's studies
(`reports.sections`: best responses over the baseline, convergence bands, final-cost spread).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import pandas as pd

from chassistune._io import write_text
from chassistune.papers import published
from chassistune.papers.claims import FIELDS
from chassistune.papers.common import (
    BOUND_RATIOS,
    VERDICT_MARKS,
    VERDICTS,
    PaperSection,
    Table,
    Verdict,
)
from chassistune.papers.full_run import quick_banner
from chassistune.papers.notation import NO_VALUE, NOT_PRINTED, notation_table
from chassistune.reports.html import FLAG, Download, FigureView, Item, Section, TableView, render
from chassistune.reports.tables import StudyData, write_table

INTERACTIVE_NAME = "report_interactive.html"
PaperPlots = Callable[[PaperSection], list[Item]]
"""The extra items of a paper's section (the interactive page's plotly figures)."""


@dataclass(frozen=True)
class ReportFiles:
    """The files a reproduction wrote (`interactive`: None without --interactive)."""

    html: Path
    verdicts: Path
    tables: tuple[Path, ...]
    figures: tuple[Path, ...]
    interactive: Path | None = None


VERDICT_COLUMNS = ["paper", "claim", "quote", "verdict", "evidence", *FIELDS[1:]]
"""The verdict table's columns: the paper's sentence beside our verdict."""


def verdict_frame(verdicts: Sequence[Verdict]) -> pd.DataFrame:
    """One row per claim: paper, claim (our English), the paper's quote, verdict, evidence, and
    where the claim stands, what it compares, at which mass, by which rule."""
    return pd.DataFrame(
        [
            {
                "paper": v.paper,
                "claim": v.claim.claim,
                "verdict": v.verdict,
                "evidence": v.evidence,
                **v.claim.columns(),
            }
            for v in verdicts
        ],
        columns=VERDICT_COLUMNS,
    )


def verdict_counts(sections: Sequence[PaperSection]) -> pd.DataFrame:
    """Per paper: its claims and how many get each verdict."""
    return pd.DataFrame(
        [
            {
                "paper": s.key,
                "claims": len(s.verdicts),
                **{w: sum(v.verdict == w for v in s.verdicts) for w in VERDICTS},
            }
            for s in sections
        ]
    )


def counts_text(verdicts: Sequence[Verdict]) -> str:
    """'16 claims: 2 hold, 1 holds in ranking only, 13 do not hold' (verdicts present)."""
    words = [v.verdict for v in verdicts]
    return f"{len(words)} claims: " + ", ".join(
        f"{words.count(w)} {agree(w, words.count(w))}" for w in VERDICTS if w in words
    )


def agree(verdict: str, count: int) -> str:
    """The verdict's verb in agreement with `count` claims: 'holds' -> 'hold', 'does not hold'
    -> 'do not hold' for any count but one."""
    if count == 1:
        return verdict
    return verdict.replace("does not", "do not", 1).replace("holds", "hold", 1)


def quote(value: object) -> str:
    """A published number in full (shortest exact decimal, no exponent padding); blank for
    none."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    return f"{value:.15g}" if isinstance(value, float) else str(value)


def published_table(key: str) -> Table:
    """Every number of paper `key` that the report quotes, with where it is printed and its
    unit."""
    rows = [
        {
            "printed at": q.source,
            "quantity": q.name,
            "road": q.road or "",
            "unit": q.unit,
            "label": label,
            "value": value,
            "note": q.note,
        }
        for q in published.quantities(key)
        for label, value in q.as_printed().items()
    ]
    return Table(
        "published",
        "The paper's numbers quoted in this report",
        pd.DataFrame(rows),
        "Exactly as published (package data chassistune/data/paper_results.toml); the "
        "tables below quote them in their 'paper' columns.",
        quoted=("value",),
    )


class _Writer:
    """Writes each table's CSV once and turns tables and figures into page items."""

    def __init__(self, out: Path) -> None:
        self.out = out
        self.tables_dir = out / "tables"
        self.tables_dir.mkdir(parents=True, exist_ok=True)
        self.written: list[Path] = []
        self.count = 0
        self._ids = 0

    def next_id(self, kind: str) -> str:
        self._ids += 1
        return f"{kind}-{self._ids}"

    def table(self, t: Table, prefix: str) -> TableView:
        path = self.tables_dir / f"{prefix}{t.name}.csv"
        write_table(t.frame, str(path))
        if path not in self.written:
            self.written.append(path)
        self.count += 1
        view = TableView.from_frame(
            t.frame, f"t{self.count}", t.title, t.caption, (Download.from_csv(path, self.out),)
        )
        return replace(view, rows=_shown(t, view.rows))


def _shown(t: Table, rows: list[list[str]]) -> list[list[str]]:
    """The page's cells: quoted columns in full, a verdict with its mark, a published distance
    below its adhesion bound flagged, an empty cell saying why it is empty."""
    out = [list(r) for r in rows]
    for j, col in enumerate(t.frame.columns):
        values = t.frame.iloc[:, j].tolist()
        blank = t.missing.get(col, NOT_PRINTED if col in t.quoted else NO_VALUE)
        for i, v in enumerate(values):
            if col in t.quoted:
                out[i][j] = quote(v)
            elif col == "verdict" and v in VERDICT_MARKS:
                out[i][j] = f"{VERDICT_MARKS[v]} {v}"
            elif col in BOUND_RATIOS and isinstance(v, float) and v < 1.0:
                out[i][j] = f"{out[i][j]} {FLAG} below the bound"
            out[i][j] = out[i][j] or blank
    return out


def _first_section(w: _Writer, sections: Sequence[PaperSection], quick: bool) -> Section:
    verdicts = [v for s in sections for v in s.verdicts]
    bounds = [b for s in sections for b in s.bounds]
    items: list[Item] = [
        w.table(
            Table(
                "verdict_counts",
                "Verdicts per paper",
                verdict_counts(sections),
                "Claims per paper and how many get each verdict.",
            ),
            "",
        ),
        w.table(
            Table(
                "verdicts",
                "Verdict per claim, all papers",
                verdict_frame(verdicts),
                " / ".join(f"{m} {w}" for w, m in VERDICT_MARKS.items())
                + "; quote: the paper's sentence as printed; the evidence gives the numbers and "
                "tests (p-values at alpha 0.05); rule: how we judge the claim.",
            ),
            "",
        ),
    ]
    below = [b for b in bounds if not b.possible]
    intro = (
        (quick_banner(verdicts) + " " if quick else "")
        + f"{counts_text(verdicts)}. Physical bounds: {len(below)} of {len(bounds)} "
        "published stopping distances and times are below the adhesion bound "
        "(v0^2 - v_stop^2)/(2 mu_peak g) or (v0 - v_stop)/(mu_peak g) of their own speed and road"
        + (f" (papers {', '.join(sorted({b.paper for b in below}))})" if below else "")
        + f" ({FLAG} below the bound); no run of ours beats its bound (each table lists "
        "ours / bound and ours time / time bound)."
    )
    if bounds:
        items.append(
            w.table(
                Table(
                    "bounds",
                    "Published distances and times against the physical bound",
                    pd.DataFrame([b.row() for b in bounds]),
                    "published: the paper's stopping distance or time, as printed; bound: the "
                    "shortest distance or time tire adhesion allows from the paper's speed on "
                    "that road (the same bound as the paper's table); a bound that rests on a "
                    "modelling assumption names it, with the strict, assumption-free bound "
                    "beside; reading: what a time below its bound means.",
                    quoted=("published",),
                ),
                "",
            )
        )
    items.append(w.table(notation_table(), ""))
    return Section("Verdicts and physical bounds", intro, items, id="verdicts")


def _paper_section(w: _Writer, s: PaperSection, plots: PaperPlots | None) -> Section:
    prefix = f"{s.key}_"
    items: list[Item] = [
        w.table(
            Table(
                "setting",
                "Setting: our reading, assumptions, the paper's defects",
                pd.DataFrame(s.setting, columns=["topic", "text"]),
            ),
            prefix,
        ),
    ]
    if s.key in published.papers():
        items.append(w.table(published_table(s.key), prefix))
    items += [w.table(t, prefix) for t in s.tables]
    for f in s.figures:
        w.count += 1
        items.append(
            FigureView.from_png(
                f.path, f"f{w.count}", f.title, f.caption, file=f"figures/{f.path.name}"
            )
        )
    if plots is not None:
        items += plots(s)
    items.append(w.table(Table("verdicts", "Verdicts", verdict_frame(s.verdicts)), prefix))
    return Section(s.title, f"Paper key: {s.key}. {counts_text(s.verdicts)}.", items, id=s.key)


def _version() -> str:
    try:
        return version("chassistune")
    except PackageNotFoundError:  # pragma: no cover - source tree without metadata
        return "unknown"


def _page(
    w: _Writer, sections: Sequence[PaperSection], quick: bool, plots: PaperPlots | None = None
) -> list[Section]:
    """Every section of the page, in order."""
    return [_first_section(w, sections, quick)] + [_paper_section(w, s, plots) for s in sections]


def timing_text(wall_time_s: float, studies: Mapping[str, StudyData]) -> str:
    """This command's wall time and the runs' own: a resumed reproduction's wall time covers
    only what it ran, the summed run times every run stored."""
    runs = [r for d in studies.values() for r in d.records]
    summed = sum(r.wall_time_s or 0.0 for r in runs)
    return (
        f"wall time of this command {wall_time_s:.1f} s; the {len(runs)} stored runs took "
        f"{summed:.0f} s summed over runs (their own wall times, on whatever workers ran "
        "them)"
    )


def _heading(sections: Sequence[PaperSection], quick: bool, timing: str) -> tuple[str, str, str]:
    kind = "quick run (reduced budgets and seeds)" if quick else "full run"
    return (
        f"of {sum(s.key in published.papers() for s in sections)} paper(s)",
        f"chassistune reproduce, {kind}; {timing}.",
        "Each paper's tables put its published numbers beside ours; figures are redrawn "
        "from our runs; the stores under studies/ hold every run.",
    )


def write_report(
    out: Path, sections: Sequence[PaperSection], quick: bool, timing: str
) -> ReportFiles:
    """Write report.html, tables/*.csv and verdicts.csv into `out` (figures are there already)."""
    w = _Writer(out)
    page = _page(w, sections, quick)
    verdicts = out / "verdicts.csv"
    write_table(verdict_frame([v for s in sections for v in s.verdicts]), str(verdicts))
    html = out / "report.html"
    write_text(
        html, render(*_heading(sections, quick, timing), page, _version(), kind="Reproduction")
    )
    figures = tuple(f.path for s in sections for f in s.figures)
    return ReportFiles(html, verdicts, tuple(w.written), figures)


def write_interactive(
    out: Path,
    sections: Sequence[PaperSection],
    studies: Mapping[str, Sequence[tuple[str, StudyData]]],
    quick: bool,
    timing: str,
) -> Path:
    """Write OUT/report_interactive.html: the static page's sections (tables sortable) with each
    paper's studies drawn by plotly (`studies`: (study name, data) by paper key)."""
    from chassistune.reports import sections as study_sections
    from chassistune.reports.interactive import PlotlyFigures, interactive_page, require_plotly

    require_plotly()
    w = _Writer(out)
    figures = PlotlyFigures(w)

    def plots(s: PaperSection) -> list[Item]:
        items: list[Item] = []
        for name, data in studies.get(s.key, ()):
            for i, sc in enumerate(data.scenarios, start=1):
                tag = f"{name}-{i:02d}-{study_sections.slug(sc)}"
                items += study_sections.response_items(data, sc, tag, figures)
                items += study_sections.cost_figures(data, sc, tag, figures)
        return items

    html = out / INTERACTIVE_NAME
    write_text(
        html,
        interactive_page(
            *_heading(sections, quick, timing),
            _page(w, sections, quick, plots),
            kind="Reproduction",
        ),
    )
    return html
