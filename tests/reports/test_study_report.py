"""`study report` and `study export`: tables, figures, a self-contained page, the run table."""

from __future__ import annotations

import base64
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from chassistune import stats
from chassistune.reports.tables import load_study, runs_table
from chassistune.studies.executors import SerialExecutor
from chassistune.studies.runner import run_study
from chassistune.studies.spec import load_plan
from chassistune.studies.store import Store, open_study
from chassistune.studies.worker import failed_result

CONFIG = """
[study]
name = "report-test"
description = "A tiny study <with> characters to escape & such"
seeds = 4

[[scenarios]]
name = "qc"
plant = "quarter-car"
roads = ["iso-b", "iso-c"]
tune_roads = ["iso-b", "iso-c"]
controller = "pid"
objective = "rms-ratio-exact"
bounds = { kp = [0.0, 500.0], ki = [0.0, 500.0], kd = [0.0, 500.0] }

[[scenarios]]
name = "sky"
plant = "quarter-car"
preset = "typical"
controller = "skyhook"

[[optimizers]]
name = "pso"

[[optimizers]]
name = "de"

[[optimizers]]
name = "ga"

[budget]
pop_size = 6
iterations = 3
"""
N_RUNS = 4 * 3 * 4


@pytest.fixture(scope="module")
def study(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("report")
    config = folder / "study.toml"
    config.write_text(CONFIG)
    plan = load_plan(config)
    out = folder / "study"
    # every run but one completes; that one is recorded failed (a worker lost, say)
    run_study(plan, out, SerialExecutor())
    lost = next(s for s in plan.runs if s.scenario == "sky/iso-b" and s.optimizer == "ga")
    with Store.create(out) as store:
        store.record(lost, failed_result(lost, "worker lost <on purpose>"))
    return out


class _Page(HTMLParser):
    """Collects the contents list, element ids, tables (rows) and embedded images."""

    def __init__(self) -> None:
        super().__init__()
        self.contents: list[tuple[str, str]] = []
        self.ids: dict[str, str] = {}
        self.rows: dict[str, int] = {}
        self.images: dict[str, str] = {}
        self.external: list[str] = []
        self._stack: list[str] = []  # ids of the open table/figure
        self._in_nav = False

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = dict(attrs)
        if tag == "nav":
            self._in_nav = True
        if self._in_nav and tag == "a" and "data-kind" in a:
            self.contents.append((str(a["href"]).lstrip("#"), str(a["data-kind"])))
        if a.get("id"):
            self.ids[str(a["id"])] = tag
            if tag in ("table", "figure"):
                self._stack.append(str(a["id"]))
        if tag == "tr" and self._stack:
            self.rows[self._stack[-1]] = self.rows.get(self._stack[-1], 0) + 1
        if tag == "img":
            self.images[self._stack[-1]] = str(a["src"])
        if tag in ("script", "link", "iframe") or (
            tag == "img" and not str(a.get("src", "")).startswith("data:")
        ):
            self.external.append(tag)

    def handle_endtag(self, tag: str) -> None:
        if tag == "nav":
            self._in_nav = False
        if tag in ("table", "figure") and self._stack:
            self._stack.pop()


@pytest.fixture(scope="module")
def report(study: Path) -> tuple[Path, _Page]:
    from chassistune.cli.main import main

    with pytest.raises(SystemExit) as exc:
        main(["study", "report", str(study), "--reference", "de"])
    assert exc.value.code == 0
    html = study / "report.html"
    page = _Page()
    page.feed(html.read_text(encoding="utf-8"))
    page.close()
    return html, page


def test_the_page_parses_and_holds_every_table_and_figure_it_lists(report, study):
    html, page = report
    kinds = [k for _, k in page.contents]
    assert kinds.count("table") >= 10 and kinds.count("figure") >= 10
    assert kinds.count("code") == 1  # the config
    for target, kind in page.contents:
        assert page.ids.get(target) == {"code": "pre"}.get(kind, kind)
        if kind == "table":
            assert page.rows.get(target, 0) >= 2  # a header and at least one row
        elif kind == "figure":
            src = page.images[target]
            assert src.startswith("data:image/png;base64,")
            assert base64.b64decode(src.split(",", 1)[1])[:8] == b"\x89PNG\r\n\x1a\n"
    assert page.external == []  # self-contained
    text = html.read_text(encoding="utf-8")
    assert "&lt;with&gt; characters to escape &amp; such" in text
    assert "worker lost &lt;on purpose&gt;" in text
    assert 'download="summary.csv" href="data:text/csv' in text and "report/figures/" in text
    for name in (
        "summary",
        "rank_sum",
        "rank_sum_counts",
        "friedman",
        "posthoc",
        "generalization",
        "failures",
    ):
        assert (study / "report" / "tables" / f"{name}.csv").is_file()
    pngs = list((study / "report" / "figures").glob("*.png"))
    assert len(pngs) == kinds.count("figure")


def test_summary_and_rank_sums_match_the_statistics_module(report, study):
    with open_study(study) as store:
        data = load_study(store)
    summary = pd.read_csv(study / "report" / "tables" / "summary.csv")
    costs = {o: data.costs("qc/iso-b", o) for o in data.optimizers}
    row = summary[
        (summary.scenario == "qc/iso-b")
        & (summary.optimizer == "pso")
        & (summary.quantity == "best_cost")
    ].iloc[0]
    expected = stats.summary(costs["pso"])
    for key in ("mean", "std", "best", "worst", "median"):
        assert row[key] == pytest.approx(expected[key], rel=1e-12)
    assert set(summary.quantity) >= {
        "best_cost",
        "body_acc_rms",
        "objective_exact",
        "body_acc_rms@iso-b",
    }
    sky_ga = summary[(summary.scenario == "sky/iso-b") & (summary.optimizer == "ga")]
    assert (sky_ga.failed == 1).all() and (sky_ga.n == 3).all()
    ranks = pd.read_csv(study / "report" / "tables" / "rank_sum.csv")
    r = ranks[(ranks.scenario == "qc/iso-b") & (ranks.optimizer == "pso")].iloc[0]
    assert r.reference == "de"
    assert r.sign == stats.rank_sum(costs["de"], costs["pso"]).sign
    friedman = pd.read_csv(study / "report" / "tables" / "friedman.csv")
    assert list(friedman.optimizer) == ["pso", "de", "ga"]
    assert friedman.mean_rank.sum() == pytest.approx(6.0)


def test_generalization_matrix_tuned_on_x_tested_on_y(report, study):
    gen = pd.read_csv(study / "report" / "tables" / "generalization.csv")
    qc = gen[(gen.group == "qc") & (gen.optimizer == "pso")]
    assert set(qc.tuned_on) == {"iso-b", "iso-c", "iso-b+iso-c"}
    assert set(qc.tested_on) == {"iso-b", "iso-c"}
    assert (qc.n == 4).all()
    with open_study(study) as store:
        runs = [
            r
            for r in store.records()
            if r.spec.scenario == "qc/iso-c" and r.spec.optimizer == "pso"
        ]
    diag = qc[(qc.tuned_on == "iso-c") & (qc.tested_on == "iso-c")].median_cost.iloc[0]
    assert diag == pytest.approx(float(np.median([r.best_cost for r in runs])), rel=1e-12)
    assert "sky" not in set(gen.group)  # one road: no matrix


def test_export_csv_and_parquet_one_row_per_run(cli, study, tmp_path):
    frames = {}
    for fmt in ("csv", "parquet"):
        out = tmp_path / f"runs.{fmt}"
        r = cli("study", "export", str(study), "--format", fmt, "--output", str(out))
        assert r.code == 0, r.err
        frames[fmt] = pd.read_csv(out) if fmt == "csv" else pd.read_parquet(out)
    df = frames["parquet"]
    assert len(df) == N_RUNS
    for col in (
        "scenario",
        "plant",
        "road",
        "controller",
        "optimizer",
        "seed",
        "status",
        "best_cost",
        "nfev",
        "gain_kp",
        "gain_ki",
        "gain_kd",
        "gain_c_sky",
        "cost@iso-b",
        "cost@iso-c",
        "metric_body_acc_rms",
        "metric_body_acc_rms@iso-c",
    ):
        assert col in df.columns, col
    assert df.groupby(["scenario", "optimizer", "seed"]).size().max() == 1
    assert set(df.status) == {"completed", "failed"}
    assert df.loc[df.road == "iso-b+iso-c", "metric_body_acc_rms"].isna().all()
    csv = frames["csv"]
    assert np.array_equal(csv.best_cost.to_numpy(), df.best_cost.to_numpy(), equal_nan=True)
    with open_study(study) as store:
        assert df.drop(columns=["versions"]).equals(
            runs_table(list(store.records())).drop(columns=["versions"])
        )


def test_report_and_export_bad_input(cli, study, tmp_path):
    r = cli("study", "report", str(study), "--reference", "annealing")
    assert r.code == 2 and r.err.startswith("chassistune: error: --reference")
    r = cli("study", "export", str(study), "--format", "xlsx", "--output", str(tmp_path / "x"))
    assert r.code == 2 and len(r.err.strip().splitlines()) == 1
    r = cli(
        "study", "export", str(study), "--format", "csv", "--output", str(tmp_path / "no" / "x.csv")
    )
    assert r.code == 2 and "--output" in r.err


def test_quarter_car_overlay_runs_every_best_on_one_road_over_the_passive(study):
    from chassistune.reports.responses import response_sets

    with open_study(study) as store:
        data = load_study(store)
    (rs,) = response_sets(data, "qc/iso-b")
    best = min(data.runs("qc/iso-b"), key=lambda r: (r.best_cost, r.spec.seed))
    assert rs.seed == best.spec.seed  # one road realization for every curve
    base, *curves = rs.curves
    assert base.baseline and base.label == "passive" and len(curves) == 3
    assert [p.signal for p in rs.panels] == ["body_acc_m_s2", "susp_travel_m", "tire_defl_m"]
    for c in rs.curves:
        assert c.time_s[-1] <= 5.0 and c.time_s.size <= 2500
    rms = {c.label: float(np.sqrt(np.mean(c.values["body_acc_m_s2"] ** 2))) for c in rs.curves}
    # tuned for the RMS ratio: the best PID eases the body (on the shown window too)
    assert min(v for k, v in rms.items() if k != "passive") < rms["passive"]


def test_interactive_without_plotly_says_which_extra_in_one_line(cli, study, monkeypatch):
    import sys

    page = study / "report.html"
    before = page.stat().st_mtime_ns if page.exists() else None
    monkeypatch.setitem(sys.modules, "plotly.graph_objects", None)  # import fails
    r = cli("study", "report", str(study), "--interactive")
    assert r.code == 2 and len(r.err.strip().splitlines()) == 1
    assert "chassistune[interactive]" in r.err and r.err.startswith("chassistune: error:")
    assert (page.stat().st_mtime_ns if page.exists() else None) == before  # nothing written
    assert not (study / "report_interactive.html").exists()
