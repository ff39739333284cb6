"""`chassistune.minimize`: result fields, callback, scalar objectives, bad input."""

from __future__ import annotations

import numpy as np
import pytest

import chassistune
from chassistune import benchmarks
from chassistune.optimizers import OptimizeResult, minimize


def test_result_fields_and_budget() -> None:
    f = benchmarks.get("F1")
    res = chassistune.minimize(f, [(-5, 5)] * 4, method="pso", pop_size=12, max_evals=500, seed=1)
    assert isinstance(res, OptimizeResult)
    assert res.nfev == 500 and res.nit == len(res.history) == len(res.history_nfev)
    assert res.fun == res.history[-1] == pytest.approx(float(f(res.x)))
    assert res["fun"] == res.fun and res.method == "pso" and res.success
    assert res.message == "max_evals reached"


def test_scalar_objective_matches_vectorized() -> None:
    f = benchmarks.get("F10")
    a = minimize(f, f.bounds(3), method="de", max_iter=20, seed=2)
    b = minimize(
        lambda x: float(f(x)), f.bounds(3), method="de", max_iter=20, seed=2, vectorized=False
    )
    assert np.array_equal(a.history, b.history)


def test_callback_sees_every_iteration_and_can_stop() -> None:
    seen: list[int] = []

    def cb(r: OptimizeResult) -> bool:
        seen.append(r.nit)
        return r.nit == 4

    res = minimize(benchmarks.get("F1"), [(-1, 1)] * 2, method="gwo", max_iter=50, callback=cb)
    assert seen == [1, 2, 3, 4] and res.nit == 4 and res.message == "stopped by the callback"


def test_hyperparameters_pass_through() -> None:
    res = minimize(benchmarks.get("F1"), [(-1, 1)] * 2, method="de", max_iter=3, F=0.7, CR=0.2)
    assert res.hyperparameters == {"F": 0.7, "CR": 0.2}


@pytest.mark.parametrize(
    ("fun", "bounds", "kw", "match"),
    [
        (lambda x: np.zeros((x.shape[0], 1)), [(-1, 1)], {}, r"fun: returned shape \(\d+, 1\)"),
        (lambda x: np.zeros(3), [(-1, 1)], {}, "fun: returned shape"),
        (lambda x: x, [(-1, 1)] * 2, {"vectorized": False}, "fun: returned shape"),
        (np.sum, [(2, 1)], {}, "bounds: dimension 0 has lo >= hi"),
        (np.sum, [(0, np.inf)], {}, "bounds: every bound must be finite"),
        (np.sum, [(-1, 1)], {"method": "nope"}, "optimizer: unknown optimizer 'nope'"),
        (np.sum, [(-1, 1)], {"pop_size": 1}, "pop_size: .* at least"),
        (np.sum, [(-1, 1)], {"max_iter": None}, "give max_iter or max_evals"),
        ("not callable", [(-1, 1)], {}, "fun: expected a callable"),
    ],
)
def test_bad_input_is_a_value_error_naming_the_field(fun, bounds, kw, match) -> None:  # type: ignore[no-untyped-def]
    args = {"method": "ao", "max_iter": 3, **kw}
    with pytest.raises(ValueError, match=match):
        minimize(fun, bounds, **args)
