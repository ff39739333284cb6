"""The papers' figures and tables beyond the results (the session's quick `reproduce all`): every
figure the papers print is redrawn (by file name), with the papers' comparators; the papers'
parameter and rule tables are tables (the rule tables equal the rule base files cell by cell); the
tuned parameter sets shown are the stores' median runs; every caption says what is drawn; and the
page explains its notation and its empty cells once."""

from __future__ import annotations

import html
import re
from dataclasses import replace
from html.parser import HTMLParser

import numpy as np
import pandas as pd
import pytest

from chassistune.fuzzy.loader import builtin_path, load_rulebase
from chassistune.papers.claims import Claim
from chassistune.papers.common import (
    FAILS,
    HOLDS,
    RANKING_ONLY,
    UNCHECKED,
    Verdict,
    median_run,
)
from chassistune.papers.param_tables import PARAMETER_TABLES, SAME, Printed
from chassistune.papers.report import counts_text
from chassistune.papers.supplement import CONTROLLER_STUDIES
from chassistune.papers.tuned import default_parameters
from chassistune.reports.tables import load_study
from chassistune.studies.store import open_study

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
FIGURES = [
    "derlsp-ao-abs_fig2_mu_slip",
    "deffao-vehicle-abs_fig2_mu_slip",
    "iabc-suspension_fig2_road_profile",
    "deffao-vehicle-abs_fig4_membership",
    "deffao-vehicle-abs_fig6_tuned_factors",
    "deffao-vehicle-abs_fig7_dry-concrete",
    "deffao-vehicle-abs_fig8_mu-jump",
    "deffao-vehicle-abs_fig9_split-mu",
    "iabc-suspension_fig7_responses",
    *(
        f"{k}_tuning_convergence"
        for k in ("derlsp-ao-abs", "iabc-suspension", "deffao-vehicle-abs", "fuzzy-immune-abs")
    ),
]
"""The papers' figures the reproduction must draw."""
TABLES = [
    "derlsp-ao-abs_table1_roads",
    "iabc-suspension_table1_quarter_car",
    "deffao-vehicle-abs_table1_roads",
    "deffao-vehicle-abs_table2_vehicle",
    "deffao-vehicle-abs_table3_rules",
    "fuzzy-immune-abs_table1_rules",
    "fuzzy-immune-abs_table2_vehicle",
    "derlsp-ao-abs_tuned_pid",
    "iabc-suspension_tuned_pid",
    "deffao-vehicle-abs_tuned_fuzzy-pid",
    *(f"fuzzy-immune-abs_tuned_{c}" for c in ("pid", "fuzzy-pid", "fuzzy-immune-pid")),
    "notation",
]
RULE_TABLES = {
    "deffao-vehicle-abs_table3_rules": "deffao",
    "fuzzy-immune-abs_table1_rules": "immune",
}


class _Page(HTMLParser):
    """Figure titles with their captions, and every table cell, of a report page."""

    def __init__(self) -> None:
        super().__init__()
        self.figures: list[tuple[str, str]] = []
        self.cells: list[str] = []
        self._in: str | None = None
        self._text = ""
        self._title = ""
        self._figure = False

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag == "figure":
            self._figure = True
        if tag in ("h3", "figcaption", "td"):
            self._in, self._text = tag, ""

    def handle_endtag(self, tag: str) -> None:
        if tag != self._in:
            return
        if tag == "td":
            self.cells.append(self._text.strip())
        elif tag == "h3" and self._figure:
            self._title = self._text
        elif tag == "figcaption":
            self.figures.append((self._title, self._text))
            self._figure = False
        self._in = None

    def handle_data(self, data: str) -> None:
        if self._in:
            self._text += data


@pytest.fixture(scope="module")
def report_page(reproduced) -> _Page:
    parser = _Page()
    parser.feed((reproduced.out / "report.html").read_text(encoding="utf-8"))
    return parser


def _table(reproduced, name: str) -> pd.DataFrame:
    """A written table; a paper's column as text (its values as printed)."""
    path = reproduced.out / "tables" / f"{name}.csv"
    return pd.read_csv(path, keep_default_na=False, dtype={"paper": str})


def test_the_quick_reproduction_draws_every_figure_of_the_papers(reproduced) -> None:
    for name in FIGURES:
        path = reproduced.out / "figures" / f"{name}.png"
        assert path.read_bytes()[:8] == PNG_MAGIC, name


def test_the_quick_reproduction_writes_the_papers_tables(reproduced) -> None:
    for name in TABLES:
        assert len(_table(reproduced, name)) > 0, name


def test_the_comparators_are_drawn_as_in_the_papers(report_page) -> None:
    titles = [t for t, _ in report_page.figures]
    for fig, road in (("7", "dry-concrete"), ("8", "mu-jump"), ("9", "split-mu")):
        title = next(t for t in titles if f"Fig. {fig} redrawn ({road})" in t)
        assert all(c in title for c in ("PID", "fuzzy PID", "AO-", "DEFFAO-fuzzy PID")), title
    fig7 = next(t for t in titles if "Fig. 7 redrawn: time responses" in t)
    assert "/ ABC-PID /" in fig7 and "IABC-PID" in fig7


