"""Every claim is declared as data (the paper's sentence, where it stands, what it compares, the
rule) and gets one verdict row in the quick and in the full configuration; the quick page opens
with its banner; every published time below its physical bound is flagged and none of ours is."""

from __future__ import annotations

import re
from html import unescape
from pathlib import Path

import pandas as pd
import pytest

from chassistune.papers import common, full_run, standard
from chassistune.papers.claims import FIELDS, Claim
from chassistune.papers.reproduce import PAPERS, plan_reproduction
from chassistune.reports.tables import load_study
from chassistune.scenarios.registry import get_plant
from chassistune.studies.store import open_study

SEEDS = Path("/work/shared/seeds")
PAPER_FILES = {
    "derlsp-ao-abs": "000_4940b2aae5319300.txt",
    "iabc-suspension": "001_3bbbcac677226f9f.txt",
    "deffao-vehicle-abs": "003_2d283ad9cef99d8f.txt",
    "fuzzy-immune-abs": "004_3b0b373ef99b53ac.txt",
}
CJK = re.compile(r"[\u4e00-\u9fff]")
ALL_CLAIMS = [c for m in PAPERS.values() for c in m.CLAIMS] + list(standard.CLAIMS)


def test_every_declared_claim_has_its_sentence_where_it_stands_and_a_rule() -> None:
    for key, module in PAPERS.items():
        names = [c.name for c in module.CLAIMS]
        assert len(set(names)) == len(names), key
        english = [c.claim for c in module.CLAIMS]
        assert len(set(english)) == len(english), key
        for c in module.CLAIMS:
            assert c.paper == key
            assert CJK.search(c.quote) or c.quote.startswith("Tab."), c.name
            assert c.location and c.compares and c.rule and c.mass
    with pytest.raises(ValueError, match="empty rule"):
        Claim("p", "n", "原文", "claim", "Fig. 1", "A against B", " ")


@pytest.mark.skipif(not SEEDS.is_dir(), reason="the papers' texts are not on this machine")
def test_every_quoted_sentence_is_the_papers_own_text() -> None:
    # table quotes ('Tab. ...') name a table and its rows; every sentence is quoted verbatim
    for key, module in PAPERS.items():
        text = re.sub(r"\s+", "", (SEEDS / PAPER_FILES[key]).read_text(encoding="utf-8"))
        for c in module.CLAIMS:
            if not c.quote.startswith("Tab."):
                for piece in c.quote.split(" / "):
                    assert re.sub(r"\s+", "", piece) in text, (key, c.name, piece)


def _verdicts(reproduced) -> pd.DataFrame:
    return pd.read_csv(reproduced.out / "verdicts.csv", dtype=str, keep_default_na=False)


def test_every_verdict_row_has_a_declaration_and_every_declaration_a_verdict(reproduced) -> None:
    df = _verdicts(reproduced)
    assert list(df.columns[:5]) == ["paper", "claim", "quote", "verdict", "evidence"]
    assert set(FIELDS) <= set(df.columns)
    declared = {(c.paper, c.claim): c for c in ALL_CLAIMS}
    assert sorted(zip(df["paper"], df["claim"], strict=True)) == sorted(declared)
    for row in df.itertuples():
        c = declared[(row.paper, row.claim)]
        assert (row.quote, row.location, row.compares, row.mass, row.rule) == (
            c.quote,
            c.location,
            c.compares,
            c.mass,
            c.rule,
        )
        assert row.verdict in common.VERDICTS and len(row.evidence) > 10


@pytest.fixture(scope="module")
def full_sections(reproduced, tmp_path_factory):
    """Every paper's section built in the full configuration from the quick run's stores."""
    runs = plan_reproduction("all", quick=True)
    data = {}
    for r in runs:
        with open_study(r.folder(reproduced.out)) as store:
            data[r.name] = load_study(store)
    ctx = common.Context(
        tmp_path_factory.mktemp("figures"), data, {r.name: r.configs for r in runs}, quick=False
    )
    return [m.build(ctx) for m in PAPERS.values()] + [standard.build()]


@pytest.mark.slow
def test_every_declaration_has_a_verdict_in_the_full_configuration(full_sections) -> None:
    judged = [v.claim for s in full_sections for v in s.verdicts]
    assert sorted(judged, key=lambda c: (c.paper, c.name)) == sorted(
        ALL_CLAIMS, key=lambda c: (c.paper, c.name)
    )


