"""The vehicle's straight-line path: no yaw, lateral velocity, heading or steering, the loads in
closed form; one RK4 step of a lane in registers, branch-free, committed by select only where
every stage and the step's end were straight (the body of the vector loop, `lane_steps`)."""

from __future__ import annotations

import math

import numba

from chassistune._branchfree import clip, fmax, fmin, select
from chassistune.sim.abs_vehicle_lane import NO_REFCOUNT, front_gap, laws_surfaces, state_of
from chassistune.sim.abs_vehicle_layout import (
    KC_A,
    KC_DMAX,
    KC_DRIVER,
    KC_DT,
    KC_FZ0,
    KC_GAIN,
    KC_GX,
    KC_GY,
    KC_H6,
    KC_HS,
    KC_INV_IZ,
    KC_INV_J,
    KC_INV_ST,
    KC_INV_TAU,
    KC_KPSI,
    KC_KQ,
    KC_KR,
    KC_MASS,
    KC_NF,
    KC_QMAX,
    KC_RW,
    KC_SELECT_LOW,
    KC_VMIN,
    KC_VSTOP,
    LANES,
    R_DONE,
    R_K4,
    VECTOR,
)
from chassistune.sim.abs_vehicle_step_end import end_step
from chassistune.sim.abs_vehicle_wheels import (
    select_low,
    straight_wheel,
    unsteered,
    wheel_law_rates,
)
from chassistune.sim.inlined import INLINE, inlined
from chassistune.sim.integrate import rk4_point, rk4_update


@numba.njit(**INLINE)
def lane_wheel_rates(form, wt, e, fx, g, ctrl, kc, kq):
    """`wheel_law_rates` of wheel j's state wt = (w, q, qr, x0, x1), x the law's continuous
    state (`ContinuousForm.state`, padded), with held values g = (kp, ki, kd, u0), the law's
    continuous form of key `form`, the controller vector ctrl and brake torque per unit pressure
    kq."""
    dw, dq, dqr, dx = wheel_law_rates(
        form,
        wt[0],
        wt[1],
        wt[2],
        (wt[3], wt[4]),
        e,
        fx,
        (g[3], g[0], g[1], g[2]),
        ctrl,
        kc[KC_RW],
        kq,
        kc[KC_INV_J],
        kc[KC_NF],
        kc[KC_GAIN],
        kc[KC_INV_TAU],
        kc[KC_QMAX],
    )
    return dw, dq, dqr, dx[0], dx[1]


@inlined
def closed_loads(c, kc):
    """The load/force loop in closed form (`plants.abs_vehicle.solve_loads` without lateral
    slip or steering) with the wheels' forces per unit load c: ax = sum c_i Fz0_i /
    (m - sum c_i A_i), Fz_i = Fz0_i + A_i ax; returns (sum Fx_i / m, the forces Fx_i = c_i
    Fz_i, whether every load is >= 0)."""
    c0, c1, c2, c3 = c
    num = 0.0
    num += c0 * kc[KC_FZ0]
    num += c1 * kc[KC_FZ0 + 1]
    num += c2 * kc[KC_FZ0 + 2]
    num += c3 * kc[KC_FZ0 + 3]
    mass = kc[KC_MASS]
    den = mass
    den -= c0 * kc[KC_A]
    den -= c1 * kc[KC_A + 1]
    den -= c2 * kc[KC_A + 2]
    den -= c3 * kc[KC_A + 3]
    ax = num / den
    fz0 = kc[KC_FZ0] + kc[KC_A] * ax
    fz1 = kc[KC_FZ0 + 1] + kc[KC_A + 1] * ax
    fz2 = kc[KC_FZ0 + 2] + kc[KC_A + 2] * ax
    fz3 = kc[KC_FZ0 + 3] + kc[KC_A + 3] * ax
    ok = (fz0 >= 0.0) & (fz1 >= 0.0) & (fz2 >= 0.0) & (fz3 >= 0.0)
    fx0 = c0 * fz0
    fx1 = c1 * fz1
    fx2 = c2 * fz2
    fx3 = c3 * fz3
    total = 0.0
    total += fx0
    total += fx1
    total += fx2
    total += fx3
    return total / mass, (fx0, fx1, fx2, fx3), ok


