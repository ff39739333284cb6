"""Transient slip: the first-order relaxation-length model (Pacejka 2012, sec. 7.2.1, the
single-contact-point model, sigma dkappa'/dt + |V| kappa' = |V| kappa with the kinematic slip
kappa = -V_sx / |V|).

The lagged slip kappa' (longitudinal, or the lateral slip alpha' alike) follows the kinematic slip
with the time constant sigma / |V|: the tire must roll its relaxation length sigma for the force
to build up. The forces are then evaluated at kappa' instead of kappa. sigma = 0 is the static
tire (kappa' = kappa). sigma is a parameter, or the TIR file's: MF 6.1's from the carcass
stiffness, or MF 5.2's from PTX1-3 (longitudinal) and PTY1-2 (lateral).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from chassistune.plants import mf_coefficients as mfc
from chassistune.plants.magic_formula import lateral_shape, load_increment, longitudinal_shape


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def lagged_slip_rate_per_s(
    slip: float, lagged_slip: float, speed_m_s: float, relaxation_length_m: float
) -> float:
    """dkappa'/dt = (|V| / sigma) (kappa - kappa'), for sigma > 0."""
    return abs(speed_m_s) / relaxation_length_m * (slip - lagged_slip)


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def lagged_slip_rate_from_slip_speed_per_s(
    slip_speed_m_s: float, lagged_slip: float, speed_m_s: float, relaxation_length_m: float
) -> float:
    """dkappa'/dt = (V_s - |V| kappa') / sigma, V_s = |V| kappa the slip speed: the same ODE in
    the form that stays well posed as V -> 0 (no division by V; Pacejka 2012, eq. 7.9), for
    sigma > 0."""
    return (slip_speed_m_s - abs(speed_m_s) * lagged_slip) / relaxation_length_m


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def lagged_slip_after(
    slip: float, lagged_slip: float, speed_m_s: float, relaxation_length_m: float, dt_s: float
) -> float:
    """kappa' after dt_s with kappa and V held: the exact solution
    kappa + (kappa' - kappa) exp(-|V| dt / sigma); sigma = 0 gives kappa itself."""
    if relaxation_length_m == 0.0:
        return slip
    return slip + (lagged_slip - slip) * math.exp(-abs(speed_m_s) * dt_s / relaxation_length_m)


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def longitudinal_relaxation_length_m(c: np.ndarray, fz_n: float) -> float:
    """The TIR file's sigma_kappa at load fz_n: MF 6.1's |K_xkappa / C_x| where the file gives
    LONGITUDINAL_STIFFNESS (`carcass_relaxation_length_m`), else MF 5.2's from PTX1-3
    (`pac2002_relaxation_length_m`); NaN where it gives neither."""
    if c[mfc.LONGITUDINAL_STIFFNESS_N_M] > 0.0:
        return carcass_relaxation_length_m(c, fz_n)
    if c[mfc.PTX1] > 0.0:
        return pac2002_relaxation_length_m(c, fz_n)
    return math.nan


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def pac2002_relaxation_length_m(c: np.ndarray, fz_n: float) -> float:
    """MF 5.2's sigma_kappa = F_z (PTX1 + PTX2 dfz) exp(-PTX3 dfz) (R_0 / F_z0) LSGKP, with
    R_0 = UNLOADED_RADIUS and F_z0 = FNOMIN (MF-Tyre 5.2's equation manual, as MFeval 4.0 and
    the Modelica PlanarMechanics MF 5.2 tire write it)."""
    dfz = load_increment(c, fz_n)
    shape = (c[mfc.PTX1] + c[mfc.PTX2] * dfz) * math.exp(-c[mfc.PTX3] * dfz)
    return fz_n * shape * (c[mfc.UNLOADED_RADIUS_M] / c[mfc.FNOMIN_N]) * c[mfc.LSGKP]


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def carcass_relaxation_length_m(c: np.ndarray, fz_n: float) -> float:
    """MF 6.1's sigma_kappa = |K_xkappa / C_x| at load fz_n, with the longitudinal carcass
    stiffness C_x = LONGITUDINAL_STIFFNESS (1 + PCFX1 dfz + PCFX2 dfz^2) (Besselink, Schmeitz and
    Pacejka 2010, Vehicle System Dynamics 48 sup. 1, eqs. 17 and 19, at nominal pressure). Needs
    LONGITUDINAL_STIFFNESS > 0 (0 in `MagicFormulaTire` when the file does not give it)."""
    k = longitudinal_shape(c, 0.0, fz_n)[6]
    return carcass_length_m(c, k, mfc.LONGITUDINAL_STIFFNESS_N_M, fz_n)


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def carcass_length_m(c: np.ndarray, slip_stiffness: float, row: int, fz_n: float) -> float:
    """|K / C| at load fz_n, the carcass stiffness C = c[row] (1 + c[row + 1] dfz + c[row + 2]
    dfz^2): LONGITUDINAL_STIFFNESS, PCFX1, PCFX2 or LATERAL_STIFFNESS, PCFY1, PCFY2 (Besselink,
    Schmeitz and Pacejka 2010, eqs. 17-19, at nominal pressure)."""
    dfz = load_increment(c, fz_n)
    stiffness_n_m = c[row] * (1.0 + c[row + 1] * dfz + c[row + 2] * dfz * dfz)
    return abs(slip_stiffness / stiffness_n_m)


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def lateral_relaxation_length_m(c: np.ndarray, fz_n: float) -> float:
    """The TIR file's sigma_alpha at load fz_n: MF 6.1's |K_yalpha / C_y| where the file gives
    LATERAL_STIFFNESS (`carcass_lateral_relaxation_length_m`), else MF 5.2's from PTY1-2
    (`pac2002_lateral_relaxation_length_m`); NaN where it gives neither."""
    if c[mfc.LATERAL_STIFFNESS_N_M] > 0.0:
        return carcass_lateral_relaxation_length_m(c, fz_n)
    pac2002 = c[mfc.PTY1] > 0.0 and c[mfc.PTY2] > 0.0
    return pac2002_lateral_relaxation_length_m(c, fz_n) if pac2002 else math.nan


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def pac2002_lateral_relaxation_length_m(c: np.ndarray, fz_n: float) -> float:
    """MF 5.2's sigma_alpha = PTY1 sin(2 arctan(F_z / (PTY2 F'_z0))) R_0 LFZO LSGAL at zero camber,
    F'_z0 = FNOMIN LFZO, R_0 = UNLOADED_RADIUS (MF-Tyre 5.2's equation manual, as MFeval.jl's
    `calc_relax`, src/solver/relaxation.jl, and BobLib's MF 5.2 TransientSlip.mo write it, there
    times (1 - PKY3 |gamma|))."""
    fz0 = c[mfc.FNOMIN_N] * c[mfc.LFZO]
    shape = c[mfc.PTY1] * math.sin(2.0 * math.atan(fz_n / (c[mfc.PTY2] * fz0)))
    return shape * c[mfc.UNLOADED_RADIUS_M] * c[mfc.LFZO] * c[mfc.LSGAL]


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def carcass_lateral_relaxation_length_m(c: np.ndarray, fz_n: float) -> float:
    """MF 6.1's sigma_alpha = |K_yalpha / C_y| at load fz_n, with the lateral carcass stiffness
    C_y = LATERAL_STIFFNESS (1 + PCFY1 dfz + PCFY2 dfz^2) (Besselink, Schmeitz and Pacejka 2010,
    eqs. 18 and 19, at nominal pressure) and K_yalpha at zero camber (4.E25). Needs
    LATERAL_STIFFNESS > 0 (0 in `MagicFormulaTire` when the file does not give it)."""
    k = lateral_shape(c, 0.0, fz_n)[6]
    return carcass_length_m(c, k, mfc.LATERAL_STIFFNESS_N_M, fz_n)
