"""Tire curves: peaks and target slips (design.md 3.2)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from chassistune.errors import InputError
from chassistune.plants.tires import BURCKHARDT_SURFACES, BilinearTire, BurckhardtTire


def test_bilinear_matches_seed_000_eq_6_for_dry_concrete():
    tire = BilinearTire(0.2, 0.9, 0.75)
    s = np.array([0.0, 0.1, 0.2, 0.5, 1.0])
    expected = np.where(s <= 0.2, 4.5 * s, 0.9375 - 0.1875 * s)
    np.testing.assert_allclose(tire.mu(s), expected, rtol=1e-12)
    assert tire.peak() == (0.9, 0.2, 0.2)


@pytest.mark.parametrize("name", [n for n, c in BURCKHARDT_SURFACES.items() if c[2] > 0])
def test_burckhardt_peak_matches_the_analytic_optimum(name):
    c1, c2, c3 = BURCKHARDT_SURFACES[name]
    s_star = math.log(c1 * c2 / c3) / c2
    mu_peak, s_peak, target = BurckhardtTire(c1, c2, c3).peak()
    assert s_peak == pytest.approx(s_star, abs=1e-6)
    assert target == s_peak
    assert mu_peak == pytest.approx(c1 * (1 - math.exp(-c2 * s_star)) - c3 * s_star, rel=1e-9)


def test_a_curve_without_interior_peak_targets_98_percent_not_a_locked_wheel():
    mu_peak, s_peak, target = BurckhardtTire(*BURCKHARDT_SURFACES["ice"]).peak()
    assert s_peak == 1.0
    assert target == pytest.approx(math.log(50) / 306.39, abs=2e-6)
    assert mu_peak == pytest.approx(0.05)


def test_bilinear_rejects_a_target_slip_outside_the_unit_interval():
    with pytest.raises(InputError, match="slip_opt"):
        BilinearTire(1.5, 0.9, 0.75)
