"""The vehicle's general path (design.md 3.3): the right-hand side with the loads by Newton's
method (`plants.abs_vehicle.solve_loads`), for yaw, lateral velocity, steering or an unloaded
wheel, and the step of one lane stage by stage (straight-line stages where they hold, so that a
lane's numbers do not depend on the path); and a trace row, re-evaluated at the lane's state."""

from __future__ import annotations

import math

import numba

from chassistune.plants.abs_vehicle import SF_TARGET, solve_loads
from chassistune.sim.abs_vehicle_lane import (
    NO_REFCOUNT,
    lane_arrays,
    lane_get,
    laws_surfaces,
    state_of,
)
from chassistune.sim.abs_vehicle_layout import (
    G_X,
    G_Y,
    KC_DT,
    KC_H6,
    KC_HS,
    KC_QMAX,
    LANES,
    LAW_KD,
    LAW_KI,
    LAW_KP,
    LAW_U0,
    N_STATE,
    P_DMAX,
    P_DRIVER,
    P_FRONT_SHARE,
    P_K,
    P_KPSI,
    P_KQ,
    P_KR,
    P_MASS,
    P_NF,
    P_QMAX,
    P_R,
    P_SELECT_LOW,
    R_AX,
    R_AY,
    R_DIST,
    R_ITER,
    R_K4,
    R_SLIP,
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
    T_AX,
    T_AY,
    T_DELTA,
    T_DIST,
    T_FX,
    T_FZ,
    T_PSI,
    T_SLIP,
    T_SPEED,
    T_SURF,
    T_TARGET,
    T_TB,
    T_TIME,
    T_VX,
    T_VY,
    T_WV,
    T_X,
    T_Y,
    T_YR,
    W_E,
    W_FXB,
    W_FXW,
    W_FYB,
    W_FZ,
    W_SLIP,
    W_VABS,
)
from chassistune.sim.abs_vehicle_step_end import end_step
from chassistune.sim.abs_vehicle_straight import straight_stage
from chassistune.sim.abs_vehicle_wheels import (
    kinematics,
    select_low,
    wheel_brake_gain,
    wheel_pid_rates,
    wheel_speeds,
)
from chassistune.sim.integrate import rk4_point, rk4_update


@numba.njit(**NO_REFCOUNT)
def rhs(y, dy, i, law, sidx, guess, p, geo, surfs, sc, wbuf, tgt, inv):
    """Derivatives of candidate i's state `y` into dy[:, i]; returns the load-solve iterations.

    guess[:, i] holds the last (ax, ay) of the candidate (start of the load iteration), updated;
    inv = (1/Iz, 1/J, 1/T, 1/tau_steer).
    """
    vx = y[S_VX]
    vy = y[S_VY]
    r = y[S_YR]
    psi = y[S_PSI]
    delta = y[S_DELTA]
    for j in range(4):
        wbuf[j] = y[S_W + j]
    kinematics(vx, vy, r, delta, wbuf, p, geo, sc)
    for j in range(4):
        tgt[j] = surfs[sidx[j, i], SF_TARGET]
    ax, ay, it = solve_loads(sc, surfs, sidx, i, geo, p[P_MASS], guess[0, i], guess[1, i])
    guess[0, i] = ax
    guess[1, i] = ay
    mz = 0.0
    for j in range(4):
        mz += geo[G_X, j] * sc[W_FYB, j] - geo[G_Y, j] * sc[W_FXB, j]
    dy[S_VX, i] = ax + vy * r
    dy[S_VY, i] = ay - vx * r
    dy[S_YR, i] = mz * inv[0]
    if psi != 0.0:
        cp = math.cos(psi)
        sp = math.sin(psi)
        dy[S_X, i] = vx * cp - vy * sp
        dy[S_Y, i] = vx * sp + vy * cp
    else:
        dy[S_X, i] = vx
        dy[S_Y, i] = vy
    dy[S_PSI, i] = r
    if p[P_DRIVER] != 0.0:
        cmd = min(max(-p[P_KPSI] * psi - p[P_KR] * r, -p[P_DMAX]), p[P_DMAX])
        dy[S_DELTA, i] = (cmd - delta) * inv[3]
    else:
        dy[S_DELTA, i] = 0.0
    for j in range(4):
        sc[W_E, j] = tgt[j] - sc[W_SLIP, j]
    sc[W_E, 2], sc[W_E, 3], _ = select_low(sc[W_E, 2], sc[W_E, 3], p[P_SELECT_LOW] != 0.0)
    for j in range(4):
        dw, dq, dqr, dz, dxf = wheel_pid_rates(
            y[S_W + j],
            y[S_Q + j],
            y[S_QR + j],
            y[S_Z + j],
            y[S_XF + j],
            sc[W_E, j],
            sc[W_FXW, j],
            law[LAW_KP, j, i],
            law[LAW_KI, j, i],
            law[LAW_KD, j, i],
            law[LAW_U0, j, i],
            p[P_R],
            wheel_brake_gain(p[P_KQ], p[P_FRONT_SHARE], j),
            inv[1],
            p[P_NF],
            p[P_K],
            inv[2],
            p[P_QMAX],
        )
        dy[S_W + j, i] = dw
        dy[S_Q + j, i] = dq
        dy[S_QR + j, i] = dqr
        dy[S_Z + j, i] = dz
        dy[S_XF + j, i] = dxf
    return it


