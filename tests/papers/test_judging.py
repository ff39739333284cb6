"""The judging rules on constructed data whose answer is known: a fixed baseline against tuned
runs, a settling comparison, equal evaluations against equal iterations, an undecided verdict at
a budget too small to decide, a claim on most functions, and the bounds."""

from __future__ import annotations

import math

import numpy as np
import pytest

from chassistune._rng import make_rng
from chassistune.papers import common
from chassistune.papers.claims import Claim
from chassistune.scenarios.base import Trace


def _runs(centre: float, n: int, seed: int = 0) -> np.ndarray:
    return centre + 0.05 * make_rng(seed).standard_normal(n)


def test_a_fixed_fuzzy_pid_beats_tuned_ga_pid_on_ice() -> None:
    # Table 4's ice row as a constructed table: untuned fuzzy PID one value, GA-PID 30 seeds
    table = {"fuzzy PID": np.array([47.216]), "GA-PID": _runs(47.898, 30)}
    word, evidence = common.order_verdict(table, "fuzzy PID", fixed=("fuzzy PID",))
    assert word == common.HOLDS and "signed-rank +" in evidence
    table["GA-PID"] = _runs(46.9, 30)
    assert common.order_verdict(table, "fuzzy PID", fixed=("fuzzy PID",))[0] == common.FAILS
    # one tuned run is one seed, not a fixed value: it decides nothing
    one = {"fuzzy PID": np.array([47.216]), "GA-PID": np.array([47.898])}
    assert common.order_verdict(one, "fuzzy PID", fixed=("fuzzy PID",))[0] == common.UNDECIDED


def test_the_worst_is_judged_from_above() -> None:
    table = {"PID": np.array([48.7]), "fuzzy PID": np.array([47.2]), "AO-PID": _runs(46.8, 30)}
    fixed = ("PID", "fuzzy PID")
    assert common.order_verdict(table, "PID", lowest=False, fixed=fixed)[0] == common.HOLDS
    assert common.order_verdict(table, "AO-PID", lowest=False, fixed=fixed)[0] == common.FAILS


def test_two_seeds_leave_a_ranking_undecided_that_thirty_decide() -> None:
    few = {"DERLSP-AO-PID": _runs(31.0, 2), "AO-PID": _runs(31.6, 2, 1)}
    word, evidence = common.order_verdict(few, "DERLSP-AO-PID")
    assert word == common.UNDECIDED and "smallest attainable p = 0.33" in evidence
    # the wrong order at two seeds is undecided too, not 'does not hold'
    assert common.order_verdict(few, "AO-PID")[0] == common.UNDECIDED
    many = {"DERLSP-AO-PID": _runs(31.0, 30), "AO-PID": _runs(31.6, 30, 1)}
    assert common.order_verdict(many, "DERLSP-AO-PID")[0] == common.HOLDS
    assert common.order_verdict(many, "AO-PID")[0] == common.FAILS
    # a part that does not hold decides before an undecided one
    assert common.combine([common.UNDECIDED, common.FAILS]) == common.FAILS
    assert common.combine([common.HOLDS, common.UNDECIDED]) == common.UNDECIDED


def test_the_smallest_attainable_p_values() -> None:
    assert common.compare(_runs(1, 3), _runs(2, 3)).floor_p == pytest.approx(0.1)
    assert common.compare(_runs(1, 4), _runs(2, 4)).decidable
    assert common.compare(_runs(1, 5), np.array([2.0]), rival_fixed=True).floor_p == 1 / 16
    assert common.compare(_runs(1, 6), np.array([2.0]), rival_fixed=True).decidable
    assert common.compare(np.array([1.0]), np.array([2.0]), True, True).decidable


def _curves(evals_per_iteration: int, rate: float, seed: int) -> list[common.Curve]:
    """Ten runs of 50 iterations, population 10: cost rate^iteration, a little noise."""
    rng = make_rng(seed)
    out = []
    for _ in range(10):
        it = np.arange(1, 51)
        cost = rate**it * (1.0 + 0.01 * rng.random(50))
        out.append(common.Curve(np.minimum.accumulate(cost), 10 + 10 * evals_per_iteration * it))
    return out