def test_every_figure_caption_says_what_it_draws(report_page) -> None:
    assert len(report_page.figures) >= len(FIGURES)
    for title, caption in report_page.figures:
        assert re.search(r"\b(un)?tuned\b|no controller", caption, re.I), title


@pytest.mark.parametrize("name", sorted(RULE_TABLES))
def test_a_rule_table_equals_its_rule_base_cell_by_cell(reproduced, name) -> None:
    rb = load_rulebase(RULE_TABLES[name])
    table = _table(reproduced, name).set_index(f"{rb.inputs[0].name} \\ {rb.inputs[1].name}")
    assert list(table.index) == list(rb.inputs[0].set_names)
    assert list(table.columns) == list(rb.inputs[1].set_names)
    rules = {(r[0], r[1]): ",".join(r[2:]) for r in rb.rules}
    assert {(a, b): table.loc[a, b] for a in table.index for b in table.columns} == rules
    # the paper's table as transcribed in the rule base file's header comment, cell by cell
    text = builtin_path(RULE_TABLES[name]).read_text(encoding="utf-8")
    words = [line.lstrip("#").split() for line in text.splitlines() if line.startswith("#")]
    printed = [w[1:] for w in words if len(w) == 1 + len(table.columns) and w[0] in table.index]
    assert printed == table.to_numpy().tolist()


@pytest.mark.parametrize("key", sorted(PARAMETER_TABLES))
def test_parameter_tables_give_a_reason_wherever_ours_differs(reproduced, key) -> None:
    for build in PARAMETER_TABLES[key]:
        t = build()
        if "paper" not in t.frame.columns or "why they differ" not in t.frame.columns:
            continue
        frame = _table(reproduced, f"{key}_{t.name}")
        for _, row in frame.iterrows():
            try:
                printed = float(str(row["paper"]).replace(" ", "").replace("×10^", "e"))
            except ValueError:  # 'not given'
                printed = np.nan
            same = bool(np.isclose(printed, float(row["ours"]), rtol=1e-9, atol=0.0))
            assert (row["why they differ"] == SAME) == same, row.to_dict()


def test_a_printed_value_ours_differs_from_needs_a_reason() -> None:
    entry = Printed(
        "p", "Table 1", "yaw inertia", "Iz", "kg m2", "1.44", "paper-deffao.yaw_inertia_kg_m2"
    )
    with pytest.raises(ValueError, match="no reason"):
        entry.row()
    assert replace(entry, why="read as 1440").row()["why they differ"] == "read as 1440"
    assert replace(entry, printed="1440").row()["why they differ"] == SAME


def test_the_yaw_inertia_is_shown_as_printed_beside_ours(reproduced) -> None:
    t = _table(reproduced, "deffao-vehicle-abs_table2_vehicle").set_index("symbol")
    assert t.loc["Iz", "paper"] == "1.44" and float(t.loc["Iz", "ours"]) == 1440.0
    assert "1440" in t.loc["Iz", "why they differ"]


@pytest.mark.parametrize("key", sorted(CONTROLLER_STUDIES))
def test_the_tuned_sets_shown_are_the_stores_median_runs(reproduced, key) -> None:
    with open_study(reproduced.out / "studies" / f"{CONTROLLER_STUDIES[key]}-quick") as store:
        data = load_study(store)
    shown = 0
    for cell in data.scenarios:
        spec = data.runs(cell)[0].spec
        frame = _table(reproduced, f"{key}_tuned_{spec.controller}")
        mine = frame[frame["cell"] == cell].set_index("run")
        defaults = default_parameters(spec)
        assert [float(mine.loc["defaults (untuned)", n]) for n in spec.bounds] == [
            defaults[n] for n in spec.bounds
        ]
        for opt in data.optimizers:
            rec = median_run(data.runs(cell, opt))
            assert [float(mine.loc[opt, n]) for n in spec.bounds] == [
                rec.best_gains[n] for n in spec.bounds
            ]
            assert float(mine.loc[opt, "final cost"]) == rec.best_cost
            shown += 1
    assert shown > 0


def test_the_page_names_the_tables_folder_it_wrote(reproduced) -> None:
    text = (reproduced.out / "report.html").read_text(encoding="utf-8")
    assert "report/tables/" not in text
    assert text.count("also in tables/ beside it") == text.count('<p class="source">data:')


def test_the_page_explains_its_notation_and_its_empty_cells(reproduced, report_page) -> None:
    notation = _table(reproduced, "notation")
    for mark in ("(p = 0.33)", "single values", "not printed", "never settles", "untuned"):
        assert notation["notation"].str.contains(mark, regex=False).any(), mark
    assert "" not in report_page.cells
    assert not [c for c in report_page.cells if re.search(r"\bnan\b", c)]
    text = html.unescape((reproduced.out / "report.html").read_text(encoding="utf-8"))
    assert "nan s" not in text


def test_verdict_counts_agree_with_their_number() -> None:
    words = [HOLDS] * 2 + [RANKING_ONLY] + [FAILS] * 13 + [UNCHECKED]
    verdicts = [
        Verdict(Claim("p", f"c{i}", "q", f"claim {i}", "l", "c", "r"), w, "")
        for i, w in enumerate(words)
    ]
    assert counts_text(verdicts) == (
        "17 claims: 2 hold, 1 holds in ranking only, 13 do not hold, 1 cannot be checked"
    )
