"""What the report pages say, checked against the store and the statistics module: tuned gains
with bound flags, the setup (every parameter, the config), verdicts, Friedman only over several
scenarios, generalization metrics, the no-ABS baseline, and tables embedded in the page."""

from __future__ import annotations

import base64
import math
import re
import tomllib
from typing import Any

import numpy as np
import pandas as pd
import pytest

from chassistune import stats
from chassistune._io import file_set
from chassistune.reports.gains import bound_flag
from chassistune.reports.responses import response_sets
from chassistune.reports.sections import Assets, comparison_section
from chassistune.reports.tables import StudyData
from chassistune.reports.versus import BETTER, BOTH_WORSE, SAME, WORSE


def _csv(reported: Any, name: str) -> pd.DataFrame:
    return pd.read_csv(
        reported.dir / "report" / "tables" / f"{name}.csv", keep_default_na=False, na_values=[""]
    )


def test_bound_flag_marks_the_last_percent_of_the_range() -> None:
    assert bound_flag(0.0, 0.0, 100.0) == "lower"
    assert bound_flag(1.0, 0.0, 100.0) == "lower"
    assert bound_flag(1.01, 0.0, 100.0) == ""
    assert bound_flag(98.99, 0.0, 100.0) == ""
    assert bound_flag(99.0, 0.0, 100.0) == "upper"
    assert bound_flag(math.nan, 0.0, 100.0) == ""


def test_gains_table_best_median_every_seed_and_bound_flags(reported) -> None:
    sc = reported.data.scenarios[0]
    gains = _csv(reported, "gains-01-abs-pid-dry-concrete")
    bounds = reported.data.runs(sc)[0].spec.bounds
    for opt in reported.data.optimizers:
        runs = reported.data.runs(sc, opt)
        mine = gains[gains.optimizer == opt].set_index("row")
        assert list(mine.index) == ["best", "median"] + [f"seed {r.spec.seed}" for r in runs]
        best = min(runs, key=lambda r: r.best_cost)
        for g, (lo, hi) in bounds.items():
            assert mine.loc["best", g] == best.best_gains[g]
            assert mine.loc["median", g] == pytest.approx(
                np.median([r.best_gains[g] for r in runs]), rel=1e-12
            )
            for r in runs:
                v = r.best_gains[g]
                flag = mine.loc[f"seed {r.spec.seed}", f"{g} at bound"]
                want = (
                    "lower"
                    if v - lo <= 0.01 * (hi - lo)
                    else "upper"
                    if hi - v <= 0.01 * (hi - lo)
                    else ""
                )
                assert (flag if isinstance(flag, str) else "") == want
    page = reported.static.read_text(encoding="utf-8")
    flagged = (gains.filter(like="at bound").fillna("") != "").to_numpy().sum()
    assert flagged > 0  # this tiny budget leaves gains on the box (ki at 0 or 1e4)
    assert page.count("⚑ lower") + page.count("⚑ upper") >= flagged


def _pre(html: str) -> str:
    import html as h

    return h.unescape(re.search(r"<pre id=\"[^\"]+\">(.*?)</pre>", html, re.S).group(1))


def _drop_none(x: Any) -> Any:
    if isinstance(x, dict):
        return {k: _drop_none(v) for k, v in x.items() if v is not None}
    if isinstance(x, list):
        return [_drop_none(v) for v in x]
    return x


def test_setup_holds_the_config_every_parameter_and_what_was_spent(reported) -> None:
    from chassistune.optimizers.registry import hyperparameters
    from chassistune.scenarios.registry import get_plant

    for page in (reported.static, reported.interactive):
        toml = tomllib.loads(_pre(page.read_text(encoding="utf-8")))
        assert toml == _drop_none(reported.config)
    spec = reported.data.records[0].spec
    params = _csv(reported, "parameters-abs-pid").set_index("parameter")
    for road in spec.test_roads:
        expected = (
            get_plant(spec.plant).scenario(spec.preset, road, spec.controller, spec.params).params()
        )
        for k, v in expected.items():
            if k != "seed":
                shown = str(params.loc[k, road])
                assert shown == (
                    repr(v)
                    if isinstance(v, float)
                    else ", ".join(map(repr, v))
                    if isinstance(v, tuple | list)
                    else str(v)
                ), k
    opts = _csv(reported, "optimizers").set_index("optimizer")
    for opt in reported.data.optimizers:
        runs = [r for r in reported.data.records if r.spec.optimizer == opt]
        hyper = hyperparameters(runs[0].spec.optimizer_name).as_dict()
        assert all(f"{k} = {v}" in opts.loc[opt, "hyperparameters"] for k, v in hyper.items())
        nfev = [r.nfev for r in runs]
        assert str(opts.loc[opt, "evaluations spent"]).startswith(str(min(nfev)))
        assert str(max(nfev)) in str(opts.loc[opt, "evaluations spent"])
    html = reported.static.read_text(encoding="utf-8")
    for text in (
        "report written",
        "versions of the runs",
        "numpy",
        "root seed",
        "gain bounds",
        "report made with",
        "matplotlib",
        "kp in [0, 10000]",
    ):
        assert text in html


