"""Magic Formula 6.1 tire forces (Pacejka, "Tire and Vehicle Dynamics", 3rd ed., 2012, sec. 4.3.2,
eqs. 4.E1-4.E30, 4.E50-4.E67) at zero camber, without turn slip, at the nominal inflation pressure.

Scalar, compiled, inlined functions of the coefficient array `c` (`MagicFormulaTire.kernel_array`),
the longitudinal slip kappa (positive when driving), the lateral slip alpha* = tan(alpha) and the
vertical load fz_n; forces in N, in the TIR file's axis system (ISO-W, as MF-Tyre and MFeval).

`commonroad=True` (used only by the reference tests) evaluates CommonRoad's simplified PAC2002
(`vehiclemodels.utils.tire_model`) instead: no epsilon in B, the longitudinal vertical shift
inside the sine, K_y = PKY1 F_z, and lateral shifts that vanish at zero camber (docs/tires.md).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from chassistune.plants import mf_coefficients as mfc

EPSILON = 1e-6
"""epsilon_x, epsilon_y of 4.E16 and 4.E26: keeps B finite where C D vanishes (zero load)."""

FRICTION_DEGRESSION = 10.0
"""A_mu of 4.E8 (lambda'_mu = A_mu lambda*_mu / (1 + (A_mu - 1) lambda*_mu))."""

_jit = numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
"""Compile as a scalar function inlined into its callers (as the wheel kernel's tire laws)."""


@_jit
def sign(x: float) -> float:
    """sgn(x): 1, -1, or 0 at 0."""
    return 1.0 if x > 0.0 else (-1.0 if x < 0.0 else 0.0)


@_jit
def stiffness_factor(k: float, cs: float, d: float, commonroad: bool) -> float:
    """B = K / (C D + epsilon sgn D) (4.E16, 4.E26; CommonRoad's mode: no epsilon)."""
    eps = 0.0 if commonroad else (EPSILON if d >= 0.0 else -EPSILON)
    return k / (cs * d + eps)


@_jit
def load_increment(c: np.ndarray, fz_n: float) -> float:
    """dfz = (F_z - F'_z0) / F'_z0 with F'_z0 = FNOMIN LFZO (4.E1, 4.E2a)."""
    fz0 = c[mfc.FNOMIN_N] * c[mfc.LFZO]
    return (fz_n - fz0) / fz0


@_jit
def degressive_friction_scale(scale: float) -> float:
    """lambda'_mu of a friction scaling factor, which scales the vertical shifts (4.E8)."""
    return FRICTION_DEGRESSION * scale / (1.0 + (FRICTION_DEGRESSION - 1.0) * scale)


@_jit
def cos_arctan(x: float) -> float:
    """cos(arctan x) = 1 / sqrt(1 + x^2), the identity (one square root for an arctangent and a
    cosine in series)."""
    return 1.0 / math.sqrt(1.0 + x * x)


@_jit
def sin_shape_arctan(shape: float, x: float) -> float:
    """sin(shape arctan x), by the identity sin(2 arctan x) = 2 x / (1 + x^2) at MF 5.2's shape
    2 (PKY4's neutral value)."""
    if shape == 2.0:
        return 2.0 * x / (1.0 + x * x)
    return math.sin(shape * math.atan(x))


@_jit
def sine_curve(b: float, cs: float, d: float, e: float, x: float) -> float:
    """D sin[C arctan{B x - E (B x - arctan B x)}], the Magic Formula (4.E9, 4.E19)."""
    bx = b * x
    return d * math.sin(cs * math.atan(bx - e * (bx - math.atan(bx))))


@_jit
def cosine_curve(b: float, cs: float, e: float, x: float) -> float:
    """cos[C arctan{B x - E (B x - arctan B x)}], the combined-slip weighting (4.E51, 4.E59)."""
    bx = b * x
    return math.cos(cs * math.atan(bx - e * (bx - math.atan(bx))))


@_jit
def longitudinal_shape(
    c: np.ndarray, kappa: float, fz_n: float, commonroad: bool = False
) -> tuple[float, float, float, float, float, float, float]:
    """(B_x, C_x, D_x, E_x, S_Hx, S_Vx, K_xkappa) at slip kappa and load fz_n (4.E10-4.E18; E_x
    uses sgn(kappa_x), capped at 1)."""
    dfz = load_increment(c, fz_n)
    shx = (c[mfc.PHX1] + c[mfc.PHX2] * dfz) * c[mfc.LHX]
    svx = (
        fz_n
        * (c[mfc.PVX1] + c[mfc.PVX2] * dfz)
        * c[mfc.LVX]
        * degressive_friction_scale(c[mfc.LMUX])
    )
    cx = c[mfc.PCX1] * c[mfc.LCX]
    dx = (c[mfc.PDX1] + c[mfc.PDX2] * dfz) * c[mfc.LMUX] * fz_n
    ex = c[mfc.PEX1] + c[mfc.PEX2] * dfz + c[mfc.PEX3] * dfz * dfz
    ex = min(ex * (1.0 - c[mfc.PEX4] * sign(kappa + shx)) * c[mfc.LEX], 1.0)
    kx = fz_n * (c[mfc.PKX1] + c[mfc.PKX2] * dfz) * math.exp(c[mfc.PKX3] * dfz) * c[mfc.LKX]
    return stiffness_factor(kx, cx, dx, commonroad), cx, dx, ex, shx, svx, kx


@_jit
def longitudinal_force_pure_n(
    c: np.ndarray, kappa: float, fz_n: float, commonroad: bool = False
) -> float:
    """F_x0 = D_x sin[C_x arctan{B_x kappa_x - E_x (B_x kappa_x - arctan B_x kappa_x)}] + S_Vx
    (4.E9); CommonRoad's mode adds S_Vx to the sine's argument instead."""
    bx, cx, dx, ex, shx, svx, _ = longitudinal_shape(c, kappa, fz_n, commonroad)
    if commonroad:
        x = bx * (kappa + shx)
        return dx * math.sin(cx * math.atan(x - ex * (x - math.atan(x))) + svx)
    return sine_curve(bx, cx, dx, ex, kappa + shx) + svx


@_jit
def lateral_friction(c: np.ndarray, fz_n: float) -> float:
    """mu_y = (PDY1 + PDY2 dfz) LMUY (4.E23 at zero camber and nominal pressure)."""
    return (c[mfc.PDY1] + c[mfc.PDY2] * load_increment(c, fz_n)) * c[mfc.LMUY]


@_jit
def lateral_shape(
    c: np.ndarray, alpha: float, fz_n: float, commonroad: bool = False
) -> tuple[float, float, float, float, float, float, float]:
    """(B_y, C_y, D_y, E_y, S_Hy, S_Vy, K_yalpha) at lateral slip alpha and load fz_n (4.E20-4.E29
    at zero camber; K_yalpha 4.E25, E_y uses sgn(alpha_y), capped at 1)."""
    dfz = load_increment(c, fz_n)
    fz0 = c[mfc.FNOMIN_N] * c[mfc.LFZO]
    if commonroad:  # the shifts are signed by the camber, so vanish at zero camber
        shy = 0.0
        svy = 0.0
        ky = c[mfc.PKY1] * fz_n * c[mfc.LKY]
    else:
        shy = (c[mfc.PHY1] + c[mfc.PHY2] * dfz) * c[mfc.LHY]
        svy = (
            fz_n
            * (c[mfc.PVY1] + c[mfc.PVY2] * dfz)
            * c[mfc.LVY]
            * degressive_friction_scale(c[mfc.LMUY])
        )
        ky = (
            c[mfc.PKY1]
            * fz0
            * sin_shape_arctan(c[mfc.PKY4], fz_n / (c[mfc.PKY2] * fz0))
            * c[mfc.LKY]
        )
    cy = c[mfc.PCY1] * c[mfc.LCY]
    dy = lateral_friction(c, fz_n) * fz_n
    ey = (c[mfc.PEY1] + c[mfc.PEY2] * dfz) * (1.0 - c[mfc.PEY3] * sign(alpha + shy)) * c[mfc.LEY]
    return stiffness_factor(ky, cy, dy, commonroad), cy, dy, min(ey, 1.0), shy, svy, ky


@_jit
def lateral_force_pure_n(
    c: np.ndarray, alpha: float, fz_n: float, commonroad: bool = False
) -> float:
    """F_y0 = D_y sin[C_y arctan{B_y alpha_y - E_y (B_y alpha_y - arctan B_y alpha_y)}] + S_Vy
    (4.E19)."""
    by, cy, dy, ey, shy, svy, _ = lateral_shape(c, alpha, fz_n, commonroad)
    return sine_curve(by, cy, dy, ey, alpha + shy) + svy


@_jit
def longitudinal_weight(c: np.ndarray, kappa: float, alpha: float, fz_n: float) -> float:
    """G_xalpha, the reduction of F_x by lateral slip (4.E51-4.E57 at zero camber)."""
    shxa = c[mfc.RHX1]
    bxa = c[mfc.RBX1] * cos_arctan(c[mfc.RBX2] * kappa) * c[mfc.LXAL]
    cxa = c[mfc.RCX1]
    exa = min(c[mfc.REX1] + c[mfc.REX2] * load_increment(c, fz_n), 1.0)
    return cosine_curve(bxa, cxa, exa, alpha + shxa) / cosine_curve(bxa, cxa, exa, shxa)


@_jit
def lateral_weight(c: np.ndarray, kappa: float, alpha: float, fz_n: float) -> float:
    """G_ykappa, the reduction of F_y by longitudinal slip (4.E59-4.E65 at zero camber)."""
    dfz = load_increment(c, fz_n)
    shyk = c[mfc.RHY1] + c[mfc.RHY2] * dfz
    byk = c[mfc.RBY1] * cos_arctan(c[mfc.RBY2] * (alpha - c[mfc.RBY3])) * c[mfc.LYKA]
    cyk = c[mfc.RCY1]
    eyk = min(c[mfc.REY1] + c[mfc.REY2] * dfz, 1.0)
    return cosine_curve(byk, cyk, eyk, kappa + shyk) / cosine_curve(byk, cyk, eyk, shyk)


@_jit
def lateral_shift_by_slip_n(
    c: np.ndarray, kappa: float, alpha: float, fz_n: float, mu_y: float
) -> float:
    """S_Vykappa, the lateral force longitudinal slip induces (4.E66, 4.E67 at zero camber)."""
    dvyk = mu_y * fz_n * (c[mfc.RVY1] + c[mfc.RVY2] * load_increment(c, fz_n))
    dvyk *= cos_arctan(c[mfc.RVY4] * alpha)
    return dvyk * math.sin(c[mfc.RVY5] * math.atan(c[mfc.RVY6] * kappa)) * c[mfc.LVYKA]


@_jit
def longitudinal_force_n(c: np.ndarray, kappa: float, alpha: float, fz_n: float) -> float:
    """F_x = G_xalpha F_x0 under combined slip (4.E50)."""
    return longitudinal_weight(c, kappa, alpha, fz_n) * longitudinal_force_pure_n(c, kappa, fz_n)


@_jit
def lateral_force_n(c: np.ndarray, kappa: float, alpha: float, fz_n: float) -> float:
    """F_y = G_ykappa F_y0 + S_Vykappa under combined slip (4.E58)."""
    fy0 = lateral_force_pure_n(c, alpha, fz_n)
    mu_y = lateral_friction(c, fz_n)
    return lateral_weight(c, kappa, alpha, fz_n) * fy0 + lateral_shift_by_slip_n(
        c, kappa, alpha, fz_n, mu_y
    )
