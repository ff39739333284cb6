"""7-DOF vehicle ABS physics (`abs-vehicle`, design.md 3.3; deffao-vehicle-abs Table 2).

The combined-slip tire, the load/force loop solved exactly at every evaluation, and the exact
stopping bounds (the parameters and the preset `paper-deffao`: `plants.abs_vehicle_params`). The
closed loop itself is compiled in `chassistune.sim.abs_vehicle_kernel`.

Axes ISO 8855: x forward, y left, yaw counter-clockwise positive. Wheels fl, fr, rl, rr at
x_i = (lf, lf, -lr, -lr), y_i = (tf/2, -tf/2, tr/2, -tr/2).

Loads (design.md 3.3), with ax = sum Fx_i / m, ay = sum Fy_i / m the CG accelerations:
    Fz_f{l,r} = m g lr/(2L) - m ax h/(2L) -/+ m ay h lr/(tf L)
    Fz_r{l,r} = m g lf/(2L) + m ax h/(2L) -/+ m ay h lf/(tr L),   Fz_i >= 0,
i.e. Fz_i = Fz0_i + A_i ax + B_i ay (lateral transfer split by the static axle loads).

Tire (combined slip, in the slip-vector form of design.md 3.3 scaled by S_T), with |V| the wheel
centre's speed floored at `min_speed_m_s`:
    sx = (u - w R)/|V|,   sy = (v/|V|) C S_T/(mu_h Fz),   s = |(sx, sy)|,
    |F| = Fz mu(min(s, 1)),   (Fx, Fy) = -|F| (sx, sy)/s     (mu the bilinear curve of 3.2),
or the Magic Formula under combined slip from a TIR file (`plants.vehicle_mf`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from chassistune.plants.abs_vehicle_params import VehicleParams
from chassistune.plants.mf_arrays import forces_n
from chassistune.plants.mf_coefficients import N_MF_COEFFICIENTS, MagicFormulaTire
from chassistune.plants.mf_peak import braking_peak
from chassistune.plants.vehicle_mf import wheel_forces_and_derivative

WHEELS = ("fl", "fr", "rl", "rr")
N_WHEELS = 4

# surface rows (one per surface of a road): bilinear coefficients as `tires.tire_mu` reads them,
# then the peak, the lock value and C S_T / mu_h (the lateral slip scale times Fz), the target
# slip; then 1.0 for the Magic Formula tire (`plants.vehicle_mf`) and its coefficients
# (`MagicFormulaTire.kernel_array`, the friction scaled to the surface), 0 for the bilinear one
SF_ST, SF_RISE, SF_FALL0, SF_FALL1, SF_MU_PEAK, SF_MU_LOCK, SF_LAT, SF_TARGET, SF_MF = range(9)
SF_COEF = 9
N_SURFACE = SF_COEF + N_MF_COEFFICIENTS

# work rows of one force evaluation (columns: the four wheels)
WK_SX, WK_VR, WK_CS, WK_SN, WK_FZ, WK_FXW, WK_FXB, WK_FYB = range(8)
N_WORK = 8
# geometry rows (columns: the four wheels): x_i, y_i, Fz0_i, A_i, B_i
GEO_X, GEO_Y, GEO_FZ0, GEO_A, GEO_B = range(5)
N_GEO = 5

MF_SLIP_OPT_MAX = 0.999
"""The target slip of a Magic Formula curve that peaks at a locked wheel (or beyond)."""

RK4_REAL_LIMIT = 2.785
"""RK4's stability limit on the negative real axis (|lambda dt| below it)."""


def wheel_positions(pp: VehicleParams) -> tuple[np.ndarray, np.ndarray]:
    """(x_i, y_i) of the four wheels in the body frame."""
    lf, lr = pp.cg_to_front_m, pp.cg_to_rear_m
    tf, tr = pp.track_front_m, pp.track_rear_m
    return np.array([lf, lf, -lr, -lr]), np.array([tf / 2, -tf / 2, tr / 2, -tr / 2])


