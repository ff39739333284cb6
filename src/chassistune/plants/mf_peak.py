"""Where the Magic Formula's longitudinal force peaks, and a road's friction as the TIR file's
friction scaling (LMUX, LMUY).

The pure-slip force D sin[C arctan f(x)] + S_V (Pacejka 2012, eq. 4.E9) is extreme where
C arctan f(x) = +-pi/2, i.e. f(x) = B x - E (B x - arctan B x) = +-tan(pi / (2 C)) for C > 1;
f is increasing for E < 1 (f' >= min(B, B (1 - E))), so the root is unique. The peak is
+-D + S_V at kappa = x - S_Hx.
"""

from __future__ import annotations

import dataclasses
import math

from scipy.optimize import brentq

from chassistune.errors import InputError
from chassistune.plants.magic_formula import longitudinal_force_pure_n, longitudinal_shape
from chassistune.plants.mf_coefficients import MagicFormulaTire


def braking_peak(tire: MagicFormulaTire, fz_n: float) -> tuple[float, float]:
    """(kappa at the braking peak, the peak braking force F_x0 < 0 in N) at load fz_n, over
    kappa in [-1, 0]: the root above, or kappa = -1 when the curve has no peak there (C <= 1, or
    the peak beyond a locked wheel); for |S_Hx| < 1."""
    c = tire.kernel_array()
    bx, cx, dx, ex, shx, svx, _ = longitudinal_shape(c, -1.0, fz_n)  # E of kappa_x < 0
    locked = (-1.0, float(longitudinal_force_pure_n(c, -1.0, fz_n)))
    if not cx > 1.0:
        return locked
    target = -math.tan(math.pi / (2.0 * cx))

    def shape(x: float) -> float:
        return bx * x - ex * (bx * x - math.atan(bx * x)) - target

    x_lo = -1.0 + shx
    if shape(x_lo) > 0.0:
        return locked
    x_peak = brentq(shape, x_lo, 0.0, xtol=1e-15)
    return float(x_peak - shx), float(-dx + svx)


def braking_friction_peak(tire: MagicFormulaTire, fz_n: float) -> float:
    """The peak braking friction coefficient |F_x0| / F_z at load fz_n."""
    return -braking_peak(tire, fz_n)[1] / fz_n


def scaled_to_road(tire: MagicFormulaTire, road_mu_peak: float, fz_n: float) -> MagicFormulaTire:
    """The tire on a road of peak friction road_mu_peak: LMUX and LMUY times the road's peak over
    the tire's braking peak at fz_n (the peak then is the road's where S_Vx = 0; K_x stays, so the
    peak slip moves)."""
    if not road_mu_peak > 0.0:
        raise InputError("road", f"peak friction must be positive, got {road_mu_peak:g}")
    factor = road_mu_peak / braking_friction_peak(tire, fz_n)
    return dataclasses.replace(tire, lmux=tire.lmux * factor, lmuy=tire.lmuy * factor)
