"""The wheel laws in the vehicle's lanes: a lane's start (the law's held values, `law_start`)
and a sampled law's ticks of the lane's four wheels at its sample instants (on the channel
errors after select-low: one call of the law's own function, its tick inlined, per lane;
`controllers.laws.dispatch.tick_pass`), through the one dispatch generated from the registry;
`laws_key`, the registry's fingerprint, reaches them as a literal argument."""

from __future__ import annotations

import functools
from typing import Any

import numba
import numpy as np

from chassistune._branchfree import select
from chassistune._rows import read_rows, write_rows
from chassistune.controllers.laws.dispatch import law_initial_state, law_start, tick_pass
from chassistune.sim.abs_vehicle_lane import NO_REFCOUNT, lane_get, target_slip
from chassistune.sim.abs_vehicle_layout import (
    KC_DT,
    KC_GCOL,
    KC_NF,
    KC_QMAX,
    KC_RW,
    KC_SELECT_LOW,
    KC_TCOL,
    KC_TTIMEOUT,
    LANES,
    MEMORY,
    N_ROWS,
    R_ALL_D,
    R_ALL_T,
    R_ALL_V,
    R_GMA,
    R_KD,
    R_KI,
    R_KP,
    R_LOCK_T,
    R_MEM,
    R_PSI1,
    R_QS,
    R_SLIP,
    R_SPEED,
    R_SPIN_T,
    R_STATUS,
    R_SURF,
    R_TEND,
    R_TGT,
    R_U0,
    R_WS,
    R_Y1,
    S_Q,
    S_VX,
    S_W,
    S_XF,
    S_Z,
    STATUS_TIMEOUT,
)
from chassistune.sim.abs_vehicle_wheels import select_low, surface_flag
from chassistune.sim.inlined import inlined

_MEMORY_ZEROS = (0.0,) * MEMORY


@inlined
def _wheel_inputs(st, l, j, src, e, kc, t):
    """What the law's tick at time t reads for wheel j of lane l on its channel error e: the
    signals of wheel src (itself, or under select-low the rear wheel whose error it took; the
    reference speed is the CG's), wheel j's held values, pressures and memory."""
    sig = (
        e,
        lane_get(st, R_SLIP + src, l),
        target_slip(st, src, l),
        lane_get(st, S_W + src, l),
        lane_get(st, R_WS + src, l),
        kc[KC_RW],
        kc[KC_NF] * (e - lane_get(st, S_XF + j, l)),
        lane_get(st, R_SPEED, l),
        lane_get(st, S_Q + j, l),
        lane_get(st, R_QS + j, l),
        t,
    )
    held = (
        lane_get(st, R_U0 + j, l),
        lane_get(st, R_KP + j, l),
        lane_get(st, R_KI + j, l),
        lane_get(st, R_KD + j, l),
    )
    mem = read_rows(st, (R_MEM + j) * LANES + l, 4 * LANES, _MEMORY_ZEROS)
    return sig, held, mem


@inlined
def _wheel_store(st, l, j, held, mem):
    """Wheel j of lane l after the law's tick: its held values and memory (the slots its tick
    returns)."""
    st[(R_U0 + j) * LANES + l], st[(R_KP + j) * LANES + l] = held[0], held[1]
    st[(R_KI + j) * LANES + l], st[(R_KD + j) * LANES + l] = held[2], held[3]
    write_rows(st, (R_MEM + j) * LANES + l, 4 * LANES, mem)


@functools.cache
def _wheel_ticks_of(law_tick: Any) -> Any:
    """The four wheels' ticks of lane l of the sampled law whose tick is `law_tick` (inlined:
    numba inlines a closure's function), compiled as a function of its own once per entry point
    compilation (not cached: the entry point's cache holds it): wheel j on its channel error
    errors[j] with the signals of wheel sources[j], in wheel order."""

    def wheel_ticks(st, l, i, k, errors, sources, gains, col0, c, table, kc, ts):
        for j in range(4):
            sig, held, mem = _wheel_inputs(st, l, j, sources[j], errors[j], kc, k * kc[KC_DT])
            held, mem = law_tick(sig, held, mem, gains[i], col0[j], c, table, ts, k == 0)
            _wheel_store(st, l, j, held, mem)

    wheel_ticks.__qualname__ = f"wheel_ticks_{law_tick.py_func.__module__.rsplit('.', 1)[-1]}"
    return numba.njit(**{**NO_REFCOUNT, "cache": False})(wheel_ticks)