def load_coefficients(pp: VehicleParams) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(Fz0_i, A_i, B_i) of Fz_i = Fz0_i + A_i ax + B_i ay (design.md 3.3 load transfer)."""
    m, g, h = pp.mass_kg, pp.g_m_s2, pp.cg_height_m
    lf, lr, big_l = pp.cg_to_front_m, pp.cg_to_rear_m, pp.wheelbase_m
    tf, tr = pp.track_front_m, pp.track_rear_m
    fz0 = np.array([m * g * lr, m * g * lr, m * g * lf, m * g * lf]) / (2 * big_l)
    a = np.array([-1.0, -1.0, 1.0, 1.0]) * m * h / (2 * big_l)
    b = np.array(
        [
            -m * h * lr / (tf * big_l),
            m * h * lr / (tf * big_l),
            -m * h * lf / (tr * big_l),
            m * h * lf / (tr * big_l),
        ]
    )
    return fz0, a, b


def surface_row(
    slip_opt: float, mu_peak: float, mu_lock: float, stiffness_n_rad: float
) -> np.ndarray:
    """One surface row (SF_* columns) of a bilinear curve (derlsp-ao-abs eq. 5)."""
    st, h, g = slip_opt, mu_peak, mu_lock
    row = np.zeros(N_SURFACE)
    row[SF_ST] = st
    row[SF_RISE] = h / st
    row[SF_FALL0] = (h - g * st) / (1.0 - st)
    row[SF_FALL1] = (h - g) / (1.0 - st)
    row[SF_MU_PEAK] = h
    row[SF_MU_LOCK] = g
    row[SF_LAT] = stiffness_n_rad * st / h
    row[SF_TARGET] = st
    return row


def mf_surface_row(tire: MagicFormulaTire, fz_n: float, stiffness_n_rad: float) -> np.ndarray:
    """One surface row of the Magic Formula tire `tire` (its friction already the surface's):
    the bilinear columns from its braking curve at the load fz_n (the peak's slip and friction,
    the locked wheel's friction; the target is the peak's slip), then SF_MF = 1 and the
    coefficients. The bilinear columns serve the bounds' and step checks' figures only: the
    kernel's forces are the Magic Formula's."""
    kappa, force_n = braking_peak(tire, fz_n)
    peak = -force_n / fz_n
    lock = -float(forces_n(tire, -1.0, 0.0, fz_n)[0]) / fz_n
    row = surface_row(min(-kappa, MF_SLIP_OPT_MAX), peak, min(lock, peak), stiffness_n_rad)
    row[SF_MF] = 1.0
    row[SF_COEF:] = tire.kernel_array()
    return row


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def bilinear_mu(s, surfs, k):
    """mu(s) of surface row k for s in [0, 1] (the longitudinal curve, as `tires.tire_mu`)."""
    return (
        surfs[k, SF_RISE] * s
        if s <= surfs[k, SF_ST]
        else surfs[k, SF_FALL0] - surfs[k, SF_FALL1] * s
    )


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def tire_force(sx, vr, fz, surfs, k, right=False):
    """Combined-slip force (Fx, Fy) of one wheel in its own frame and dF/dFz (design.md 3.3).

    sx = (u - w R)/|V|, vr = v/|V|; the surface is row k of `surfs` (indexed in place: a row
    view would cost reference counting in the kernel's inner loop). Returns
    (fx, fy, dfx_dfz, dfy_dfz). With vr = 0 the force is exactly fx = -mu(|sx|) Fz sign(sx), fy = 0.
    A Magic Formula surface (SF_MF) gives `vehicle_mf.wheel_forces_and_derivative` instead, the
    file's tyre mirrored on a `right` wheel.
    """
    if surfs[k, SF_MF] != 0.0:
        return wheel_forces_and_derivative(sx, vr, max(fz, 0.0), surfs[k, SF_COEF:], right)
    if fz <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    sy = vr * surfs[k, SF_LAT] / fz
    s = math.sqrt(sx * sx + sy * sy)
    if s == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    sc = min(s, 1.0)
    mu = bilinear_mu(sc, surfs, k)
    if sc <= surfs[k, SF_ST]:
        dmu = surfs[k, SF_RISE]
    elif s < 1.0:
        dmu = -surfs[k, SF_FALL1]
    else:
        dmu = 0.0
    f = fz * mu
    cx = sx / s
    cy = sy / s
    # F = -Fz phi(s) (sx, sy) with phi = mu/s and sy ~ 1/Fz: differentiate in Fz
    t = (dmu * s - mu) / (s * s) * sy * sy / s
    return -f * cx, -f * cy, -mu * cx + t * sx, t * sy


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def straight_force_per_load(sx, surfs, k):
    """Fx / Fz of `tire_force` without lateral slip: -mu(min(|sx|, 1)) sign(sx) (0 at sx = 0)."""
    s = abs(sx)
    mu = bilinear_mu(min(s, 1.0), surfs, k)
    return -math.copysign(mu, sx) if s > 0.0 else 0.0


MAX_LOAD_ITERATIONS = 40
LOAD_TOL_M_S2 = 1e-11


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def solve_loads(wk, surfs, sidx, col, geo, mass, ax0, ay0):
    """Solve the load/force loop Fz_i(ax, ay), F_i(Fz_i), (ax, ay) = sum F_i / m exactly.

    wk: work rows (WK_*) x 4 wheels holding the wheel-frame slips wk[WK_SX], wk[WK_VR] and the
    steer rotation (wk[WK_CS], wk[WK_SN]) from wheel to body frame; surface of wheel i is
    surfs[sidx[i, col]]; geo: GEO_* rows x 4 wheels. Writes wk[WK_FZ], the wheel-frame
    longitudinal force wk[WK_FXW] and the body-frame forces wk[WK_FXB], wk[WK_FYB]; returns
    (ax, ay, iterations). Without lateral slip and steering the loop is linear:
    ax = -sum c_i Fz0_i / (m + sum c_i A_i) with Fx_i = -c_i Fz_i (iterations 0); otherwise
    Newton's method on (ax, ay) from (ax0, ay0) (the previous evaluation's values), always with
    the Magic Formula tire (a road's surfaces are both of one tire).
    """
    straight = surfs[0, SF_MF] == 0.0  # the Magic Formula's force is not linear in the load
    for i in range(4):
        if wk[WK_VR, i] != 0.0 or wk[WK_SN, i] != 0.0:
            straight = False
    if straight:
        num = 0.0
        den = mass
        for i in range(4):
            c = straight_force_per_load(wk[WK_SX, i], surfs, sidx[i, col])
            wk[WK_FXW, i] = c  # the force is c Fz exactly (tire_force without lateral slip)
            num += c * geo[GEO_FZ0, i]
            den -= c * geo[GEO_A, i]
        ax = num / den
        ok = True
        for i in range(4):
            z = geo[GEO_FZ0, i] + geo[GEO_A, i] * ax
            ok = ok and z >= 0.0
            wk[WK_FZ, i] = z
        if ok:
            total = 0.0
            for i in range(4):
                fx = wk[WK_FXW, i] * wk[WK_FZ, i]
                wk[WK_FXW, i] = fx
                wk[WK_FXB, i] = fx
                wk[WK_FYB, i] = 0.0
                total += fx
            return total / mass, 0.0, 0
    ax = ax0
    ay = ay0
    it = 0
    while True:
        sfx = 0.0
        sfy = 0.0
        j11 = 0.0
        j12 = 0.0
        j21 = 0.0
        j22 = 0.0
        for i in range(4):
            z = max(geo[GEO_FZ0, i] + geo[GEO_A, i] * ax + geo[GEO_B, i] * ay, 0.0)
            wk[WK_FZ, i] = z
            fx, fy, dfx, dfy = tire_force(
                wk[WK_SX, i], wk[WK_VR, i], z, surfs, sidx[i, col], i % 2 == 1
            )
            cs = wk[WK_CS, i]
            sn = wk[WK_SN, i]
            bx = cs * fx - sn * fy
            by = sn * fx + cs * fy
            dbx = cs * dfx - sn * dfy
            dby = sn * dfx + cs * dfy
            wk[WK_FXW, i] = fx
            wk[WK_FXB, i] = bx
            wk[WK_FYB, i] = by
            sfx += bx
            sfy += by
            j11 += dbx * geo[GEO_A, i]
            j12 += dbx * geo[GEO_B, i]
            j21 += dby * geo[GEO_A, i]
            j22 += dby * geo[GEO_B, i]
        r1 = sfx / mass - ax
        r2 = sfy / mass - ay
        if abs(r1) + abs(r2) <= LOAD_TOL_M_S2 or it >= MAX_LOAD_ITERATIONS:
            return sfx / mass, sfy / mass, it
        a11 = j11 / mass - 1.0
        a12 = j12 / mass
        a21 = j21 / mass
        a22 = j22 / mass - 1.0
        det = a11 * a22 - a12 * a21
        if it < MAX_LOAD_ITERATIONS // 2 and det != 0.0:
            ax += (-r1 * a22 + r2 * a12) / det
            ay += (-r2 * a11 + r1 * a21) / det
        else:  # Newton stalled at a kink: fixed-point steps (a contraction, about mu h / L)
            ax += r1
            ay += r2
        it += 1


def geometry(pp: VehicleParams) -> np.ndarray:
    """The GEO_* rows x 4 wheels: positions and the load coefficients."""
    geo = np.zeros((N_GEO, 4))
    geo[GEO_X], geo[GEO_Y] = wheel_positions(pp)
    geo[GEO_FZ0], geo[GEO_A], geo[GEO_B] = load_coefficients(pp)
    return geo


# ------------------------------------------------------------------------------------------------
# exact bounds (design.md 3.3): v_stop included everywhere


@dataclass(frozen=True)
class Bound:
    """Shortest stop any controller can reach on a road from v0 down to v_stop."""

    distance_m: float
    time_s: float


def uniform_bound(pp: VehicleParams, mu_peak: float) -> Bound:
    """(v0^2 - v_stop^2)/(2 mu_peak g) at the constant deceleration mu_peak g."""
    a = mu_peak * pp.g_m_s2
    return Bound((pp.v0_m_s**2 - pp.v_stop_m_s**2) / (2 * a), (pp.v0_m_s - pp.v_stop_m_s) / a)


def split_mu_bound(pp: VehicleParams, mu_left: float, mu_right: float) -> Bound:
    """(v0^2 - v_stop^2)/((mu_L + mu_R) g): each side at its own peak, equal side loads."""
    return uniform_bound(pp, 0.5 * (mu_left + mu_right))


def axle_limited_deceleration(pp: VehicleParams, mu_front: float, mu_rear: float) -> float:
    """Largest deceleration with the axles at their peaks on different surfaces:
    a = g (mu_f lr + mu_r lf) / (L - h (mu_f - mu_r)) (the load transfer feeds back)."""
    return (
        pp.g_m_s2
        * (mu_front * pp.cg_to_rear_m + mu_rear * pp.cg_to_front_m)
        / (pp.wheelbase_m - pp.cg_height_m * (mu_front - mu_rear))
    )


def mu_jump_bound(pp: VehicleParams, mu_first: float, mu_second: float, x_jump_m: float) -> Bound:
    """Integrate v dv/dx = -a_max(x): mu_first g until the front axle reaches the jump (CG at
    x_jump_m, measured from the front axle's start), the axle-wise limit for the next L metres,
    then mu_second g."""
    g = pp.g_m_s2
    segments = (
        (x_jump_m, mu_first * g),
        (pp.wheelbase_m, axle_limited_deceleration(pp, mu_second, mu_first)),
        (math.inf, mu_second * g),
    )
    return phased_bound(pp, segments)


def phased_bound(pp: VehicleParams, segments: tuple[tuple[float, float], ...]) -> Bound:
    """Integrate v dv/dx = -a over consecutive segments (length in m, the largest deceleration a
    in m/s^2 on it), from v0 down to v_stop."""
    half_v2 = 0.5 * pp.v0_m_s**2
    end = 0.5 * pp.v_stop_m_s**2
    dist = 0.0
    time = 0.0
    for length, a in segments:
        drop = min(a * length, half_v2 - end)
        v_a = math.sqrt(2 * half_v2)
        half_v2 -= drop
        dist += drop / a
        time += (v_a - math.sqrt(2 * half_v2)) / a
        if half_v2 <= end:
            break
    return Bound(dist, time)


def wheel_mode_rate(pp: VehicleParams, rise_max: float, mu_peak_max: float) -> float:
    """Largest |eigenvalue| of the wheel-spin mode at v_stop: R^2 (mu_h/S_T) Fz / (J v)
    (design.md 3.3), Fz the heaviest wheel's load braking at mu_peak_max g in a straight line."""
    fz0, a, _b = load_coefficients(pp)
    fz_max = float(np.max(fz0 - a * mu_peak_max * pp.g_m_s2))
    return pp.wheel_radius_m**2 * rise_max * fz_max / (pp.wheel_inertia_kg_m2 * pp.v_stop_m_s)
