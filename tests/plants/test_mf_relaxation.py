"""The lagged slip follows the kinematic slip with the time constant sigma / V."""

from __future__ import annotations

import math
import warnings
from importlib.resources import files
from pathlib import Path

import numpy as np
import pytest
from mf_tires import SAMPLE_TIR
from scipy.integrate import solve_ivp

from chassistune.plants import mf_coefficients as mfc
from chassistune.plants.mf_relaxation import (
    carcass_relaxation_length_m,
    lagged_slip_after,
    lagged_slip_rate_per_s,
    longitudinal_relaxation_length_m,
)
from chassistune.plants.tir import read_tir

CHRONO = str(files("chassistune") / "data" / "tires" / "chrono_185_80R14_pac2002.tir")

SIGMA_M = 0.25
SPEED_M_S = 10.0
TAU_S = SIGMA_M / SPEED_M_S


def test_a_slip_step_relaxes_with_time_constant_sigma_over_speed() -> None:
    kappa = -0.1
    sol = solve_ivp(
        lambda t, y: [lagged_slip_rate_per_s(kappa, y[0], SPEED_M_S, SIGMA_M)],
        (0.0, 10 * TAU_S),
        [0.0],
        rtol=1e-11,
        atol=1e-14,
        dense_output=True,
    )
    times = np.array([0.5, 1.0, 2.0, 5.0, 10.0]) * TAU_S
    lagged = sol.sol(times)[0]
    np.testing.assert_allclose(lagged, kappa * (1.0 - np.exp(-times / TAU_S)), rtol=1e-8)
    assert lagged[1] == pytest.approx(kappa * (1.0 - math.exp(-1.0)), rel=1e-8)  # t = tau
    assert abs(lagged[-1] - kappa) < 1e-4 * abs(kappa)  # tends to the kinematic slip


def test_the_exact_step_matches_the_ode_and_reaches_the_slip() -> None:
    kappa, lagged, dt = 0.08, -0.02, 1e-3
    for _ in range(round(3 * TAU_S / dt)):
        lagged = lagged_slip_after(kappa, lagged, SPEED_M_S, SIGMA_M, dt)
    assert lagged == pytest.approx(kappa + (-0.02 - kappa) * math.exp(-3.0), rel=1e-12)
    assert lagged_slip_after(kappa, -0.02, -SPEED_M_S, SIGMA_M, dt) == lagged_slip_after(
        kappa, -0.02, SPEED_M_S, SIGMA_M, dt
    )  # the lag depends on |V|


def test_zero_relaxation_length_is_the_static_slip_bit_for_bit() -> None:
    for kappa in (-1.0, -0.123456789, 0.0, 0.3):
        assert lagged_slip_after(kappa, 0.7, SPEED_M_S, 0.0, 1e-3) == kappa


@pytest.mark.parametrize("force_unit", ["newton", "kN"])
def test_relaxation_length_from_the_tir_carcass_stiffness(tmp_path: Path, force_unit: str) -> None:
    per_n = 1e-3 if force_unit == "kN" else 1.0
    text = Path(SAMPLE_TIR).read_text(encoding="utf-8").replace("'newton'", f"'{force_unit}'")
    text = text.replace("= 4000 ", f"= {4000 * per_n:g} ")
    text += f"[STRUCTURAL]\nLONGITUDINAL_STIFFNESS = {4e5 * per_n:g}\nPCFX1 = 0.2\nPCFX2 = 0.05\n"
    path = tmp_path / "stiff.tir"
    path.write_text(text, encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tire = read_tir(str(path))
    assert tire.longitudinal_stiffness_n_m == pytest.approx(4e5)
    for fz in (2000.0, 4000.0, 6000.0):
        dfz = (fz - 4000.0) / 4000.0
        expected = fz * tire.pkx1 / (4e5 * (1.0 + 0.2 * dfz + 0.05 * dfz**2))  # no PKX2, PKX3
        sigma = longitudinal_relaxation_length_m(tire.kernel_array(), fz)
        assert sigma == pytest.approx(expected, rel=1e-12)
    assert longitudinal_relaxation_length_m(tire.kernel_array(), 4000.0) == pytest.approx(0.22303)


def test_relaxation_length_from_mf52_ptx_coefficients() -> None:
    """Chrono's PAC2002 sample (PTX1 1.9021, PTX2 -0.0014739, PTX3 0.03631, R0 0.376 m, FNOMIN
    3800 N, LSGKP 1): sigma = F_z (PTX1 + PTX2 dfz) exp(-PTX3 dfz) R0 / FNOMIN, by hand; at the
    nominal load PTX1 R0 = 0.7152 m. A carcass stiffness, where given, takes precedence."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tire = read_tir(CHRONO)
    c = tire.kernel_array()
    assert (tire.ptx1, tire.ptx2, tire.ptx3, tire.lsgkp) == (1.9021, -0.0014739, 0.03631, 1.0)
    for fz in (981.0, 3800.0, 6000.0):
        dfz = (fz - 3800.0) / 3800.0
        expected = fz * (1.9021 - 0.0014739 * dfz) * math.exp(-0.03631 * dfz) * 0.376 / 3800.0
        assert longitudinal_relaxation_length_m(c, fz) == pytest.approx(expected, rel=1e-14)
    assert longitudinal_relaxation_length_m(c, 3800.0) == pytest.approx(1.9021 * 0.376, rel=1e-14)
    stiff = c.copy()
    stiff[mfc.LONGITUDINAL_STIFFNESS_N_M] = 4e5
    assert longitudinal_relaxation_length_m(stiff, 3800.0) == carcass_relaxation_length_m(
        stiff, 3800.0
    )
    none = c.copy()
    none[mfc.PTX1] = 0.0
    assert math.isnan(longitudinal_relaxation_length_m(none, 3800.0))


def test_a_file_without_carcass_stiffness_gives_none_silently() -> None:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        tire = read_tir(SAMPLE_TIR)
    assert tire.longitudinal_stiffness_n_m == 0.0
    assert not any("LONGITUDINAL_STIFFNESS" in str(w.message) for w in caught)
