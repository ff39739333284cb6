"""A lane's rows of the vehicle kernel (`sim.abs_vehicle_kernel`) as the stages read and write
them: row r of lane l at st[r * LANES + l] (`abs_vehicle_layout.LANE_LAYOUT`), the state as
tuples (body, wheel fl, fr, rl, rr), the wheel laws and the surfaces under the wheels; and the
kernel's constants, one tuple (`abs_vehicle_layout.CONSTANTS_LAYOUT`)."""

from __future__ import annotations

import math
from typing import Any

import numba
from numba.extending import register_jitable

from chassistune._branchfree import select
from chassistune.plants.abs_vehicle import (
    SF_COEF,
    SF_FALL0,
    SF_FALL1,
    SF_LAT,
    SF_MF,
    SF_RISE,
    SF_ST,
    SF_TARGET,
)
from chassistune.plants.vehicle_mf import wheel_forces, wheel_forces_and_derivative
from chassistune.sim.abs_vehicle_layout import (
    G_A,
    G_B,
    G_FZ0,
    G_X,
    G_Y,
    KC_DT,
    LANES,
    P_DMAX,
    P_DRIVER,
    P_DT,
    P_FRONT_SHARE,
    P_GCOL,
    P_HOPELESS,
    P_IZ,
    P_J,
    P_K,
    P_KPSI,
    P_KQ,
    P_KR,
    P_LOCK,
    P_MASS,
    P_NF,
    P_QMAX,
    P_R,
    P_ROAD,
    P_SELECT_LOW,
    P_SIGMA_X,
    P_SIGMA_Y,
    P_SPLIT_ROAD,
    P_STAU,
    P_TAU,
    P_TCOL,
    P_TMAX,
    P_VMIN,
    P_VSTOP,
    P_WINDOW,
    P_XJUMP,
    P_YSPLIT,
    R_AX,
    R_AY,
    R_GMA,
    R_KD,
    R_KI,
    R_KP,
    R_STEP,
    R_SURF,
    R_TGT,
    R_U0,
    S_DELTA,
    S_PSI,
    S_Q,
    S_QR,
    S_VX,
    S_VY,
    S_W,
    S_X,
    S_XF,
    S_Y,
    S_YR,
    S_Z,
)
from chassistune.sim.abs_vehicle_wheels import wheel_brake_gain
from chassistune.sim.inlined import INDEXING, INLINE, inlined

NO_REFCOUNT: dict[str, Any] = {
    "cache": True,
    "nogil": True,
    "error_model": "numpy",
    "_nrt": False,
}
"""Options of the vehicle kernel's entry point and its scalar passes (the functions not inlined):
compiled without numba's runtime, hence no reference counting (`_nrt` is not in numba's type
stubs)."""


@numba.njit(**INLINE)
def constants(p, geo):
    """The constants tuple (KC_* entries) of a plant vector and geometry."""
    dt = p[P_DT]
    n_steps = math.ceil(p[P_TMAX] / dt - 1e-9)
    return (
        p[P_MASS],
        geo[G_FZ0, 0],
        geo[G_FZ0, 1],
        geo[G_FZ0, 2],
        geo[G_FZ0, 3],
        geo[G_A, 0],
        geo[G_A, 1],
        geo[G_A, 2],
        geo[G_A, 3],
        geo[G_B, 0],
        geo[G_B, 1],
        geo[G_B, 2],
        geo[G_B, 3],
        geo[G_X, 0],
        geo[G_X, 1],
        geo[G_X, 2],
        geo[G_X, 3],
        geo[G_Y, 0],
        geo[G_Y, 1],
        geo[G_Y, 2],
        geo[G_Y, 3],
        p[P_R],
        p[P_VMIN],
        wheel_brake_gain(p[P_KQ], p[P_FRONT_SHARE], 0),
        wheel_brake_gain(p[P_KQ], p[P_FRONT_SHARE], 1),
        wheel_brake_gain(p[P_KQ], p[P_FRONT_SHARE], 2),
        wheel_brake_gain(p[P_KQ], p[P_FRONT_SHARE], 3),
        p[P_NF],
        p[P_K],
        p[P_QMAX],
        p[P_KPSI],
        p[P_KR],
        p[P_DMAX],
        1.0 / p[P_IZ],
        1.0 / p[P_J],
        1.0 / p[P_TAU],
        1.0 / p[P_STAU],
        p[P_DRIVER],
        p[P_SELECT_LOW],
        p[P_ROAD],
        p[P_XJUMP],
        p[P_SPLIT_ROAD],
        p[P_YSPLIT],
        p[P_VSTOP],
        p[P_LOCK],
        p[P_HOPELESS],
        p[P_WINDOW],
        dt,
        0.5 * dt,
        dt / 6.0,
        float(n_steps),
        n_steps * dt,
        p[P_TCOL],
        p[P_GCOL],
        p[P_SIGMA_X],
        p[P_SIGMA_X + 1],
        p[P_SIGMA_X + 2],
        p[P_SIGMA_X + 3],
        p[P_SIGMA_Y],
        p[P_SIGMA_Y + 1],
        p[P_SIGMA_Y + 2],
        p[P_SIGMA_Y + 3],
    )