def test_verdicts_are_symbols_from_the_compared_side(reported) -> None:
    key = _csv(reported, "key_results")
    ref, other = reported.data.optimizers
    seen = set()
    for sc in reported.data.scenarios:
        row = key[(key.scenario == sc) & (key.quantity == "final cost")].iloc[0]
        res = stats.rank_sum(reported.data.costs(sc, ref), reported.data.costs(sc, other))
        want = {"+": WORSE, "-": BETTER, "=": SAME}[res.sign]
        medians = (row[f"{ref} (reference)"], row[other])
        if want == BETTER and min(medians) > row["default gains"]:
            want = BOTH_WORSE  # no "better" between two optimizers that lost to the defaults
        assert row[f"{other} vs reference"] == want
        assert row[f"{ref} (reference)"] == pytest.approx(np.median(reported.data.costs(sc, ref)))
        seen |= set(key[key.scenario == sc][f"{other} vs reference"])
    assert seen <= {BETTER, SAME, WORSE, BOTH_WORSE}  # never a blank or a bare sign
    html = reported.static.read_text(encoding="utf-8")
    shown = sum(
        html.count(f'<td class="{c}">{v}</td>')
        for c, v in (("same", SAME), ("better", BETTER), ("worse", WORSE), ("worse", BOTH_WORSE))
    )
    assert shown >= len(key)  # each verdict cell styled by its meaning


def test_friedman_ranks_only_over_two_or_more_scenarios(reported, tmp_path) -> None:
    data = reported.data
    one = StudyData(
        data.name,
        tuple(r for r in data.records if r.spec.scenario == data.scenarios[0]),
        data.scenarios[:1],
        data.optimizers,
    )
    with file_set() as staged:
        assert comparison_section(one, data.optimizers[0], Assets(tmp_path, staged)) is None
        full = comparison_section(data, data.optimizers[0], Assets(tmp_path, staged))
    assert full is not None and "Friedman mean ranks" in [i.title for i in full.items]


def test_generalization_reports_stop_ratio_and_lock_time_beside_the_cost(reported) -> None:
    gen = _csv(reported, "generalization")
    assert {"median_cost", "median_distance_ratio", "median_locked_time_s"} <= set(gen.columns)
    for opt in reported.data.optimizers:
        for road in ("dry-concrete", "ice"):
            runs = reported.data.runs(f"abs-pid/{road}", opt)
            row = gen[
                (gen.optimizer == opt) & (gen.tuned_on == road) & (gen.tested_on == road)
            ].iloc[0]
            # re-simulated on the road it was tuned on: the run's own stored metrics
            for k in ("distance_ratio", "locked_time_s"):
                assert row[f"median_{k}"] == pytest.approx(
                    np.median([r.metrics[road][k] for r in runs]), rel=1e-9, abs=1e-12
                )
    ice = gen[(gen.tuned_on == "dry-concrete") & (gen.tested_on == "ice")]
    assert (ice.median_distance_ratio >= 1.0).all()  # no controller beats the physical bound
    html = reported.static.read_text(encoding="utf-8")
    assert html.count('class="group">tested on ice</th>') == len(reported.data.optimizers)


def test_best_responses_are_drawn_over_the_no_abs_baseline(reported) -> None:
    (rs,) = response_sets(reported.data, "abs-pid/dry-concrete")
    base, *best = rs.curves
    assert base.baseline and base.label == "no ABS" and len(best) == 2
    assert max(base.values["slip"]) > 0.95  # the wheel locks without ABS
    for c in best:
        assert not c.baseline
        assert c.values["distance_m"][-1] < base.values["distance_m"][-1]  # ABS stops shorter
        late = c.time_s > 0.5
        assert max(c.values["slip"][late]) < 0.5  # and keeps the wheel rolling


def test_every_table_link_embeds_its_csv(reported) -> None:
    html = reported.static.read_text(encoding="utf-8")
    links = re.findall(
        r'download="([^"]+)"\s+href="data:text/csv;charset=utf-8;base64,'
        r'([^"]+)"',
        html,
    )
    assert {name for name, _ in links} == {
        p.name for p in (reported.dir / "report" / "tables").glob("*.csv")
    }
    for name, data in links:
        assert base64.b64decode(data) == (reported.dir / "report" / "tables" / name).read_bytes()


def test_config_toml_round_trips_awkward_values() -> None:
    from chassistune.reports.toml_text import to_toml

    config = {
        "study": {
            "name": 'a "quoted" name',
            "description": "tabs\tand ünïcode",
            "seeds": [0, 2, 5],
            "seed": 7,
        },
        "scenarios": [
            {
                "name": "x",
                "params": {"mu peak": 0.9, "mode": "a\\b"},
                "bounds": {"kp": [0.0, 1e4]},
                "preset": None,
            },
            {"name": "y", "params": {}, "flag": True},
        ],
        "budget": {"pop_size": 6, "iterations": None, "evaluations": 120},
    }
    assert tomllib.loads(to_toml(config)) == _drop_none(config)