def test_equal_evaluations_and_equal_iterations_pick_different_winners() -> None:
    # "twice" halves its cost each iteration at two evaluations per individual; "once" cuts it
    # by 40 % at one: per iteration "twice" wins, per evaluation "once" does (0.6 < 0.5^0.5)
    curves = {"twice": _curves(2, 0.5, 1), "once": _curves(1, 0.6, 2)}
    at_iterations = common.finals_at(curves, None)
    assert common.order_verdict(at_iterations, "twice")[0] == common.HOLDS
    spent = common.equal_evaluations(curves)
    assert spent == 510.0
    at_evaluations = common.finals_at(curves, spent)
    assert common.order_verdict(at_evaluations, "twice")[0] == common.FAILS
    assert common.order_verdict(at_evaluations, "once")[0] == common.HOLDS
    # convergence speed: fewer iterations for "twice", fewer evaluations for "once"
    assert common.speed_verdict(curves, "twice", by_evaluations=False)[0] == common.HOLDS
    assert common.speed_verdict(curves, "once", by_evaluations=True)[0] == common.HOLDS


def _trace(settles_at_s: float | None) -> Trace:
    time_s = np.linspace(0.0, 3.0, 301)
    slip = np.where(time_s < (settles_at_s if settles_at_s is not None else 9.0), 0.5, 0.21)
    speed = np.linspace(30.0, 0.5, 301)
    return Trace(
        {
            "time_s": time_s,
            "slip": slip,
            "target_slip": np.full(301, 0.2),
            "vehicle_speed_m_s": speed,
        },
        {},
    )


def test_a_settling_comparison() -> None:
    assert common.settle_time_s(_trace(1.2)) == pytest.approx(1.2)
    assert math.isnan(common.settle_time_s(_trace(None)))
    # every run's settling time: ours about 1.2 s, the tuned rival 2.5 s, a fixed baseline never
    settle = {
        "ours": np.array([common.settle_time_s(_trace(t)) for t in 1.2 + 0.02 * np.arange(8)]),
        "other": np.array([common.settle_time_s(_trace(t)) for t in 2.5 + 0.02 * np.arange(8)]),
        "never": np.array([common.settle_time_s(_trace(None))]),
    }
    fixed = ("never",)
    assert common.settle_verdict(settle, "ours", 1.5, fixed)[0] == common.HOLDS
    assert common.settle_verdict(settle, "ours", 1.0, fixed)[0] == common.RANKING_ONLY
    assert common.settle_verdict(settle, "other", 3.0, fixed)[0] == common.FAILS
    assert common.settle_verdict(settle, "never", None, fixed)[0] == common.FAILS
    # one run each cannot decide who settles first
    one = {k: v[:1] for k, v in settle.items()}
    assert common.settle_verdict(one, "ours", 1.5, fixed)[0] == common.UNDECIDED


def test_most_functions() -> None:
    h, r, f, u = common.HOLDS, common.RANKING_ONLY, common.FAILS, common.UNDECIDED
    assert common.most([h, h, h, f]) == h
    assert common.most([h, h, f, f]) == f  # two of four is not most
    assert common.most([h, r, r, f]) == r
    assert common.most([h, u, u, f]) == u


CLAIM = Claim("p", "physical", "原文", "possible", "Table 1", "times", "bound")


def test_a_time_below_its_bound_fails_only_below_the_strict_bound() -> None:
    modelled = common.BoundCheck(
        "p",
        "split-mu",
        "X",
        "braking time",
        "s",
        6.0,
        "6.000",
        6.5,
        assumption="loads",
        strict=3.6,
    )
    impossible = common.BoundCheck("p", "ice", "X", "braking time", "s", 7.5, "7.50", 29.3)
    assert not modelled.possible and modelled.strictly_possible
    assert common.bound_verdict(CLAIM, [modelled]).verdict == common.HOLDS
    v = common.bound_verdict(CLAIM, [modelled, impossible])
    assert v.verdict == common.FAILS
    assert "2 of 2 published braking times are below the bound (1 below the strict" in v.evidence
    assert impossible.row()["published"] == "7.50"