@numba.njit(**NO_REFCOUNT)
def general_step(st, l, kc, srf, p, geo, surfs, x, ks, y, dy, law, sidx, guess, sc, wbuf, tgt, inv):
    """The step of lane l stage by stage: each stage in the straight-line case where it holds,
    else the general right-hand side `rhs` (loads by Newton's method from the lane's last
    general solution). Returns whether the run ended."""
    for s in range(N_STATE):
        x[s] = lane_get(st, s, l)
        ks[3, s] = lane_get(st, R_K4 + s, l)  # stage 1 reads the last step's k4
    lane_arrays(st, l, law, sidx, guess)
    g, srfs = laws_surfaces(st, l, srf)
    iters = lane_get(st, R_ITER, l)
    for stage in range(4):
        c = 0.0 if stage == 0 else (kc[KC_DT] if stage == 3 else kc[KC_HS])
        prev = 3 if stage == 0 else stage - 1
        for s in range(N_STATE):
            y[s] = rk4_point(x[s], c, ks[prev, s])
        (kb, k0, k1, k2, k3), ok = straight_stage(state_of(y, 0, 1, 0), g, srfs, kc)
        if ok:
            for s in range(7):
                ks[stage, s] = kb[s]
            for j, kw in enumerate((k0, k1, k2, k3)):
                ks[stage, S_W + j] = kw[0]
                ks[stage, S_Q + j] = kw[1]
                ks[stage, S_QR + j] = kw[2]
                ks[stage, S_Z + j] = kw[3]
                ks[stage, S_XF + j] = kw[4]
        else:
            it = rhs(y, dy, 0, law, sidx, guess, p, geo, surfs, sc, wbuf, tgt, inv)
            iters = max(iters, it)
            for s in range(N_STATE):
                ks[stage, s] = dy[s, 0]
    h6 = kc[KC_H6]
    for s in range(N_STATE):
        y[s] = rk4_update(x[s], h6, ks[0, s], ks[1, s], ks[2, s], ks[3, s])
    for j in range(4):
        y[S_W + j] = max(y[S_W + j], 0.0)
        y[S_Q + j] = min(max(y[S_Q + j], 0.0), kc[KC_QMAX])
        wbuf[j] = y[S_W + j]
    kinematics(y[S_VX], y[S_VY], y[S_YR], y[S_DELTA], wbuf, p, geo, sc)
    psi = y[S_PSI]
    cp = math.cos(psi) if psi != 0.0 else 1.0
    sp = math.sin(psi) if psi != 0.0 else 0.0
    x0 = state_of(x, 0, 1, 0)
    ended = end_step(
        st,
        l,
        True,
        x0,
        wheel_speeds(x0, kc),
        state_of(y, 0, 1, 0),
        (sc[W_SLIP, 0], sc[W_SLIP, 1], sc[W_SLIP, 2], sc[W_SLIP, 3]),
        (sc[W_VABS, 0], sc[W_VABS, 1], sc[W_VABS, 2], sc[W_VABS, 3]),
        cp,
        sp,
        state_of(ks[3], 0, 1, 0),
        kc,
        srf,
        True,
    )
    st[R_AX * LANES + l] = guess[0, 0]
    st[R_AY * LANES + l] = guess[1, 0]
    st[R_ITER * LANES + l] = iters
    return ended


@numba.njit(**NO_REFCOUNT)
def trace_row(
    trace_row, start, t, st, l, p, geo, surfs, law, sidx, guess, sc, y, dy, wbuf, tgt, inv
):
    """Trace row `trace_row` of lane l: its state, and loads and forces re-evaluated at it (`rhs`
    on scratch copies of the lane's arrays: tracing does not change the run); the start row
    (`start`) takes the slips of that evaluation."""
    for s in range(N_STATE):
        y[s] = lane_get(st, s, l)
    lane_arrays(st, l, law, sidx, guess)
    rhs(y, dy, 0, law, sidx, guess, p, geo, surfs, sc, wbuf, tgt, inv)
    trace_row[T_TIME] = t
    trace_row[T_VX] = y[S_VX]
    trace_row[T_VY] = y[S_VY]
    trace_row[T_SPEED] = math.sqrt(y[S_VX] ** 2 + y[S_VY] ** 2)
    trace_row[T_YR] = y[S_YR]
    trace_row[T_PSI] = y[S_PSI]
    trace_row[T_X] = y[S_X]
    trace_row[T_Y] = y[S_Y]
    trace_row[T_DELTA] = y[S_DELTA]
    trace_row[T_AX] = guess[0, 0]
    trace_row[T_AY] = guess[1, 0]
    trace_row[T_DIST] = lane_get(st, R_DIST, l)
    for j in range(4):
        trace_row[T_WV + j] = y[S_W + j] * p[P_R]
        trace_row[T_SLIP + j] = lane_get(st, R_SLIP + j, l) if not start else sc[W_SLIP, j]
        trace_row[T_TARGET + j] = surfs[sidx[j, 0], SF_TARGET]
        trace_row[T_FZ + j] = sc[W_FZ, j]
        trace_row[T_TB + j] = wheel_brake_gain(p[P_KQ], p[P_FRONT_SHARE], j) * y[S_Q + j]
        trace_row[T_FX + j] = sc[W_FXW, j]
        trace_row[T_SURF + j] = sidx[j, 0]