_wheel_ticks = tick_pass(_wheel_ticks_of)
"""The sampled law's ticks of a lane's four wheels (`_wheel_ticks_of`), by kind (in compiled
code)."""


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def tick(st, l, i, k, gains, col0, laws_key, ctrl_kind, c, table, kc, ts):
    """A sampled law's update of lane l (candidate i) at its step k, a sample instant, on the
    channel errors after select-low (the law dispatch compiles for `laws_key`, a literal)."""
    sel = kc[KC_SELECT_LOW] != 0.0
    e0 = target_slip(st, 0, l) - lane_get(st, R_SLIP, l)
    e1 = target_slip(st, 1, l) - lane_get(st, R_SLIP + 1, l)
    e2, e3, low = select_low(
        target_slip(st, 2, l) - lane_get(st, R_SLIP + 2, l),
        target_slip(st, 3, l) - lane_get(st, R_SLIP + 3, l),
        sel,
    )
    rear = 3 if low else 2  # select-low: the rear wheel whose error it took
    sources = (0, 1, rear, rear) if sel else (0, 1, 2, 3)
    args = (st, l, i, k, (e0, e1, e2, e3), sources, gains, col0, c, table, kc, ts)
    _wheel_ticks(laws_key, ctrl_kind, args)
    for j in range(4):
        st[(R_WS + j) * LANES + l] = lane_get(st, S_W + j, l)
        st[(R_QS + j) * LANES + l] = lane_get(st, S_Q + j, l)


@numba.njit(**NO_REFCOUNT)
def fill_lane(st, l, i, gains, col0, laws_key, ctrl_kind, c, kc, srf, v0):
    """Start candidate i in lane l: wheels rolling freely at v0, zero metrics, the law's held
    values at the start (`Law.forms`: the PID's gains, the driver's command without ABS), the
    surfaces under the wheels at t = 0 and the law's continuous state at e(0)
    (`law_initial_state`: the PID's derivative filters there, no kick; the law dispatch compiles
    for `laws_key`, a literal)."""
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
    col = int(kc[KC_TCOL])  # a fixed target's gain column, or -1: each surface's own
    fixed_target = gains[i, max(col, 0)]
    st[R_TGT * LANES + l] = select(col >= 0, fixed_target, srf[4])
    st[(R_TGT + 1) * LANES + l] = select(col >= 0, fixed_target, srf[10])
    gma = int(kc[KC_GCOL])  # the yaw-moment build-up rate's gain column, or -1: no delay
    st[R_GMA * LANES + l] = select(gma >= 0, gains[i, max(gma, 0)] * kc[KC_QMAX], -1.0)
    # e(0): the wheels roll freely
    e2, e3, _ = select_low(target_slip(st, 2, l), target_slip(st, 3, l), kc[KC_SELECT_LOW] != 0.0)
    errors = (target_slip(st, 0, l), target_slip(st, 1, l), e2, e3)
    for j in range(4):
        x0 = law_initial_state(laws_key, ctrl_kind, errors[j])
        st[(S_Z + j) * LANES + l], st[(S_XF + j) * LANES + l] = x0[0], x0[1]
    st[R_SPEED * LANES + l] = v0
    for row in (R_ALL_T, R_ALL_V, R_ALL_D, R_PSI1, R_Y1, R_SPIN_T):
        st[row * LANES + l] = np.nan
    st[R_STATUS * LANES + l] = STATUS_TIMEOUT
    st[R_TEND * LANES + l] = kc[KC_TTIMEOUT]