@numba.njit(**INLINE)
def surfaces(surfs):
    """The road's two surfaces as the lanes read them (`surface_of`): (S_T, rise, fall0,
    fall1, target, lateral scale C S_T / mu_h) of surface 0, then of surface 1; then (at
    SURFACE_ROWS) the surface rows themselves, where the Magic Formula tire reads its
    coefficients (`magic_formula_forces`)."""
    return (
        surfs[0, SF_ST],
        surfs[0, SF_RISE],
        surfs[0, SF_FALL0],
        surfs[0, SF_FALL1],
        surfs[0, SF_TARGET],
        surfs[0, SF_LAT],
        surfs[1, SF_ST],
        surfs[1, SF_RISE],
        surfs[1, SF_FALL0],
        surfs[1, SF_FALL1],
        surfs[1, SF_TARGET],
        surfs[1, SF_LAT],
        surfs,
    )


SURFACE_ROWS = 12
"""Where `surfaces` puts the surface rows."""


@inlined
def magic_formula(srf):
    """Whether the road's surfaces are of the Magic Formula tire (`plants.vehicle_mf`)."""
    return srf[SURFACE_ROWS][0, SF_MF] != 0.0


@inlined
def magic_formula_forces(srf, b, j, sx, vr, fz, derivative):
    """`vehicle_mf.wheel_forces_and_derivative` of wheel j on the surface it is on (b: 1.0 the
    second), with the coefficients of that surface's row, mirrored on the right wheels; without
    `derivative` its forces only (`wheel_forces`) and zero derivatives."""
    c = srf[SURFACE_ROWS][1 if b != 0.0 else 0, SF_COEF:]
    if derivative:
        return wheel_forces_and_derivative(sx, vr, fz, c, j % 2 == 1)
    fx, fy = wheel_forces(sx, vr, fz, c, j % 2 == 1)
    return fx, fy, 0.0, 0.0


@register_jitable
def lane_get(st, row, l):
    """Row `row` of lane l. A call, not inlined at numba's IR level: LLVM inlines it, and
    numba types it once per argument types (a constant row is not a literal of its own), where
    inlining it at every one of its hundreds of call sites is most of the passes' compile time."""
    return st[row * LANES + l]


@register_jitable
def lane_put(st, row, l, commit, value):
    """Row `row` of lane l becomes `value` where `commit` (else it keeps its value); a call
    as `lane_get`."""
    st[row * LANES + l] = select(commit, value, st[row * LANES + l])


@numba.njit(**INDEXING)
def state_of(a, row0, stride, l):
    """The state as tuples (body, wheel fl, fr, rl, rr), state row s at a[(row0 + s) stride + l]:
    the rows of lane l in `st` (stride LANES) or a state vector (stride 1, l = 0)."""
    return (
        (
            a[(row0 + S_VX) * stride + l],
            a[(row0 + S_VY) * stride + l],
            a[(row0 + S_YR) * stride + l],
            a[(row0 + S_X) * stride + l],
            a[(row0 + S_Y) * stride + l],
            a[(row0 + S_PSI) * stride + l],
            a[(row0 + S_DELTA) * stride + l],
        ),
        wheel_of(a, row0, stride, 0, l),
        wheel_of(a, row0, stride, 1, l),
        wheel_of(a, row0, stride, 2, l),
        wheel_of(a, row0, stride, 3, l),
    )


@numba.njit(**INDEXING)
def wheel_of(a, row0, stride, j, l):
    """Wheel j's (w, q, qr, z, xf) in the rows of `state_of`."""
    return (
        a[(row0 + S_W + j) * stride + l],
        a[(row0 + S_Q + j) * stride + l],
        a[(row0 + S_QR + j) * stride + l],
        a[(row0 + S_Z + j) * stride + l],
        a[(row0 + S_XF + j) * stride + l],
    )


