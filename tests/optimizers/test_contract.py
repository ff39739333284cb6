"""The common contract of optimizers_design.md, checked for every registered optimizer."""

from __future__ import annotations

import zlib

import numpy as np
import pytest
from optimizer_helpers import drive, run

from chassistune import benchmarks
from chassistune.errors import InputError
from chassistune.optimizers import registry
from chassistune.optimizers.registry import make

NAMES = registry.names()
LEARNERS = [n for n in NAMES if n != "random-search"]
"""The optimizers held to the quality bars below: random search is the floor they must beat."""


def test_registry_names_and_catalogue() -> None:
    assert NAMES == [
        "ao",
        "derlsp-ao",
        "deffao",
        "abc",
        "iabc",
        "ga",
        "pso",
        "de",
        "gwo",
        "mfo",
        "poa",
        "dbo",
        "cma-es",
        "random-search",
    ]
    for entry in registry.catalogue():
        assert {"name", "description", "min_pop", "hyperparameters"} <= set(entry)
        assert entry["min_pop"] >= 2


@pytest.mark.parametrize("name", NAMES)
def test_asks_only_in_bounds_points(name: str) -> None:
    rng = np.random.default_rng(zlib.crc32(name.encode()))  # hash() of a str varies per process
    min_pop = registry.get(name).min_pop
    for _ in range(4):
        d = int(rng.integers(1, 8))
        lo = rng.uniform(-1e3, 1e3, d)
        hi = lo + 10.0 ** rng.uniform(-6, 4, d)
        pop = int(rng.integers(min_pop, 41))
        shift = lo + rng.random(d) * (hi - lo)
        seen = []

        def fun(x: np.ndarray, shift: np.ndarray = shift, seen: list = seen) -> np.ndarray:
            seen.append(x.copy())
            return np.sum(((x - shift) * 1e3) ** 2, axis=1) - 1e6  # pushes towards and past bounds

        run(
            name,
            fun,
            np.stack([lo, hi], axis=1),
            pop=pop,
            seed=int(rng.integers(1000)),
            max_evals=int(rng.integers(1, 1500)),
        )
        pts = np.concatenate(seen)
        assert np.all(pts >= lo) and np.all(pts <= hi)
        assert np.all(np.isfinite(pts))


@pytest.mark.parametrize("name", NAMES)
def test_tolerates_nan_and_inf_costs(name: str) -> None:
    f1 = benchmarks.get("F1")

    def nasty(x: np.ndarray) -> np.ndarray:
        f = f1(x)
        f[x[:, 0] > 50] = np.nan
        f[x[:, 1] < -50] = np.inf
        f[x[:, 2] > 90] = -np.inf
        return f

    opt = run(name, nasty, f1.bounds(5), max_iter=40)
    assert np.isfinite(opt.best_f) and opt.best_f >= 0
    assert np.all(np.diff(opt.history) <= 0)
    dead = run(name, lambda x: np.full(x.shape[0], np.nan), f1.bounds(3), max_iter=5)
    assert dead.best_f == np.inf and dead.nit == 5


@pytest.mark.parametrize("name", NAMES)
def test_same_seed_same_history_other_seed_differs(name: str) -> None:
    f = benchmarks.get("F9")
    a = run(name, f, f.bounds(6), seed=3, max_iter=30)
    b = run(name, f, f.bounds(6), seed=3, max_iter=30)
    c = run(name, f, f.bounds(6), seed=4, max_iter=30)
    assert np.array_equal(a.history, b.history) and np.array_equal(a.best_x, b.best_x)
    assert np.array_equal(a.history_nfev, b.history_nfev)
    assert not np.array_equal(a.history, c.history)
    g = run(name, f, f.bounds(6), seed=np.random.default_rng(3), max_iter=30)
    s = run(name, f, f.bounds(6), seed=np.random.SeedSequence(3), max_iter=30)
    assert np.array_equal(g.history, a.history) and np.array_equal(s.history, a.history)


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("budget", [1, 29, 31, 157, 1001])
def test_stops_at_max_evals_exactly(name: str, budget: int) -> None:
    f = benchmarks.get("F5")
    rows = []

    def fun(x: np.ndarray) -> np.ndarray:
        rows.append(x.shape[0])
        return f(x)

    opt = run(name, fun, f.bounds(4), max_evals=budget)
    assert opt.nfev == budget == sum(rows)
    assert len(opt.history) == opt.nit
    if opt.nit:
        assert opt.history_nfev[-1] == budget
        assert np.all(np.diff(opt.history_nfev) > 0)
    both = run(name, fun, f.bounds(4), max_evals=10_000, max_iter=3)
    assert both.nit == 3 and both.nfev < 10_000


