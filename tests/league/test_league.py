"""The league end to end at the quick budget: every law of the registry on each ABS plant is
tuned, scored on every held-out case, ranked; no stop beats its adhesion bound; a second call
resumes (nothing re-run, the same scores); the process executor gives the same numbers."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest

from chassistune.cli.main import main
from chassistune.controllers import laws
from chassistune.league.cases import PLANTS
from chassistune.league.page import PAGE, SCORES_CSV, ranking
from chassistune.league.plan import Setting, league_laws


def _league(out: Path, *extra: str) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["league", "--quick", "--out", str(out), *extra])
    assert exc.value.code == 0


@pytest.fixture(scope="module")
def quick(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("league")
    _league(out)
    return out


def test_every_registered_law_meets_every_held_out_case(quick: Path) -> None:
    scores = pd.read_csv(quick / SCORES_CSV)
    for name, lp in PLANTS.items():
        tuned, untuned = league_laws(lp, Setting(tuple(PLANTS)))
        assert set(tuned + untuned) == set(scores[scores.plant == name].law)
        every = {s.name for s in laws.for_plant(name)}
        missing = every - set(tuned + untuned)
        assert all(laws.get(n).ecu is None for n in missing)  # only laws the ECU cannot run
        for law in tuned:
            rows = scores[(scores.plant == name) & (scores.law == law)]
            assert sorted(set(rows.seed)) == [0, 1]
            assert set(rows.case) == {c.name for c in lp.held_out}


def test_no_stop_beats_its_adhesion_bound(quick: Path) -> None:
    scores = pd.read_csv(quick / SCORES_CSV)
    stopped = scores[scores.status == "stopped"]
    assert len(stopped) > 0.8 * len(scores)
    assert (stopped.distance_ratio >= 1.0).all(), stopped[stopped.distance_ratio < 1.0]
    assert stopped.distance_ratio.notna().all()
    assert scores[scores.status != "stopped"].distance_ratio.isna().all()


def test_scores_are_in_their_ranges(quick: Path) -> None:
    scores = pd.read_csv(quick / SCORES_CSV)
    wheel = scores[scores.plant == "abs-wheel"]
    eps = wheel.r13h_epsilon.dropna()
    assert len(eps) > 0 and ((eps >= 0.0) & (eps <= 1.2)).all()
    assert (wheel[wheel.law == "none"].r13h_epsilon == 0.0).all()  # a locked wheel never cycles
    assert wheel[wheel.law == "pid"].r13h_epsilon.notna().any()  # a law told a fixed target
    vehicle = scores[scores.plant == "abs-vehicle"]
    assert vehicle.r13h_epsilon.isna().all() and vehicle.valve_switches_per_s.isna().all()
    straight = vehicle[vehicle.case != "split-mu"]
    assert np.allclose(straight.yaw_rate_peak_1s_rad_s, 0.0, atol=1e-9)  # a symmetric stop
    split = vehicle[vehicle.case == "split-mu"]
    assert (split.yaw_rate_peak_1s_rad_s > 0.01).all()


def test_the_ranking_orders_by_failures_then_median_score(quick: Path) -> None:
    scores = pd.read_csv(quick / SCORES_CSV)
    for plant in PLANTS:
        table = ranking(scores, plant)
        keys = list(zip(table.failed, table["median"], strict=True))
        assert keys == sorted(keys)
        assert list(table["rank"]) == list(range(1, len(table) + 1))
    page = (quick / PAGE).read_text()
    for plant in PLANTS:
        assert f"## {plant}" in page
    for fig in ("league_cases.png", "league_traces_abs-wheel.png", "league_traces_abs-vehicle.png"):
        assert (quick / fig).stat().st_size > 10_000


def test_a_second_call_resumes_with_the_same_scores(quick: Path, cli: Any) -> None:
    before = (quick / SCORES_CSV).read_bytes()
    result = cli("league", "--quick", "--out", str(quick))
    runs = 2 * sum(len(league_laws(lp, Setting(tuple(PLANTS)))[0]) for lp in PLANTS.values())
    assert result.code == 0 and f"({runs} stored already)" in result.out
    assert (quick / SCORES_CSV).read_bytes() == before


def test_the_process_executor_gives_the_same_numbers(quick: Path, tmp_path: Path) -> None:
    _league(tmp_path, "--executor", "process", "--workers", "2")
    assert (tmp_path / SCORES_CSV).read_bytes() == (quick / SCORES_CSV).read_bytes()


def test_an_unknown_optimizer_is_one_line_naming_the_option(tmp_path: Path, cli: Any) -> None:
    result = cli("league", "--quick", "--optimizer", "nope", "--out", str(tmp_path / "x"))
    assert result.code == 2
    assert result.err.count("\n") == 1 and "--optimizer" in result.err
    assert not (tmp_path / "x").exists()