@numba.njit(**INDEXING)
def law_of(st, j, l):
    return (
        lane_get(st, R_KP + j, l),
        lane_get(st, R_KI + j, l),
        lane_get(st, R_KD + j, l),
        lane_get(st, R_U0 + j, l),
    )


@numba.njit(**INDEXING)
def put_state(st, row0, l, commit, x):
    """`state_of` rows of lane l become x = (body, wheels) where `commit`."""
    b = x[0]
    lane_put(st, row0 + S_VX, l, commit, b[0])
    lane_put(st, row0 + S_VY, l, commit, b[1])
    lane_put(st, row0 + S_YR, l, commit, b[2])
    lane_put(st, row0 + S_X, l, commit, b[3])
    lane_put(st, row0 + S_Y, l, commit, b[4])
    lane_put(st, row0 + S_PSI, l, commit, b[5])
    lane_put(st, row0 + S_DELTA, l, commit, b[6])
    put_wheel(st, row0, 0, l, commit, x[1])
    put_wheel(st, row0, 1, l, commit, x[2])
    put_wheel(st, row0, 2, l, commit, x[3])
    put_wheel(st, row0, 3, l, commit, x[4])


@numba.njit(**INDEXING)
def put_wheel(st, row0, j, l, commit, w):
    lane_put(st, row0 + S_W + j, l, commit, w[0])
    lane_put(st, row0 + S_Q + j, l, commit, w[1])
    lane_put(st, row0 + S_QR + j, l, commit, w[2])
    lane_put(st, row0 + S_Z + j, l, commit, w[3])
    lane_put(st, row0 + S_XF + j, l, commit, w[4])


@inlined
def laws_surfaces(st, l, srf):
    """Lane l's wheel laws ((kp, ki, kd, u0) per wheel) and the surfaces under its wheels, with
    the lane's targets on them."""
    t0, t1 = lane_get(st, R_TGT, l), lane_get(st, R_TGT + 1, l)
    return (
        (law_of(st, 0, l), law_of(st, 1, l), law_of(st, 2, l), law_of(st, 3, l)),
        (
            surface_of(lane_get(st, R_SURF, l), srf, t0, t1),
            surface_of(lane_get(st, R_SURF + 1, l), srf, t0, t1),
            surface_of(lane_get(st, R_SURF + 2, l), srf, t0, t1),
            surface_of(lane_get(st, R_SURF + 3, l), srf, t0, t1),
        ),
    )


@inlined
def front_gap(st, l, kc):
    """The largest difference of the front pressures at the end of lane l's step under the
    yaw-moment build-up delay, r_gma q_max t (`controllers.yaw_moment_delay`); -1: no delay."""
    rate = lane_get(st, R_GMA, l)
    t_end = (lane_get(st, R_STEP, l) + 1.0) * kc[KC_DT]
    return select(rate >= 0.0, rate * t_end, -1.0)


@numba.njit(**INDEXING)
def target_slip(st, j, l):
    """The law's target slip on the surface under wheel j of lane l (`R_TGT`)."""
    two = lane_get(st, R_SURF + j, l) != 0.0
    return select(two, lane_get(st, R_TGT + 1, l), lane_get(st, R_TGT, l))


@inlined
def surface_of(b, srf, t0, t1):
    """(S_T, rise, fall0, fall1, target, lateral scale) of the surface a wheel is on (b: 1.0
    the second), the target the lane's on it (t0 on the first, t1 on the second)."""
    two = b != 0.0
    return (
        select(two, srf[6], srf[0]),
        select(two, srf[7], srf[1]),
        select(two, srf[8], srf[2]),
        select(two, srf[9], srf[3]),
        select(two, t1, t0),
        select(two, srf[11], srf[5]),
    )


@inlined
def lane_arrays(st, l, sidx, guess):
    """Lane l's surfaces and load guess as the arrays `plants.abs_vehicle.solve_loads` reads
    (column 0)."""
    for j in range(4):
        sidx[j, 0] = 1 if lane_get(st, R_SURF + j, l) != 0.0 else 0
    guess[0, 0] = lane_get(st, R_AX, l)
    guess[1, 0] = lane_get(st, R_AY, l)
