"""The study report's baseline: the default gains' cost and key metrics beside every
optimizer's medians, its row in each final-cost table, and no "better" claimed between two
optimizers that both lost to the defaults."""

from __future__ import annotations

import math

import pandas as pd
import pytest

from chassistune._io import file_set
from chassistune.reports import versus
from chassistune.reports.baseline import LABEL, Baseline, default_baseline
from chassistune.studies.problems import problem_for


def _key_results(reported) -> pd.DataFrame:
    return pd.read_csv(reported.dir / "report" / "tables" / "key_results.csv")


def test_the_key_results_show_the_default_gains_cost(reported):
    key = _key_results(reported)
    for sc in reported.data.scenarios:
        spec = reported.data.runs(sc)[0].spec
        problem = problem_for(spec.model_dump(), spec.scenario_seed, spec.seed_sequence())
        defaults = problem.scenarios[0].gains_array(None)
        row = key[(key.scenario == sc) & (key.quantity == "final cost")].iloc[0]
        assert row[LABEL] == pytest.approx(float(problem(defaults[None, :])[0]), rel=1e-12)
        road = problem.roads[0]
        name = "stop_distance_m" if len(problem.roads) == 1 else f"stop_distance_m@{road}"
        metric = key[(key.scenario == sc) & (key.quantity == name)].iloc[0]
        stop = problem.scenarios[0].trace(defaults).metrics["stop_distance_m"]
        assert metric[LABEL] == pytest.approx(stop, rel=1e-12)


def test_every_final_cost_table_has_the_default_gains_row(reported):
    html = reported.static.read_text(encoding="utf-8")
    assert html.count(f"<td>{LABEL}</td>") == len(reported.data.scenarios)
    summary = pd.read_csv(reported.dir / "report" / "tables" / "key_results.csv")
    assert summary[LABEL].notna().sum() >= len(reported.data.scenarios)


@pytest.mark.parametrize("default_cost", [0.0, math.inf])
def test_better_is_never_claimed_when_both_medians_lose_to_the_defaults(
    reported, monkeypatch, default_cost
):
    sc = reported.data.scenarios[0]
    base = default_baseline(reported.data, sc)
    assert base is not None
    values = {q: default_cost for q in base.values}
    monkeypatch.setattr(versus, "default_baseline", lambda data, s: Baseline(base.gains, values))
    monkeypatch.setattr(versus, "verdict", lambda ref, other: versus.BETTER)
    ref, other = reported.data.optimizers
    row = versus.metrics_by_optimizer(reported.data, sc, ref).iloc[0]
    want = versus.BOTH_WORSE if default_cost == 0.0 else versus.BETTER
    assert row[f"{other} vs reference"] == want


class _NoFigures:
    """Figures as placeholders: the tables are what is checked."""

    def __getattr__(self, name):
        from chassistune.reports.html import CodeView

        return lambda *args, **kwargs: CodeView(name, name, "")


@pytest.mark.parametrize("default_cost", [0.0, math.inf])
def test_the_final_cost_table_claims_no_better_when_both_lose_to_the_defaults(
    reported, monkeypatch, tmp_path, default_cost
):
    from chassistune.reports import sections, tables

    data = reported.data
    sc = data.scenarios[0]
    base = default_baseline(data, sc)
    values = {q: default_cost for q in base.values}
    monkeypatch.setattr(sections, "default_baseline", lambda d, s: Baseline(base.gains, values))
    monkeypatch.setattr(sections, "verdict_of_sign", lambda sign: versus.BETTER)
    ref, other = data.optimizers
    summary, ranks = tables.summary_table(data), tables.rank_sum_table(data, ref)
    with file_set() as staged:
        assets = sections.Assets(tmp_path, staged)
        sources = {"summary": assets.csv(summary, "summary"), "rank_sum": assets.csv(ranks, "r")}
        section = sections.scenario_section(
            data, sc, 1, ref, summary, ranks, sources, assets, _NoFigures()
        )
    table = next(t for t in section.items if t.title.startswith("Final cost"))
    rows = {row[0]: row[-1] for row in table.rows}
    assert rows[LABEL] == "baseline"
    assert rows[other] == (versus.BOTH_WORSE if default_cost == 0.0 else versus.BETTER)
