"""The wheel laws in the vehicle's lanes: a lane's start (the law's held values, `law_start`)
and a sampled law's tick at the lane's sample instants (`law_tick`, on the channel errors after
select-low), through the one dispatch generated from the registry
(`controllers.laws.dispatch`); `laws_key`, the registry's fingerprint, reaches them as a
literal argument."""

from __future__ import annotations

import numba
import numpy as np

from chassistune.controllers.laws.dispatch import law_start, law_tick
from chassistune.sim.abs_vehicle_lane import lane_get, target_slip
from chassistune.sim.abs_vehicle_layout import (
    KC_NF,
    KC_RW,
    KC_SELECT_LOW,
    KC_TTIMEOUT,
    LANES,
    N_ROWS,
    R_ALL_D,
    R_ALL_T,
    R_ALL_V,
    R_KD,
    R_KI,
    R_KP,
    R_LOCK_T,
    R_MEM,
    R_PSI1,
    R_SLIP,
    R_SPEED,
    R_SPIN_T,
    R_STATUS,
    R_SURF,
    R_TEND,
    R_U0,
    R_WS,
    R_Y1,
    S_VX,
    S_W,
    S_XF,
    STATUS_TIMEOUT,
)
from chassistune.sim.abs_vehicle_wheels import select_low, surface_flag


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def tick_wheel(st, l, i, k, j, src, e, gains, col0, laws_key, ctrl_kind, c, table, kc, srf, ts):
    """Wheel j's part of `tick`: the law's tick (`law_tick`) on its channel error e, with the
    signals of wheel src (itself, or under select-low the rear wheel whose error it took)."""
    sig = (
        e,
        lane_get(st, R_SLIP + src, l),
        target_slip(st, src, l, srf),
        lane_get(st, S_W + src, l),
        lane_get(st, R_WS + src, l),
        kc[KC_RW],
        kc[KC_NF] * (e - lane_get(st, S_XF + j, l)),
    )
    held = (
        lane_get(st, R_U0 + j, l),
        lane_get(st, R_KP + j, l),
        lane_get(st, R_KI + j, l),
        lane_get(st, R_KD + j, l),
    )
    mem = (lane_get(st, R_MEM + j, l), lane_get(st, R_MEM + 4 + j, l))
    (u0, kp, ki, kd), (m0, m1) = law_tick(
        laws_key, ctrl_kind, sig, held, mem, gains[i], col0[j], c, table, ts, k == 0
    )
    st[(R_U0 + j) * LANES + l] = u0
    st[(R_KP + j) * LANES + l] = kp
    st[(R_KI + j) * LANES + l] = ki
    st[(R_KD + j) * LANES + l] = kd
    st[(R_MEM + j) * LANES + l] = m0
    st[(R_MEM + 4 + j) * LANES + l] = m1


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def tick(st, l, i, k, gains, col0, laws_key, ctrl_kind, c, table, kc, srf, ts):
    """A sampled law's update of lane l (candidate i) at its step k, a sample instant (the law
    dispatch compiles for `laws_key`, a literal)."""
    sel = kc[KC_SELECT_LOW] != 0.0
    e0 = target_slip(st, 0, l, srf) - lane_get(st, R_SLIP, l)
    e1 = target_slip(st, 1, l, srf) - lane_get(st, R_SLIP + 1, l)
    e2, e3, low = select_low(
        target_slip(st, 2, l, srf) - lane_get(st, R_SLIP + 2, l),
        target_slip(st, 3, l, srf) - lane_get(st, R_SLIP + 3, l),
        sel,
    )
    rear = 3 if low else 2  # select-low: the rear wheel whose error it took
    tick_wheel(st, l, i, k, 0, 0, e0, gains, col0, laws_key, ctrl_kind, c, table, kc, srf, ts)
    tick_wheel(st, l, i, k, 1, 1, e1, gains, col0, laws_key, ctrl_kind, c, table, kc, srf, ts)
    src2, src3 = (rear, rear) if sel else (2, 3)
    tick_wheel(st, l, i, k, 2, src2, e2, gains, col0, laws_key, ctrl_kind, c, table, kc, srf, ts)
    tick_wheel(st, l, i, k, 3, src3, e3, gains, col0, laws_key, ctrl_kind, c, table, kc, srf, ts)
    for j in range(4):
        st[(R_WS + j) * LANES + l] = lane_get(st, S_W + j, l)


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def fill_lane(st, l, i, gains, col0, laws_key, ctrl_kind, c, kc, srf, v0):
    """Start candidate i in lane l: wheels rolling freely at v0, zero metrics, the law's held
    values at the start (`Law.forms`: the PID's gains, the driver's command without ABS), the
    surfaces under the wheels at t = 0 and the derivative filters at e(0) (no kick; the law
    dispatch compiles for `laws_key`, a literal)."""
    for row in range(N_ROWS):
        st[row * LANES + l] = 0.0
    st[S_VX * LANES + l] = v0
    for j in range(4):
        st[(S_W + j) * LANES + l] = v0 / kc[KC_RW]
        st[(R_WS + j) * LANES + l] = v0 / kc[KC_RW]
        st[(R_LOCK_T + j) * LANES + l] = np.nan
        u0, kp, ki, kd = law_start(laws_key, ctrl_kind, gains[i], col0[j], c)
        st[(R_U0 + j) * LANES + l] = u0
        st[(R_KP + j) * LANES + l] = kp
        st[(R_KI + j) * LANES + l] = ki
        st[(R_KD + j) * LANES + l] = kd
        st[(R_SURF + j) * LANES + l] = surface_flag(0.0, 0.0, 0.0, 1.0, 0.0, j, kc)
    # e(0): the wheels roll freely
    e2, e3, _ = select_low(
        target_slip(st, 2, l, srf), target_slip(st, 3, l, srf), kc[KC_SELECT_LOW] != 0.0
    )
    st[S_XF * LANES + l] = target_slip(st, 0, l, srf)
    st[(S_XF + 1) * LANES + l] = target_slip(st, 1, l, srf)
    st[(S_XF + 2) * LANES + l] = e2
    st[(S_XF + 3) * LANES + l] = e3
    st[R_SPEED * LANES + l] = v0
    for row in (R_ALL_T, R_ALL_V, R_ALL_D, R_PSI1, R_Y1, R_SPIN_T):
        st[row * LANES + l] = np.nan
    st[R_STATUS * LANES + l] = STATUS_TIMEOUT
    st[R_TEND * LANES + l] = kc[KC_TTIMEOUT]
