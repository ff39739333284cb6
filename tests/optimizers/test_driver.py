"""optimizers.driver: the one ask/tell loop, its result, its callback, the diagnostics channel."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune import benchmarks
from chassistune.optimizers import OptimizeResult, drive
from chassistune.optimizers.registry import make, names


def _hand_loop(name: str) -> tuple[np.ndarray, float, np.ndarray]:
    f = benchmarks.get("F5")
    opt = make(name, f.bounds(4), 10, 3, max_evals=170)
    while not opt.done:
        x = opt.ask()
        opt.tell(x, f(x))
    return opt.best_x, opt.best_f, opt.history


@pytest.mark.parametrize("name", names())
def test_drive_is_the_plain_ask_tell_loop_bit_for_bit(name: str) -> None:
    f = benchmarks.get("F5")
    res = drive(make(name, f.bounds(4), 10, 3, max_evals=170), f)
    x, fun, history = _hand_loop(name)
    assert isinstance(res, OptimizeResult) and res.method == name
    assert np.array_equal(res.x, x) and res.fun == fun and np.array_equal(res.history, history)
    assert res.nfev == 170 and res.message == "max_evals reached" and res.wall_time_s > 0


def test_scout_count_comes_through_the_diagnostics_channel() -> None:
    f = benchmarks.get("F5")
    counts = {}
    for name in ("abc", "iabc"):
        opt = make(name, f.bounds(3), 6, 0, max_iter=200, limit=3)
        res = drive(opt, f)
        counts[name] = res.diagnostics["scouts"]
        assert res.diagnostics == opt.diagnostics and res.diagnostics is not opt.diagnostics
    assert counts["abc"] > 0 and counts["iabc"] > 0
    assert drive(make("de", f.bounds(3), 6, 0, max_iter=5), f).diagnostics == {}


def test_callback_gets_the_run_so_far_and_can_stop_it() -> None:
    f = benchmarks.get("F1")
    seen: list[tuple[int, int]] = []

    def cb(r: OptimizeResult) -> bool:
        seen.append((r.nit, r.nfev))
        assert r.message == "running" and len(r.history) == r.nit
        return r.nit == 3

    res = drive(make("pso", f.bounds(2), 5, 0, max_iter=10), f, cb)
    assert seen == [(1, 10), (2, 15), (3, 20)] and res.nit == 3
    assert res.message == "stopped by the callback"
