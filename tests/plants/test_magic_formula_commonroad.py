"""Our MF formulas in CommonRoad-compatible mode equal CommonRoad's `vehiclemodels.utils.
tire_model` (a simplified PAC2002) on a grid of slip, slip angle and load.

Tolerance: 1e-12 N per N of load (1e-9 N at 1000 N) for forces; 1e-12 for the weights G.
Input mapping (CommonRoad's departures, docs/tires.md): its pure longitudinal slip is MF's kappa
with the sign flipped, its combined lateral force takes the unflipped slip, its slip angle is used
where MF uses tan(alpha), zero camber.
"""

from __future__ import annotations

import numpy as np
import pytest
from mf_tires import SAMPLE_TIR, neutral_tire, sample_tire

from chassistune.plants import magic_formula as mf
from chassistune.plants.mf_coefficients import PKY2

tire_model = pytest.importorskip("vehiclemodels.utils.tire_model")
vehicle2 = pytest.importorskip("vehiclemodels.parameters_vehicle2")

KAPPAS = np.linspace(-1.0, 1.0, 41)
ALPHAS = np.linspace(-0.5, 0.5, 41)
LOADS_N = (500.0, 2000.0, 4000.0, 6000.0, 9000.0)
REL_TOL = 1e-12


@pytest.fixture(scope="module")
def cr_tire():  # CommonRoad's parameter object
    return vehicle2.parameters_vehicle2().tire


@pytest.fixture(scope="module")
def coef(cr_tire) -> np.ndarray:
    """Our coefficient array with CommonRoad's values (every other coefficient neutral)."""
    names = [n for n in dir(cr_tire) if n[:2] in ("p_", "r_")]
    values = {n.replace("_", ""): float(getattr(cr_tire, n)) for n in names}
    camber = {k for k in values if k in ("pdx3", "pdy3", "phy3", "pvy3", "rvy3")}
    assert camber  # present in CommonRoad's set, unused at zero camber
    return neutral_tire(**{k: v for k, v in values.items() if k not in camber}).kernel_array()


def test_the_shipped_sample_carries_commonroads_numbers(cr_tire) -> None:
    t = sample_tire()
    for name in ("pcx1", "pdx1", "pex1", "pkx1", "phx1", "pvx1", "rbx1", "rbx2", "rcx1", "rex1",
                 "rhx1"):  # fmt: skip
        assert getattr(t, name) == getattr(cr_tire, f"{name[0]}_{name[1:]}"), (SAMPLE_TIR, name)


def test_pure_longitudinal_force_equals_commonroad(cr_tire, coef) -> None:
    worst = 0.0
    for fz in LOADS_N:
        for kappa in KAPPAS:
            ours = mf.longitudinal_force_pure_n(coef, -kappa, fz, True)
            ref = tire_model.formula_longitudinal(kappa, 0.0, fz, cr_tire)
            worst = max(worst, abs(ours - ref) / fz)
    assert worst <= REL_TOL


def test_pure_lateral_force_and_friction_equal_commonroad(cr_tire, coef) -> None:
    worst = 0.0
    for fz in LOADS_N:
        for alpha in ALPHAS:
            ours = mf.lateral_force_pure_n(coef, alpha, fz, True)
            ref, mu_y = tire_model.formula_lateral(alpha, 0.0, fz, cr_tire)
            assert mf.lateral_friction(coef, fz) == mu_y
            worst = max(worst, abs(ours - ref) / fz)
    assert worst <= REL_TOL


def test_combined_weights_equal_commonroad(cr_tire, coef) -> None:
    worst_x = worst_y = 0.0
    for fz in LOADS_N:
        mu_y = mf.lateral_friction(coef, fz)
        for kappa in KAPPAS[::2]:
            for alpha in ALPHAS[::2]:
                fx0 = mf.longitudinal_force_pure_n(coef, -kappa, fz, True)
                ours_x = mf.longitudinal_weight(coef, -kappa, alpha, fz) * fx0
                ref_x = tire_model.formula_longitudinal_comb(kappa, alpha, fx0, cr_tire)
                fy0 = mf.lateral_force_pure_n(coef, alpha, fz, True)
                ours_y = mf.lateral_weight(coef, kappa, alpha, fz) * fy0
                ours_y += mf.lateral_shift_by_slip_n(coef, kappa, alpha, fz, mu_y)
                ref_y = tire_model.formula_lateral_comb(kappa, alpha, 0.0, mu_y, fz, fy0, cr_tire)
                worst_x = max(worst_x, abs(ours_x - ref_x) / fz)
                worst_y = max(worst_y, abs(ours_y - ref_y) / fz)
    assert worst_x <= REL_TOL
    assert worst_y <= REL_TOL


def test_the_compatible_mode_is_a_departure_from_mf61(cr_tire, coef) -> None:
    """Outside the mode the formulas differ (so the comparisons above test the flags)."""
    fz = 4000.0
    fx_mf = mf.longitudinal_force_pure_n(coef, 0.05, fz)
    fx_cr = tire_model.formula_longitudinal(-0.05, 0.0, fz, cr_tire)
    assert abs(fx_mf - fx_cr) > 1e-9 * fz
    c = coef.copy()
    c[PKY2] = 1.5  # PKY2 exists only in MF's K_y
    fy_mf = mf.lateral_force_pure_n(c, 0.05, fz)
    fy_cr = tire_model.formula_lateral(0.05, 0.0, fz, cr_tire)[0]
    assert abs(fy_mf - fy_cr) > 1.0
