"""The Magic Formula tire on the 7-DOF vehicle (docs/tires.md, "On the vehicle"): its slips from
the vehicle's wheel kinematics, its forces and their load derivative for the load solve, and the
braking capacity of the adhesion bound (the surface rows: `plants.abs_vehicle.mf_surface_row`).

Slips in the TIR files' axis system, ISO-W (TYDEX), as MF-Tyre and MFeval take them:
kappa = -V_sx/|V_cx|, tan(alpha) = V_cy/|V_cx| (the wheel centre's velocity for the contact
point's), where the files' negative cornering stiffness (PKY1 < 0) makes F_y oppose V_cy. From
the vehicle's sx = (u - w R)/|V| and v/|V| of the wheel-frame velocity (u, v)
(`plants.abs_vehicle`), with |u| = |V| sqrt(1 - (v/|V|)^2):

    kappa = -(u - w R)/|u| = -sx / c,   tan(alpha) = v/|u| = (v/|V|) / c,
    c = sqrt(max(1 - (v/|V|)^2, COS_MIN^2)),

exact while |V| is above the speed floor (`min_speed_m_s`); below it (the last instants of a stop)
they are the floored slips divided by the same cosine. The file's tyre is on the left wheels and
its mirror image on the right ones (F_y(kappa, alpha) -> -F_y(kappa, -alpha), F_x(kappa, -alpha)),
as a car mounts a left tyre's twin on its right side, so that the file's conicity and ply-steer
(S_Hy, S_Vy) cancel in straight-line braking; TYRESIDE is not read (every file is taken as
measured on the left). The forces are MF 6.1 under combined slip
(`plants.magic_formula`, eqs. 4.E50 and 4.E58) in the wheel frame: F_x < 0 braking, F_y
against v, as the bilinear tire's. The load solve's Jacobian takes dF/dF_z by a forward
difference of step FZ_STEP_RATIO FNOMIN (Newton's iteration converges on the residual, which is
exact; the difference only sets its rate).
"""

from __future__ import annotations

import math
from typing import Any

import numba
import numpy as np

from chassistune.plants import mf_coefficients as mfc
from chassistune.plants.magic_formula import lateral_force_n, longitudinal_force_n
from chassistune.plants.mf_coefficients import MagicFormulaTire
from chassistune.plants.mf_peak import braking_peak

COS_MIN = 1e-3
"""Least |u|/|V| the slips divide by (a wheel sliding sideways: kappa and tan(alpha) stay
finite, the forces saturated there)."""

FZ_STEP_RATIO = 1e-6
"""The load step of the forward difference dF/dF_z, as a fraction of FNOMIN."""

CAPACITY_GRID = 400
"""Load steps of the adhesion bound's search over load splits (`braking_capacity_n`)."""

_jit = numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
_CALLED: dict[str, Any] = {"cache": True, "nogil": True, "error_model": "numpy", "_nrt": False}
_called = numba.njit(**_CALLED)
"""A function compiled once and called (not inlined: the Magic Formula's body copied into every
caller costs the vehicle kernel's compile about 20 s), without numba's runtime, as the kernel."""


@_jit
def magic_formula_slips(sx: float, vr: float) -> tuple[float, float]:
    """(kappa, tan(alpha)) of a wheel from the vehicle's (sx, v/|V|) (module docstring)."""
    c = math.sqrt(max(1.0 - vr * vr, COS_MIN * COS_MIN))
    return -sx / c, vr / c


@_called
def wheel_forces(
    sx: float, vr: float, fz: float, c: np.ndarray, mirrored: bool
) -> tuple[float, float]:
    """(F_x, F_y) in N of a wheel with slips (sx, v/|V|) at load fz, 0 unloaded; `mirrored`: the
    file's tyre mirrored (a right wheel: module docstring), F_y(alpha) -> -F_y(-alpha)."""
    if fz <= 0.0:
        return 0.0, 0.0
    kappa, alpha = magic_formula_slips(sx, vr)
    side = -1.0 if mirrored else 1.0
    alpha *= side
    return longitudinal_force_n(c, kappa, alpha, fz), side * lateral_force_n(c, kappa, alpha, fz)


@_called
def wheel_forces_and_derivative(
    sx: float, vr: float, fz: float, c: np.ndarray, mirrored: bool
) -> tuple[float, float, float, float]:
    """(F_x, F_y, dF_x/dF_z, dF_y/dF_z) of `wheel_forces`, the derivative by the forward
    difference of FZ_STEP_RATIO FNOMIN."""
    h = FZ_STEP_RATIO * c[mfc.FNOMIN_N]
    fx, fy = wheel_forces(sx, vr, fz, c, mirrored)
    fx_h, fy_h = wheel_forces(sx, vr, fz + h, c, mirrored)
    return fx, fy, (fx_h - fx) / h, (fy_h - fy) / h


def braking_capacity_n(tires: tuple[MagicFormulaTire, ...], total_load_n: float) -> float:
    """The largest total braking force the tires can give, max over loads z_i >= 0 with
    sum z_i = total_load_n of sum_i |F_x0 peak|(z_i) (`mf_peak.braking_peak`): the max-plus
    convolution of the tires' peak-force curves on CAPACITY_GRID load steps, and the equal split
    (the optimum when every curve is concave in the load, as with linear load sensitivity)."""
    loads = np.linspace(0.0, total_load_n, CAPACITY_GRID + 1)
    curves = {t: np.array([0.0] + [-braking_peak(t, z)[1] for z in loads[1:]]) for t in set(tires)}
    k = np.arange(CAPACITY_GRID + 1)
    below = k[None, :] <= k[:, None]  # j <= k
    best = curves[tires[0]]
    for tire in tires[1:]:
        # best[k] over the tires so far = max over j <= k of best[j] + peak[k - j]
        peak = curves[tire]
        best = np.where(below, best[None, :] + peak[np.abs(k[:, None] - k[None, :])], -1.0)
        best = best.max(axis=1)
    equal = total_load_n / len(tires)
    return max(float(best[-1]), sum(-braking_peak(t, equal)[1] for t in tires))