def test_the_quick_page_opens_with_what_its_budget_can_decide(reproduced) -> None:
    html = (reproduced.out / "report.html").read_text(encoding="utf-8")
    record = full_run.last_full_run()
    start = html.index("Quick run: a few seeds")
    assert start < html.index('id="t1"')  # before the first table of the first section
    banner = unescape(html[start : html.index("</p>", start)])
    assert "cannot make a ranking of tuned runs significant" in banner
    assert f"Last full run: {record.date}" in banner and record.command in banner
    assert record.current_claims
    page = {(r.paper, r.claim): r.verdict for r in _verdicts(reproduced).itertuples()}
    recorded = {(v.paper, v.claim): v for v in record.verdicts}
    assert set(recorded) == {(c.paper, c.claim) for c in ALL_CLAIMS if c not in standard.CLAIMS}
    # the record's quick verdicts are this build's: its sources judge as these do
    assert {k: v.quick for k, v in recorded.items()} == {k: page[k] for k in recorded}
    differ = [v for v in record.verdicts if v.full != v.quick]
    assert differ and all(v.quick == common.UNDECIDED for v in differ)
    assert f"decided {len(differ)} that the quick run leaves undecided" in banner
    assert "reversed" not in banner
    for v in differ:
        assert v.claim in banner
    undecided = (_verdicts(reproduced)["verdict"] == common.UNDECIDED).sum()
    assert undecided > 0 and f"({undecided} here)" in banner


def test_a_record_of_the_current_claims_is_compared_with_this_page() -> None:
    c = ALL_CLAIMS[0]
    shown = [common.Verdict(c, common.UNDECIDED, "evidence")]
    same = full_run.RecordedVerdict(c.paper, c.claim, common.UNDECIDED, common.FAILS)
    other = full_run.RecordedVerdict(c.paper, c.claim, common.HOLDS, common.FAILS)
    record = full_run.FullRun("d", "cmd", "src", True, "", (same,))
    assert full_run.decided_differently(record, shown) == []
    record = full_run.FullRun("d", "cmd", "src", True, "", (other,))
    assert full_run.decided_differently(record, shown) == [other]


IMPOSSIBLE_TIMES = {
    *(("derlsp-ao-abs", "ice", c) for c in ("PID", "fuzzy PID", "GA-PID", "AO-PID")),
    ("derlsp-ao-abs", "ice", "DERLSP-AO-PID"),
    ("fuzzy-immune-abs", "asphalt-0.8", "fuzzy immune PID"),
}
"""000's ice times (about a quarter of the minimum) and 004's 3 s from 30 m/s on mu 0.8."""
PRESETS = {
    "derlsp-ao-abs": ("abs-wheel", "paper-derlsp-ao"),
    "fuzzy-immune-abs": ("abs-wheel", "paper-fuzzy-immune"),
    "deffao-vehicle-abs": ("abs-vehicle", "paper-deffao"),
}


def test_every_published_time_below_its_bound_is_flagged(reproduced) -> None:
    bounds = pd.read_csv(reproduced.out / "tables" / "bounds.csv")
    times = bounds[bounds["quantity"] == "braking time"]
    assert set(times["paper"]) == set(PRESETS)
    for row in times.to_dict("records"):
        plant, preset = PRESETS[row["paper"]]
        if plant == "abs-wheel":  # (v0 - v_stop) / (mu_peak g), computed here from the tire
            sc = get_plant(plant).scenario(preset, row["road"], "pid", {}, 0)
            pp = sc.plant_params
            expected = (pp.v0_m_s - pp.v_stop_m_s) / (sc.mu_peak * pp.g_m_s2)
            assert row["bound"] == pytest.approx(expected)
        assert row["possible"] == ("no" if row["published"] < row["bound"] else "yes")
    below = {(r.paper, r.road, r.controller) for r in times.itertuples() if r.possible == "no"}
    assert below == IMPOSSIBLE_TIMES
    modelled = bounds[bounds["road"].isin(["split-mu", "mu-jump"])]
    assert (modelled["bound assumes"].str.contains("our road layout|equal left and right")).all()
    assert (modelled["strict bound"] < modelled["bound"]).all()


def test_no_time_of_ours_is_below_its_bound(reproduced) -> None:
    checked = 0
    for csv in (reproduced.out / "tables").glob("*.csv"):
        df = pd.read_csv(csv)
        if "ours time / time bound" in df:
            assert "time bound (s)" in df and "bound (m)" in df, csv.name
            assert (df["ours time / time bound"] >= 1 - 1e-12).all(), csv.name
            checked += len(df)
    assert checked >= 5 * 3 + 4 * 3 + 7 * 2
