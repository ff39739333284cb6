"""The Aquila family: strategies as configurations, evaluation counts, and unimodal convergence."""

from __future__ import annotations

import numpy as np
import pytest
from optimizer_helpers import run

from chassistune import benchmarks
from chassistune.optimizers import registry
from chassistune.optimizers.minimize import minimize

FUNS = ["F1", "F2", "F3", "F4", "F9", "F10", "F11"]

# Rastrigin (F9) and Griewank (F11) are reached exactly only through AO's pull towards the
# origin: near the end of exploration, X1 = Xbest c + (XM - Xbest) rand contracts towards the
# population mean XM, which stays near 0 = the optimum while the population is spread
# symmetrically. Any strategy that concentrates the population elsewhere (the DE steps) removes
# that pull. Shift Rastrigin by 1.234 and AO ends near 30, DERLSP-AO near 17, DEFFAO near 21
# (4 seeds, 500 iterations). Measured medians of 10 runs on the unshifted F9: AO ~1e-10,
# DERLSP-AO ~3e-4, DEFFAO ~4e-4; DEFFAO on F11 ~1e-6.
KNOWN_MISSES = {("derlsp-ao", "F9"), ("deffao", "F9"), ("deffao", "F11")}


@pytest.mark.parametrize("fn", FUNS)
@pytest.mark.parametrize("name", ["ao", "derlsp-ao", "deffao"])
def test_median_of_10_runs_below_1e_10(name: str, fn: str, request: pytest.FixtureRequest) -> None:
    """d = 30, N = 30, 500 iterations. The best-so-far never increases, so a run may stop as
    soon as it is below 1e-10 (its value at iteration 500 is then below 1e-10 too)."""
    if (name, fn) in KNOWN_MISSES:
        request.applymarker(pytest.mark.xfail(strict=True, reason="AO's origin pull, see above"))
    f = benchmarks.get(fn)
    below = 0
    for seed in range(10):
        res = minimize(
            f,
            f.bounds(30),
            method=name,
            pop_size=30,
            max_iter=500,
            seed=seed,
            callback=lambda r: r.fun < 1e-10,
        )
        below += res.fun < 1e-10
        if below >= 6 or below + (9 - seed) < 6:
            break
    assert below >= 6


@pytest.mark.parametrize(
    ("name", "hyper", "per_iter"),
    [
        ("ao", {}, lambda n: n),
        ("derlsp-ao", {}, lambda n: 2 * n + 1),
        ("derlsp-ao", {"de_step": False}, lambda n: n + 1),
        ("derlsp-ao", {"de_step": False, "lens_opposition": False}, lambda n: n),
        ("deffao", {}, lambda n: n + int(np.ceil(0.3 * n))),
        ("deffao", {"de_elimination": False}, lambda n: n),
    ],
)
def test_evaluations_per_iteration(name: str, hyper: dict, per_iter) -> None:  # type: ignore[no-untyped-def]
    f = benchmarks.get("F1")
    opt = run(name, f, f.bounds(5), pop=20, max_iter=7, **hyper)
    steps = np.diff(np.concatenate([[20], opt.history_nfev]))
    assert np.all(steps == per_iter(20))


def test_strategies_are_switches_of_one_engine() -> None:
    ao, derlsp, deffao = (registry.get(n) for n in ("ao", "derlsp-ao", "deffao"))
    assert ao.__mro__[1] is derlsp.__mro__[1] is deffao.__mro__[1]
    f = benchmarks.get("F5")
    base = run("ao", f, f.bounds(8), max_iter=60, seed=1)
    off = run(
        "derlsp-ao",
        f,
        f.bounds(8),
        max_iter=60,
        seed=1,
        lens_opposition=False,
        stagnation=False,
        de_step=False,
    )
    assert np.array_equal(base.history, off.history)  # DERLSP-AO with every strategy off is AO
    off = run(
        "deffao",
        f,
        f.bounds(8),
        max_iter=60,
        seed=1,
        free_hunting=False,
        nonlinear_factor=False,
        de_elimination=False,
    )
    assert np.array_equal(base.history, off.history)
    for strategy in ("lens_opposition", "stagnation", "de_step"):
        one = run("ao", f, f.bounds(8), max_iter=60, seed=1, **{strategy: True})
        assert not np.array_equal(base.history, one.history), strategy


def test_lens_opposition_point() -> None:
    """Eq. 28 with k = 1 is plain opposition within the population's box: a + b - Xbest."""
    seen = []

    def fun(x: np.ndarray) -> np.ndarray:
        seen.append(x.copy())
        return np.sum(x * x, axis=1)

    run(
        "derlsp-ao",
        fun,
        [(-5, 5)] * 3,
        pop=6,
        max_iter=1,
        lens_k=1.0,
        de_step=False,
        stagnation=False,
    )
    pop, batch = seen[0], seen[1]
    best = pop[np.argmin(np.sum(pop * pop, axis=1))]
    expected = pop.min(axis=0) + pop.max(axis=0) - best
    np.testing.assert_allclose(batch[-1], np.clip(expected, -5, 5))
