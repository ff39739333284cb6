"""The shifted F1-F23: the minimum value kept at the moved optimum, inside the box, and nothing
in the box lower (a dense sample plus a local search from its best points)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import minimize

from chassistune import benchmarks
from chassistune.benchmarks.shifted import WRAPPED, shifted

CASES = [(n, d) for n in [f"F{i}" for i in range(1, 14)] for d in (2, 5)] + [
    (f"F{i}", None) for i in range(14, 24)
]


def _tol(f_min: float) -> float:
    return 1e-12 * max(1.0, abs(f_min))


@pytest.mark.parametrize(("name", "dim"), CASES)
@pytest.mark.parametrize("seed", [0, 1])
def test_minimum_kept_at_the_moved_optimum_and_nothing_lower(
    name: str, dim: int | None, seed: int
) -> None:
    g = shifted(name, dim, seed)
    b = g.bounds()
    lo, hi = b[:, 0], b[:, 1]
    p = g.minimizer()
    assert np.all(p >= lo) and np.all(p <= hi)
    assert not np.allclose(p, benchmarks.get(name).minimizer(g.dim))  # it did move
    f_min = g.f_min()
    assert abs(g.noise_free(p)[0] - f_min) <= _tol(f_min)
    rng = np.random.default_rng(100 + seed)
    sample = lo + rng.random((20_000, g.dim)) * (hi - lo)
    values = g.noise_free(sample)
    assert values.min() >= f_min - _tol(f_min)
    for start in sample[np.argsort(values)[:4]]:
        local = minimize(lambda x: float(g.noise_free(x)[0]), start, method="L-BFGS-B", bounds=b)
        assert local.fun >= f_min - _tol(f_min), (local.x, p)


def test_shift_is_a_translation_and_wrap_stays_on_the_box() -> None:
    g = shifted("F9", 4, 3)
    x = np.random.default_rng(0).uniform(-5.12, 5.12, (50, 4))
    s = g.optimum - benchmarks.get("F9").minimizer(4)
    assert np.array_equal(g.noise_free(x), benchmarks.get("F9")(x - s))
    assert "F9" not in WRAPPED and "F8" in WRAPPED
    h = shifted("F8", 3, 3)
    y = h.original_point(np.random.default_rng(1).uniform(-500, 500, (500, 3)))
    assert y.min() >= -500 and y.max() <= 500


def test_same_seed_same_optimum_other_seed_differs() -> None:
    a, b, c = shifted("F21", None, 5), shifted("F21", None, 5), shifted("F21", None, 6)
    assert np.array_equal(a.optimum, b.optimum) and not np.array_equal(a.optimum, c.optimum)


def test_noisy_f7_adds_its_noise_on_top() -> None:
    g = shifted("F7", 3, 0)
    noise = np.random.default_rng(0)
    value = g(g.minimizer(), noise)
    assert 0.0 <= value - g.f_min() < 1.0