@numba.njit(**INLINE)
def stage_rates(form, x, ax, ay, fxb, fyb, fxw, e, dxy, g, ctrl, kc):
    """Derivatives at state x = (b, w0, w1, w2, w3), body b = (vx, vy, r, X, Y, psi, delta),
    wheels wj = (w, q, qr, x0, x1), given the solved loads: CG accelerations (ax, ay), the
    body-frame forces fxb, fyb and wheel-frame Fx per wheel fxw, the wheels' slip errors e
    (before select-low), the position's rates dxy = (dX/dt, dY/dt), the laws' held values g and
    continuous form `form` with the controller vector ctrl: ((body rates), four wheel rates).
    The equations of `abs_vehicle_kernel` (design.md 3.3), shared by the straight and the
    general pass."""
    b, w0, w1, w2, w3 = x
    g0, g1, g2, g3 = g
    vx = b[0]
    vy = b[1]
    r = b[2]
    psi = b[5]
    delta = b[6]
    mz = 0.0
    mz += kc[KC_GX] * fyb[0] - kc[KC_GY] * fxb[0]
    mz += kc[KC_GX + 1] * fyb[1] - kc[KC_GY + 1] * fxb[1]
    mz += kc[KC_GX + 2] * fyb[2] - kc[KC_GY + 2] * fxb[2]
    mz += kc[KC_GX + 3] * fyb[3] - kc[KC_GY + 3] * fxb[3]
    dmax = kc[KC_DMAX]
    cmd = clip(-kc[KC_KPSI] * psi - kc[KC_KR] * r, -dmax, dmax)
    db = (
        ax + vy * r,
        ay - vx * r,
        mz * kc[KC_INV_IZ],
        dxy[0],
        dxy[1],
        r,
        select(kc[KC_DRIVER] != 0.0, (cmd - delta) * kc[KC_INV_ST], 0.0),
    )
    e2, e3, _ = select_low(e[2], e[3], kc[KC_SELECT_LOW] != 0.0)
    return (
        db,
        lane_wheel_rates(form, w0, e[0], fxw[0], g0, ctrl, kc, kc[KC_KQ]),
        lane_wheel_rates(form, w1, e[1], fxw[1], g1, ctrl, kc, kc[KC_KQ + 1]),
        lane_wheel_rates(form, w2, e2, fxw[2], g2, ctrl, kc, kc[KC_KQ + 2]),
        lane_wheel_rates(form, w3, e3, fxw[3], g3, ctrl, kc, kc[KC_KQ + 3]),
    )


@numba.njit(**INLINE)
def straight_stage(form, x, g, s, ctrl, kc):
    """Derivatives at state x (`stage_rates`) with laws g (form `form`, controller vector ctrl)
    and surfaces s (per wheel) in the
    straight-line case (no yaw, lateral velocity, heading or steering; loads in closed form,
    `closed_loads`): (rates, ok), ok false where the case does not hold (the general pass
    then applies). The same numbers as the general pass where it holds."""
    b, w0, w1, w2, w3 = x
    s0, s1, s2, s3 = s
    vx = b[0]
    r_w = kc[KC_RW]
    vmin = kc[KC_VMIN]
    c0, sl0 = straight_wheel(vx, w0[0], s0, r_w, vmin)
    c1, sl1 = straight_wheel(vx, w1[0], s1, r_w, vmin)
    c2, sl2 = straight_wheel(vx, w2[0], s2, r_w, vmin)
    c3, sl3 = straight_wheel(vx, w3[0], s3, r_w, vmin)
    ax, fx, loaded = closed_loads((c0, c1, c2, c3), kc)
    ok = (b[1] == 0.0) & (b[2] == 0.0) & (b[5] == 0.0) & (b[6] == 0.0) & loaded
    e = (s0[4] - sl0, s1[4] - sl1, s2[4] - sl2, s3[4] - sl3)
    zero = (0.0, 0.0, 0.0, 0.0)
    return stage_rates(form, x, ax, 0.0, fx, zero, fx, e, (vx, b[1]), g, ctrl, kc), ok