@pytest.mark.parametrize("name", NAMES)
def test_refuses_population_below_minimum(name: str) -> None:
    need = registry.get(name).min_pop
    with pytest.raises(ValueError, match=f"at least {need}"):
        make(name, [(-1, 1)] * 3, need - 1, max_iter=5)
    opt = run(name, lambda x: np.sum(x**2, axis=1), [(-1, 1)] * 3, pop=need, max_iter=5)
    assert opt.nit == 5 and np.isfinite(opt.best_f)


@pytest.mark.parametrize("name", NAMES)
def test_history_is_best_so_far(name: str) -> None:
    f = benchmarks.get("F10")
    opt = run(name, f, f.bounds(5), max_iter=25)
    assert len(opt.history) == opt.nit == 25
    assert np.all(np.diff(opt.history) <= 0)
    assert opt.history[-1] == opt.best_f == pytest.approx(float(f(opt.best_x)))


@pytest.mark.parametrize("name", LEARNERS)
def test_f1_d10_below_1e6_within_50000_evaluations(name: str) -> None:
    f = benchmarks.get("F1")
    opt = run(name, f, f.bounds(10), pop=30, max_evals=50_000)
    assert opt.nfev == 50_000
    assert opt.best_f < 1e-6, f"{name}: {opt.best_f:.3g}"


@pytest.mark.parametrize("name", LEARNERS)
def test_f16_within_1e3_in_4_of_5_seeds_within_6000_evaluations(name: str) -> None:
    f = benchmarks.get("F16")
    gaps = [
        run(name, f, f.bounds(), pop=30, seed=s, max_evals=6000).best_f - f.f_min()
        for s in range(5)
    ]
    assert sum(g < 1e-3 for g in gaps) >= 4, gaps


def test_ask_tell_protocol() -> None:
    opt = make("de", [(-1, 1)] * 2, 4, max_evals=6)
    x1 = opt.ask()
    assert opt.ask() is not x1 and np.array_equal(opt.ask(), x1)
    assert not x1.flags.writeable
    with pytest.raises(InputError, match=r"shape \(3,\)"):
        opt.tell(x1, np.zeros(3))
    with pytest.raises(InputError, match="x"):
        opt.tell(x1[:2], np.zeros(2))
    opt.tell(x1, np.zeros(4))
    x2 = opt.ask()
    assert x2.shape == (2, 2)  # cut to the remaining budget
    opt.tell(x2, np.ones(2))
    assert opt.done and opt.nfev == 6
    with pytest.raises(RuntimeError):
        opt.ask()


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (dict(bounds=[(1, -1)]), "lo >= hi"),
        (dict(bounds=[(0, np.inf)]), "finite"),
        (dict(bounds=[(0, np.nan)]), "finite"),
        (dict(bounds=[1, 2, 3]), "pairs"),
        (dict(max_iter=None, max_evals=None), "max_iter or max_evals"),
        (dict(max_iter=0), "positive integer"),
        (dict(seed=-1), "non-negative"),
        (dict(pop_size=2.5), "integer"),
        (dict(F=3.0), "F"),
        (dict(bogus=1), "no hyperparameter 'bogus'"),
    ],
)
def test_bad_input_raises_value_error(kwargs: dict, match: str) -> None:
    args = dict(name="de", bounds=[(-1, 1)] * 2, pop_size=10, max_iter=5)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        make(**args)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="unknown optimizer"):
        make("nope", [(-1, 1)], 10, max_iter=5)


def test_reflect_repair_keeps_points_inside() -> None:
    seen = []

    def fun(x: np.ndarray) -> np.ndarray:
        seen.append(x.copy())
        return -np.sum(x, axis=1)

    drive(make("pso", [(0, 1)] * 3, 10, max_iter=20, repair="reflect"), fun)
    pts = np.concatenate(seen)
    assert pts.min() >= 0 and pts.max() <= 1
