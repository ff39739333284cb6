"""Our MF 6.1 evaluation against a second implementation: MFeval (MFeval.jl, useMode 221) on
its MF 6.1 sample tyre and on Project Chrono's HMMWV PAC2002 tyre (tests/plants/data/README.md).

Tolerance: 1e-12 N per N of load for the forces, 1e-12 relative for the stiffnesses, friction
coefficients and relaxation length (measured: at most 2e-16, i.e. last-bit rounding).
"""

from __future__ import annotations

import csv
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from chassistune.plants import magic_formula as mf
from chassistune.plants.mf_arrays import forces_n
from chassistune.plants.mf_coefficients import MagicFormulaTire
from chassistune.plants.mf_relaxation import longitudinal_relaxation_length_m
from chassistune.plants.tir import read_tir

DATA = Path(__file__).parent / "data"
REL_TOL = 1e-12


def rows(tyre: str) -> list[dict[str, float]]:
    with open(DATA / "mfeval_reference.csv", encoding="utf-8") as fh:
        return [
            {k: float(v) if v else math.nan for k, v in row.items() if k != "tyre"}
            for row in csv.DictReader(fh)
            if row["tyre"] == tyre
        ]


def read(tyre: str) -> MagicFormulaTire:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # camber, pressure and moment terms: ignored
        return read_tir(str(DATA / f"{tyre}.tir"), lateral=True)


def coefficients(tyre: str) -> np.ndarray:
    return read(tyre).kernel_array()


@pytest.mark.parametrize(
    ("tyre", "n_rows"), [("MagicFormula61_Parameters", 81), ("HMMWV_Pac02Tire", 10)]
)
def test_forces_equal_mfeval(tyre: str, n_rows: int) -> None:
    points = rows(tyre)
    assert len(points) == n_rows
    fz, kappa, alpha, fx, fy = (
        np.array([p[k] for p in points]) for k in ("fz_n", "kappa", "alpha_rad", "fx_n", "fy_n")
    )
    ours_x, ours_y = forces_n(read(tyre), kappa, np.tan(alpha), fz)
    assert np.max(np.abs(ours_x - fx) / fz) <= REL_TOL
    assert np.max(np.abs(ours_y - fy) / fz) <= REL_TOL


def test_the_array_forces_are_the_scalar_functions_bit_for_bit() -> None:
    tire = read("MagicFormula61_Parameters")
    c = tire.kernel_array()
    kappa = np.linspace(-1.0, 1.0, 21)[:, None]
    alpha = np.linspace(-0.4, 0.4, 9)[None, :]
    fx, fy = forces_n(tire, kappa, alpha, 5000.0)
    assert fx.shape == fy.shape == (21, 9)
    for i, k in enumerate(kappa[:, 0]):
        for j, a in enumerate(alpha[0]):
            assert fx[i, j] == mf.longitudinal_force_n(c, k, a, 5000.0)
            assert fy[i, j] == mf.lateral_force_n(c, k, a, 5000.0)


@pytest.mark.parametrize("tyre", ["MagicFormula61_Parameters", "HMMWV_Pac02Tire"])
def test_stiffness_and_friction_equal_mfeval(tyre: str) -> None:
    c = coefficients(tyre)
    for p in rows(tyre):
        fz = p["fz_n"]
        _, _, dx, _, _, _, kx = mf.longitudinal_shape(c, p["kappa"], fz)
        ky = mf.lateral_shape(c, math.tan(p["alpha_rad"]), fz)[6]
        assert kx == pytest.approx(p["kxk_n"], rel=REL_TOL)
        assert ky == pytest.approx(p["kya_n_rad"], rel=REL_TOL)
        assert dx / fz == pytest.approx(p["mux"], rel=REL_TOL)
        assert mf.lateral_friction(c, fz) == pytest.approx(p["muy"], rel=REL_TOL)


def test_relaxation_length_equals_mfeval() -> None:
    c = coefficients("MagicFormula61_Parameters")
    for p in rows("MagicFormula61_Parameters"):
        sigma_m = longitudinal_relaxation_length_m(c, p["fz_n"])
        assert sigma_m == pytest.approx(p["sigmax_m"], rel=REL_TOL)


def test_the_reference_is_sensitive_to_the_terms_it_checks() -> None:
    """A load term and a combined-slip term changed by 1 % move the forces far past the
    tolerance (so the comparisons above could fail)."""
    base = coefficients("HMMWV_Pac02Tire")
    p = rows("HMMWV_Pac02Tire")[-1]  # combined slip at 0.73 FNOMIN
    fz, kappa, alpha = p["fz_n"], p["kappa"], math.tan(p["alpha_rad"])
    for name in ("PDX2", "PKY2", "RBX1", "RBY1"):
        c = base.copy()
        c[getattr(mf.mfc, name)] *= 1.01
        moved = max(
            abs(mf.longitudinal_force_n(c, kappa, alpha, fz) - p["fx_n"]),
            abs(mf.lateral_force_n(c, kappa, alpha, fz) - p["fy_n"]),
        )
        assert moved / fz > 1e-6, name