@inlined
def held(x, q_max, gap):
    """The state x after the step-end limits: each wheel's w held >= 0 and q in [0, q_max], the
    front pressures at most `gap` apart when gap >= 0 (`front_gap`)."""
    b, w0, w1, w2, w3 = x
    q0, q1 = clip(w0[1], 0.0, q_max), clip(w1[1], 0.0, q_max)
    on = gap >= 0.0
    return (
        b,
        (fmax(w0[0], 0.0), select(on, fmin(q0, q1 + gap), q0), w0[2], w0[3], w0[4]),
        (fmax(w1[0], 0.0), select(on, fmin(q1, q0 + gap), q1), w1[2], w1[3], w1[4]),
        (fmax(w2[0], 0.0), clip(w2[1], 0.0, q_max), w2[2], w2[3], w2[4]),
        (fmax(w3[0], 0.0), clip(w3[1], 0.0, q_max), w3[2], w3[3], w3[4]),
    )


@numba.njit(**INLINE)
def lane_step(form, st, l, kc, srf, ctrl, live):
    """One RK4 step of lane l in the straight-line case (the laws' continuous form of key `form`,
    controller vector ctrl), committed (R_DONE 1) only if every
    stage and the step's end are straight and the run does not stop in it (that step, once a
    run, is the scalar pass's: it locates the stop); returns 1 if a live lane ended.
    Straight-line code: the body of the vector loop."""
    x = state_of(st, 0, LANES, l)
    g, s = laws_surfaces(st, l, srf)
    hs = kc[KC_HS]
    dt = kc[KC_DT]
    ka, ok1 = straight_stage(form, rk4_point(x, 0.0, state_of(st, R_K4, LANES, l)), g, s, ctrl, kc)
    kb, ok2 = straight_stage(form, rk4_point(x, hs, ka), g, s, ctrl, kc)
    kc3, ok3 = straight_stage(form, rk4_point(x, hs, kb), g, s, ctrl, kc)
    kd, ok4 = straight_stage(form, rk4_point(x, dt, kc3), g, s, ctrl, kc)
    xn = held(rk4_update(x, kc[KC_H6], ka, kb, kc3, kd), kc[KC_QMAX], front_gap(st, l, kc))
    nb, n0, n1, n2, n3 = xn
    straight = (
        ok1 & ok2 & ok3 & ok4 & (nb[1] == 0.0) & (nb[2] == 0.0) & (nb[5] == 0.0) & (nb[6] == 0.0)
    )
    stopping = math.sqrt(nb[0] * nb[0] + nb[1] * nb[1]) <= kc[KC_VSTOP]
    commit = straight & (not stopping)
    # the step end's kinematics with delta = 0 (`kinematics`, unsteered)
    va0, sl0 = unsteered(nb, n0, 0, kc)
    va1, sl1 = unsteered(nb, n1, 1, kc)
    va2, sl2 = unsteered(nb, n2, 2, kc)
    va3, sl3 = unsteered(nb, n3, 3, kc)
    v0 = fmax(abs(x[0][0]), kc[KC_VMIN])  # every wheel's |V| at the straight start
    ended = end_step(
        st,
        l,
        commit,
        x,
        (v0, v0, v0, v0),
        xn,
        (sl0, sl1, sl2, sl3),
        (va0, va1, va2, va3),
        1.0,
        0.0,
        kd,
        kc,
        False,
    )
    st[R_DONE * LANES + l] = select(commit, 1.0, 0.0)
    return ended & commit & (l < live)


@numba.njit(**NO_REFCOUNT)
def lane_steps(form, args):
    """One step of lanes 0 .. width - 1 (a whole number of vectors), args = (st, width, kc, srf,
    ctrl, live), with the laws' continuous form of key `form` (a literal: compiled once per
    form); 1 if a live lane ended."""
    numba.literally(form)
    st, width, kc, srf, ctrl, live = args
    any_end = False
    for blk in range(width // VECTOR):
        for j in range(VECTOR):
            any_end |= lane_step(form, st, blk * VECTOR + j, kc, srf, ctrl, live)
    return any_end
