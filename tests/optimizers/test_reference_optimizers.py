"""The reference optimizers: `cma-es` is the `cmaes` package, bit for bit; `random-search` is
uniform sampling of the box."""

from __future__ import annotations

import math

import numpy as np
import pytest
from cmaes import CMA
from optimizer_helpers import run
from scipy import stats

from chassistune import benchmarks
from chassistune.optimizers.registry import make


def _package_run(
    fun, lo: np.ndarray, hi: np.ndarray, popsize: int, seed: int, budget: int
) -> tuple[np.ndarray, list[int]]:
    """IPOP driven on the package directly, one `ask()` per candidate as its README does; the
    package's seed and mean drawn from `default_rng(seed)` as `cma_es.py` documents. Returns
    every evaluated point and the population of each start."""
    rng = np.random.default_rng(seed)
    points: list[np.ndarray] = []
    pops: list[int] = []
    while len(points) < budget:
        package_seed = int(rng.integers(2**32))
        mean = lo + rng.random((1, lo.size))[0] * (hi - lo)
        es = CMA(
            mean=mean,
            sigma=0.2,
            bounds=np.stack([lo, hi], axis=1),
            seed=package_seed,
            population_size=popsize,
            cov=np.diag((hi - lo) ** 2),
        )
        pops.append(popsize)
        while len(points) < budget:
            solutions = []
            for _ in range(es.population_size):
                x = es.ask()
                points.append(x)
                solutions.append((x, float(fun(x[None, :])[0])))
            es.tell(solutions)
            if es.should_stop():
                break
        popsize *= 2
    return np.array(points[:budget]), pops


def _recording(fun, seen: list[np.ndarray]):
    def wrapped(x: np.ndarray) -> np.ndarray:
        seen.append(x.copy())
        return fun(x)

    return wrapped


@pytest.mark.parametrize(
    ("function", "dim", "pop", "seed", "budget"),
    [("F16", 2, 6, 0, 3001), ("F9", 5, 8, 7, 4003), ("F5", 3, 4, 2, 2500)],
)
def test_cma_es_is_the_package_bit_for_bit_over_a_whole_run(
    function: str, dim: int, pop: int, seed: int, budget: int
) -> None:
    f = benchmarks.get(function)
    bounds = f.bounds(dim)
    seen: list[np.ndarray] = []
    opt = run("cma-es", _recording(f, seen), bounds, pop=pop, seed=seed, max_evals=budget)
    ours = np.concatenate(seen)
    theirs, pops = _package_run(f, bounds[:, 0], bounds[:, 1], pop, seed, budget)
    assert ours.shape == theirs.shape == (budget, dim)
    assert np.array_equal(ours, theirs)  # every point, bit for bit, across every restart
    assert opt.diagnostics["restarts"] == len(pops) - 1 >= 1
    assert opt.diagnostics["final_popsize"] == pops[-1]
    assert opt.best_f == float(np.min(f(theirs)))


def test_cma_es_keeps_the_package_points_at_the_bounds() -> None:
    """A cost pulling past the corner: the package resamples out-of-box candidates (then clips);
    nothing else moves the points (the base's repair is bypassed)."""
    lo, hi = np.zeros(3), np.ones(3)
    seen: list[np.ndarray] = []
    run(
        "cma-es",
        _recording(lambda x: -np.sum(x, axis=1), seen),
        np.stack([lo, hi], axis=1),
        pop=6,
        max_evals=600,
    )
    pts = np.concatenate(seen)
    theirs, _ = _package_run(lambda x: -np.sum(x, axis=1), lo, hi, 6, 0, 600)
    assert np.array_equal(pts, theirs)
    assert pts.min() >= 0.0 and pts.max() <= 1.0
    assert np.sum(pts, axis=1).max() > 2.99  # it reached the corner from inside


def test_cma_es_restart_seeds_differ_and_follow_the_run_seed() -> None:
    f = benchmarks.get("F16")
    a = run("cma-es", f, f.bounds(), pop=6, seed=1, max_evals=3000)
    b = run("cma-es", f, f.bounds(), pop=6, seed=2, max_evals=3000)
    assert a.diagnostics["restarts"] >= 1 and b.diagnostics["restarts"] >= 1
    assert not np.array_equal(a.history, b.history)


@pytest.mark.parametrize(
    ("hyper", "match"),
    [({"sigma0": 0.0}, "sigma0"), ({"sigma0": 1.5}, "sigma0"), ({"inc_popsize": 0}, "inc_popsize")],
)
def test_cma_es_refuses_bad_hyperparameters(hyper: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        make("cma-es", [(-1, 1)] * 2, 6, max_iter=5, **hyper)


def test_cma_es_without_restarts_keeps_its_population() -> None:
    rows: list[int] = []

    def fun(x: np.ndarray) -> np.ndarray:
        rows.append(x.shape[0])
        return np.sum(x * x, axis=1)

    opt = run("cma-es", fun, [(-1, 1)] * 4, pop=10, max_iter=20, inc_popsize=1)
    assert rows == [10] * 20 and opt.nit == 20


def test_random_search_is_uniform_and_keeps_the_best_sample() -> None:
    lo, hi = np.array([-3.0, 0.0, 10.0]), np.array([5.0, 1e-3, 12.0])
    seen: list[np.ndarray] = []
    f = benchmarks.get("F1")
    opt = run(
        "random-search",
        _recording(f, seen),
        np.stack([lo, hi], axis=1),
        pop=50,
        seed=5,
        max_evals=4000,
    )
    pts = np.concatenate(seen)
    assert pts.shape == (4000, 3)
    for j in range(3):
        u = (pts[:, j] - lo[j]) / (hi[j] - lo[j])
        assert stats.kstest(u, "uniform").pvalue > 1e-3
    assert opt.best_f == float(np.min(f(pts)))
    assert np.array_equal(opt.best_x, pts[int(np.argmin(f(pts)))])


def test_random_search_is_the_floor_on_f1() -> None:
    """The expected best of n uniform samples on the sphere in d = 10, [-100, 100]: P(f <= r^2)
    is the ball's share of the box, so with 50,000 samples the best stays far above 1e-6 (the
    learners' bar) and near the order-statistic value."""
    f = benchmarks.get("F1")
    best = [
        run("random-search", f, f.bounds(10), seed=s, max_evals=50_000).best_f for s in range(5)
    ]
    d, n = 10, 50_000
    unit_ball = np.pi ** (d / 2) / math.gamma(d / 2 + 1)
    median_r = (np.log(2) / n / unit_ball * 200.0**d) ** (1 / d)  # P(min > r^2) = 1/2
    assert min(best) > 1e3
    assert 0.5 * median_r**2 < float(np.median(best)) < 2.0 * median_r**2
