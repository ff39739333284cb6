"""Combined slip and load dependence of the MF forces, and their use inside a compiled loop."""

from __future__ import annotations

import numba
import numpy as np
import pytest
from mf_tires import load_sensitive_tire, sample_tire

from chassistune.plants import magic_formula as mf
from chassistune.plants.mf_coefficients import RBY1, RBY2, RCY1
from chassistune.plants.mf_peak import braking_friction_peak

KAPPAS = np.linspace(-1.0, 1.0, 81)
ALPHAS = np.linspace(-0.4, 0.4, 81)


@numba.njit(cache=False)
def braking_forces(c: np.ndarray, kappas: np.ndarray, alpha: float, fz_n: float) -> np.ndarray:
    out = np.empty_like(kappas)
    for i in range(kappas.size):
        out[i] = mf.longitudinal_force_n(c, kappas[i], alpha, fz_n)
    return out


def test_without_the_other_slip_combined_equals_pure() -> None:
    c = load_sensitive_tire().kernel_array()
    for fz in (1500.0, 4000.0, 8000.0):
        for kappa in KAPPAS:
            assert mf.longitudinal_force_n(c, kappa, 0.0, fz) == mf.longitudinal_force_pure_n(
                c, kappa, fz
            )
        for alpha in ALPHAS:
            assert mf.lateral_force_n(c, 0.0, alpha, fz) == mf.lateral_force_pure_n(c, alpha, fz)


def test_lateral_slip_reduces_the_braking_force() -> None:
    c = sample_tire().kernel_array()
    for kappa in (-0.05, -0.15, -0.5):
        forces = [abs(mf.longitudinal_force_n(c, kappa, a, 4000.0)) for a in (0.0, 0.05, 0.1, 0.2)]
        assert all(np.diff(forces) < 0.0), (kappa, forces)
        weight = mf.longitudinal_weight(c, kappa, 0.1, 4000.0)
        assert 0.0 < weight < 1.0


def test_braking_reduces_the_lateral_force() -> None:
    c = load_sensitive_tire().kernel_array()
    c[RBY1], c[RBY2], c[RCY1] = 7.1, 9.2, 1.07  # CommonRoad's magnitudes
    pure = abs(mf.lateral_force_pure_n(c, 0.05, 4000.0))
    combined = [abs(mf.lateral_force_n(c, k, 0.05, 4000.0)) for k in (-0.05, -0.2, -0.6)]
    assert pure > combined[0] > combined[1] > combined[2]


def test_friction_falls_with_load_when_pdx2_is_negative() -> None:
    tire = load_sensitive_tire()
    mus = [braking_friction_peak(tire, fz) for fz in (1000.0, 4000.0, 7000.0)]
    assert mus[0] > mus[1] > mus[2]
    assert mus[1] == pytest.approx(tire.pdx1, rel=1e-4)  # at FNOMIN dfz = 0 (up to S_Vx)


def test_the_forces_compile_inside_a_loop_bit_for_bit() -> None:
    c = sample_tire().kernel_array()
    looped = braking_forces(c, KAPPAS, 0.03, 3500.0)
    single = [mf.longitudinal_force_n(c, k, 0.03, 3500.0) for k in KAPPAS]
    assert looped.tolist() == single
