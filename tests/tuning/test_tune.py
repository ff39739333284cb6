"""Tuning: optimizer + plant batch cost through the registry's box (design.md 5, 7)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from chassistune.errors import InputError
from chassistune.tuning.problem import build_problem
from chassistune.tuning.tune import tune


def test_derlsp_ao_tunes_the_abs_pid_to_within_8_percent_of_the_bound():
    res = tune(
        "abs-wheel", "pid", "derlsp-ao", roads="dry-concrete", pop_size=20, max_iter=40, seed=1
    )
    m = res.metrics["dry-concrete"]
    assert m["stopped"] and m["wheel_lock_time_s"] is None
    assert 1.0 <= m["distance_ratio"] <= 1.08
    assert res.nfev == res.history_nfev[-1]
    assert np.all(np.diff(res.history) <= 0)
    lo, hi = zip(*res.problem.bounds, strict=True)
    gains = np.array(list(res.best_gains.values()))
    assert np.all(gains >= lo) and np.all(gains <= hi)


def test_the_same_seed_gives_the_same_tuning_and_another_seed_differs():
    a = tune("abs-wheel", "pid", "pso", pop_size=8, max_evals=120, seed=5)
    b = tune("abs-wheel", "pid", "pso", pop_size=8, max_evals=120, seed=5)
    c = tune("abs-wheel", "pid", "pso", pop_size=8, max_evals=120, seed=6)
    assert a.best_gains == b.best_gains and np.array_equal(a.history, b.history)
    assert a.nfev == 120
    assert a.best_gains != c.best_gains


@pytest.mark.parametrize("aggregate", ["mean", "max"])
def test_multi_road_cost_aggregates_the_single_road_costs(aggregate):
    roads = ["dry-concrete", "ice"]
    both = build_problem("abs-wheel", "pid", roads=roads, aggregate=aggregate)
    gains = np.array([[5000.0, 0.0, 230.0], [2000.0, 10.0, 100.0], [1.0, 0.0, 0.0]])
    single = np.stack([build_problem("abs-wheel", "pid", roads=[r])(gains) for r in roads])
    expected = single.mean(axis=0) if aggregate == "mean" else single.max(axis=0)
    np.testing.assert_array_equal(both(gains), expected)


def test_bad_tuning_input_raises_clear_errors():
    with pytest.raises(InputError, match="optimizer"):
        tune("abs-wheel", "pid", "annealing", max_iter=2)
    with pytest.raises(InputError, match="objective"):
        build_problem("abs-wheel", "pid", objective="comfort")
    with pytest.raises(InputError, match="no gains"):
        build_problem("abs-wheel", "none")
    with pytest.raises(InputError, match=r"bounds\.kp"):
        build_problem("abs-wheel", "pid", bounds={"kp": (5.0, 1.0)})


def test_tune_cli_json_and_out_folder(cli, tmp_path):
    out = tmp_path / "run"
    r = cli(
        "tune",
        "abs-wheel",
        "--controller",
        "pid",
        "--optimizer",
        "de",
        "--pop",
        "6",
        "--iters",
        "3",
        "--seed",
        "2",
        "--json",
        "--out",
        str(out),
    )
    assert r.code == 0, r.err
    doc = json.loads(r.out)
    for key in (
        "best_gains",
        "best_cost",
        "nfev",
        "nit",
        "wall_time_s",
        "history",
        "history_nfev",
        "metrics",
    ):
        assert key in doc
    assert doc["nit"] == 3 and len(doc["history"]) == 3
    assert set(doc["best_gains"]) == {"kp", "ki", "kd"}
    assert "stop_distance_m" in doc["metrics"]
    names = {p.name for p in out.iterdir()}
    assert {
        "best_gains.json",
        "tune.json",
        "history.csv",
        "convergence.png",
        "response-dry-concrete.png",
    } <= names


@pytest.mark.parametrize(
    ("args", "field"),
    [
        (["--optimizer", "annealing"], "optimizer"),
        (["--optimizer", "ao", "--iters", "0"], "--iters"),
        (["--optimizer", "ao", "--objective", "comfort"], "--objective"),
        (["--optimizer", "ao", "--road", "ice", "--road", "ice"], "--road"),
        (["--optimizer", "ao", "--pop", "1"], "pop"),
    ],
)
def test_tune_cli_bad_input_exit_2(cli, tmp_path, args, field):
    out = tmp_path / "never"
    r = cli("tune", "abs-wheel", "--controller", "pid", "--out", str(out), *args)
    assert r.code == 2, (r.out, r.err)
    assert len(r.err.strip().splitlines()) == 1 and field in r.err
    assert not out.exists()


def test_the_winner_is_checked_at_a_quarter_of_the_step_on_every_road():
    res = tune(
        "abs-wheel",
        "pid",
        "de",
        roads=["dry-concrete", "ice"],
        pop_size=6,
        max_iter=2,
        seed=3,
        params={"v0_m_s": 20.0},
    )
    gains = np.array([list(res.best_gains.values())])
    assert set(res.step_checks) == {"dry-concrete", "ice"}
    for sc in res.problem.scenarios:
        check = res.step_checks[sc.road]
        assert check.factor == 4 and check.dt_s == sc.plant_params.dt_s
        assert check.cost == float(sc.cost(gains)[0])  # built with the same v0_m_s override
        assert np.isfinite(check.cost_refined) and check.cost_refined > 0.0
        assert check.cost_rel_change == abs(check.cost - check.cost_refined) / check.cost_refined
    doc = res.as_dict()["step_check"]
    assert set(doc) == {"dry-concrete", "ice"} and doc["ice"]["factor"] == 4
    quarter_car = tune("quarter-car", "pid", "de", pop_size=6, max_iter=1, seed=0)
    assert quarter_car.step_checks == {}  # white-noise road: a finer step is another road


def test_tune_cli_warns_when_the_winner_is_not_converged_in_the_step(cli):
    r = cli(
        "tune",
        "abs-wheel",
        "--controller",
        "pid",
        "--optimizer",
        "de",
        "--pop",
        "6",
        "--iters",
        "2",
        "--param",
        "dt_s=0.01",
        "--json",
    )
    assert r.code == 0, r.err
    check = json.loads(r.out)["step_check"]["dry-concrete"]
    assert check["max_rel_change"] > 1e-3 and check["dt_s"] == 0.01
    assert "chassistune: warning: step check on dry-concrete:" in r.err
    assert check["warning"] in r.err
