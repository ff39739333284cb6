"""The MF curve peaks where its coefficients put it, and its slope at zero shifted slip is the
stiffness K the coefficients give (Pacejka 2012, 4.E15 and 4.E25)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from mf_tires import chrono_tire, load_sensitive_tire, sample_tire
from scipy.optimize import minimize_scalar

from chassistune.plants import magic_formula as mf
from chassistune.plants.mf_peak import braking_friction_peak, braking_peak, scaled_to_road

LOADS_N = (1000.0, 4000.0, 7000.0)
TIRES = {"sample": sample_tire, "load-sensitive": load_sensitive_tire, "chrono": chrono_tire}


def brute_force_peak(c: np.ndarray, fz_n: float) -> tuple[float, float]:
    """argmin and min of F_x0 over kappa in [-1, 0]: a 100,001-point grid, then a bounded
    refinement between the grid's neighbours."""
    kappas = np.linspace(-1.0, 0.0, 100_001)
    forces = np.array([mf.longitudinal_force_pure_n(c, k, fz_n) for k in kappas])
    i = int(np.argmin(forces))
    lo, hi = kappas[max(i - 1, 0)], kappas[min(i + 1, kappas.size - 1)]
    res = minimize_scalar(
        lambda k: mf.longitudinal_force_pure_n(c, k, fz_n),
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": 1e-12},
    )
    return float(res.x), float(res.fun)


@pytest.mark.parametrize("name", TIRES)
@pytest.mark.parametrize("fz_n", LOADS_N)
def test_braking_peak_is_where_the_coefficients_put_it(name: str, fz_n: float) -> None:
    tire = TIRES[name]()
    kappa, force = braking_peak(tire, fz_n)
    kappa_bf, force_bf = brute_force_peak(tire.kernel_array(), fz_n)
    assert -1.0 < kappa < 0.0
    assert kappa == pytest.approx(kappa_bf, abs=1e-5)  # the peak is flat: kappa is loose
    assert force == pytest.approx(force_bf, rel=1e-12)
    assert force <= force_bf  # closed form: at least as deep as any sampled point


@pytest.mark.parametrize("name", TIRES)
@pytest.mark.parametrize("fz_n", LOADS_N)
def test_longitudinal_slope_at_zero_shifted_slip_is_kx(name: str, fz_n: float) -> None:
    tire = TIRES[name]()
    c = tire.kernel_array()
    dfz = (fz_n - tire.fnomin_n * tire.lfzo) / (tire.fnomin_n * tire.lfzo)
    kx = fz_n * (tire.pkx1 + tire.pkx2 * dfz) * math.exp(tire.pkx3 * dfz) * tire.lkx  # 4.E15
    shx = (tire.phx1 + tire.phx2 * dfz) * tire.lhx  # 4.E17
    h = 1e-6
    slope = (
        mf.longitudinal_force_pure_n(c, -shx + h, fz_n)
        - mf.longitudinal_force_pure_n(c, -shx - h, fz_n)
    ) / (2 * h)
    assert slope == pytest.approx(kx, rel=1e-6)


@pytest.mark.parametrize("name", ["load-sensitive", "chrono"])
@pytest.mark.parametrize("fz_n", LOADS_N)
def test_lateral_slope_at_zero_shifted_slip_is_ky(name: str, fz_n: float) -> None:
    tire = TIRES[name]()
    c = tire.kernel_array()
    fz0 = tire.fnomin_n * tire.lfzo
    dfz = (fz_n - fz0) / fz0
    ky = tire.pky1 * fz0 * math.sin(tire.pky4 * math.atan(fz_n / (tire.pky2 * fz0))) * tire.lky
    shy = (tire.phy1 + tire.phy2 * dfz) * tire.lhy  # 4.E27 at zero camber
    h = 1e-6
    slope = (
        mf.lateral_force_pure_n(c, -shy + h, fz_n) - mf.lateral_force_pure_n(c, -shy - h, fz_n)
    ) / (2 * h)
    assert slope == pytest.approx(ky, rel=1e-6)
    assert ky < 0.0  # ISO-W: a positive slip angle pushes the tire to negative y


def test_a_road_scales_the_peak_through_lmux() -> None:
    tire = sample_tire()
    for mu_road in (0.2, 0.5, 0.9):
        road = scaled_to_road(tire, mu_road, 4000.0)
        assert road.lmux == pytest.approx(road.lmuy)
        assert road.lmux < 1.0
        # exact but for the vertical shift S_Vx (PVX1 = -8.8e-6 here), scaled degressively
        assert braking_friction_peak(road, 4000.0) == pytest.approx(mu_road, rel=1e-4)
        assert braking_peak(road, 4000.0)[0] > braking_peak(tire, 4000.0)[0]  # K_x stays
