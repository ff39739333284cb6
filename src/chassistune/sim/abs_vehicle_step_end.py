"""A step's end in a lane of the vehicle kernel: distance, slip integrals and locking of each
wheel, the surfaces under the wheels, the yaw metrics and the run's status; at a stop, the
state at the stop (`abs_vehicle_stop`). Branch-free (selects under `commit`), shared by the
vector loop and the general path."""

from __future__ import annotations

import math

import numba

from chassistune._branchfree import select
from chassistune.sim.abs_vehicle_lane import lane_get, lane_put, put_state, target_slip
from chassistune.sim.abs_vehicle_layout import (
    KC_DT,
    KC_HOPELESS,
    KC_LOCK,
    KC_NSTEPS,
    KC_RW,
    KC_TTIMEOUT,
    KC_VSTOP,
    KC_WINDOW,
    R_ALL_D,
    R_ALL_T,
    R_ALL_V,
    R_DIST,
    R_ENDED,
    R_IAE,
    R_ISE,
    R_ITAE,
    R_K4,
    R_LOCK_M0,
    R_LOCK_M1,
    R_LOCK_T,
    R_LOCKED,
    R_PSI1,
    R_SINT,
    R_SLIP,
    R_SPEED,
    R_SPIN_T,
    R_STATUS,
    R_STEP,
    R_SURF,
    R_TEND,
    R_Y1,
    R_YAWPK,
    R_YAWPK1,
    STATUS_DIVERGED,
    STATUS_HOPELESS,
    STATUS_STOPPED,
    STATUS_TIMEOUT,
)
from chassistune.sim.abs_vehicle_stop import at_stop
from chassistune.sim.abs_vehicle_wheels import surface_flag
from chassistune.sim.inlined import INDEXING, inlined
from chassistune.sim.integrate import crossing_fraction, error_integrals, trapezoid


@numba.njit(**INDEXING)
def put_surface(st, l, commit, j, b, cp, sp, kc):
    """The surface flag of wheel j of lane l at the body state b (`surface_flag`)."""
    lane_put(
        st,
        R_SURF + j,
        l,
        commit,
        surface_flag(lane_get(st, R_SURF + j, l), b[3], b[4], cp, sp, j, kc),
    )


@numba.njit(**INDEXING)
def wheel_end(st, l, commit, j, s_new, vabs, w, w0, vabs0, acc, timing, kc):
    """Step-end integrals of wheel j (slip, its error to the target, locking), its slip at the
    step's end (at the stop when the run stops) and, in the step it first locks, that step's
    start and its margins w R - lock_ratio |V| at the start (w0, vabs0) and the end (the lock
    time: `lock_time`). acc = (iae, itae, ise, locked, all still) so far, returned updated;
    timing = (t, the stop's crossing fraction, the step's length up to the stop, stop, moving)."""
    t, frac, h, stop, moving = timing
    slip = lane_get(st, R_SLIP + j, l)
    target = target_slip(st, j, l)
    s_end = slip + frac * (s_new - slip)
    d_iae, d_itae, d_ise = error_integrals(target - slip, target - s_end, t, h)
    lane_put(st, R_SINT + j, l, commit, lane_get(st, R_SINT + j, l) + trapezoid(slip, s_end, h))
    lane_put(st, R_SLIP + j, l, commit, select(stop, s_end, s_new))
    locked = moving & (w * kc[KC_RW] < kc[KC_LOCK] * vabs)
    lock_t = lane_get(st, R_LOCK_T + j, l)
    first = locked & (lock_t != lock_t)
    lane_put(st, R_LOCK_T + j, l, commit, select(first, t, lock_t))
    lane_put(st, R_LOCK_M0 + j, l, commit & first, w0 * kc[KC_RW] - kc[KC_LOCK] * vabs0)
    lane_put(st, R_LOCK_M1 + j, l, commit & first, w * kc[KC_RW] - kc[KC_LOCK] * vabs)
    return (
        acc[0] + d_iae,
        acc[1] + d_itae,
        acc[2] + d_ise,
        acc[3] + select(locked, kc[KC_DT], 0.0),
        acc[4] & (w == 0.0),
    )


@inlined
def end_step(st, l, commit, x0, vabs0, x, slips, vabs, cp, sp, k4, kc, stops):
    """Commit the step from state x0 (its wheels' |V|: vabs0) to state x = (b, w0, w1, w2, w3)
    and k4 of lane l where `commit`: distance, integrals, locking, surfaces, yaw metrics,
    status; at a stop the lane keeps the state at the stop (`at_stop`) and the surfaces of the
    step. `stops`, a constant: whether this pass may commit the step in which the run stops
    (False folds the stop's code away). Returns whether the run ended."""
    b, w0, w1, w2, w3 = x
    dt = kc[KC_DT]
    v_stop = kc[KC_VSTOP]
    k = lane_get(st, R_STEP, l)
    t = k * dt
    vx = b[0]
    vy = b[1]
    sp_new = math.sqrt(vx * vx + vy * vy)
    sp_old = lane_get(st, R_SPEED, l)
    stop = (sp_new <= v_stop) & stops  # a constant False folds the stop away
    frac = crossing_fraction(sp_old, sp_new, v_stop, stop)
    h = frac * dt
    dist = lane_get(st, R_DIST, l) + trapezoid(sp_old, select(stop, v_stop, sp_new), h)
    moving = sp_new > v_stop
    acc = (
        lane_get(st, R_IAE, l),
        lane_get(st, R_ITAE, l),
        lane_get(st, R_ISE, l),
        lane_get(st, R_LOCKED, l),
        True,
    )
    timing = (t, frac, h, stop, moving)
    acc = wheel_end(st, l, commit, 0, slips[0], vabs[0], w0[0], x0[1][0], vabs0[0], acc, timing, kc)
    acc = wheel_end(st, l, commit, 1, slips[1], vabs[1], w1[0], x0[2][0], vabs0[1], acc, timing, kc)
    acc = wheel_end(st, l, commit, 2, slips[2], vabs[2], w2[0], x0[3][0], vabs0[2], acc, timing, kc)
    acc = wheel_end(st, l, commit, 3, slips[3], vabs[3], w3[0], x0[4][0], vabs0[3], acc, timing, kc)
    iae, itae, ise, locked, all_still = acc
    all_t = lane_get(st, R_ALL_T, l)
    first = all_still & (all_t != all_t) & moving
    lane_put(st, R_ALL_T, l, commit, select(first, t + dt, all_t))
    lane_put(st, R_ALL_V, l, commit, select(first, sp_new, lane_get(st, R_ALL_V, l)))
    lane_put(st, R_ALL_D, l, commit, select(first, dist, lane_get(st, R_ALL_D, l)))
    switch = commit & (not stop)
    put_surface(st, l, switch, 0, b, cp, sp, kc)
    put_surface(st, l, switch, 1, b, cp, sp, kc)
    put_surface(st, l, switch, 2, b, cp, sp, kc)
    put_surface(st, l, switch, 3, b, cp, sp, kc)
    r_now = b[2]
    psi_now = b[5]
    in_window = t + 0.5 * dt < kc[KC_WINDOW]
    yaw_pk1 = lane_get(st, R_YAWPK1, l)
    lane_put(
        st, R_YAWPK1, l, commit, select(in_window & (abs(r_now) > abs(yaw_pk1)), r_now, yaw_pk1)
    )
    window_end = in_window & (t + 1.5 * dt >= kc[KC_WINDOW])
    lane_put(st, R_PSI1, l, commit, select(window_end, psi_now, lane_get(st, R_PSI1, l)))
    lane_put(st, R_Y1, l, commit, select(window_end, b[4], lane_get(st, R_Y1, l)))
    spin_t = lane_get(st, R_SPIN_T, l)
    no_spin = spin_t != spin_t
    yaw_pk = lane_get(st, R_YAWPK, l)
    lane_put(st, R_YAWPK, l, commit, select(no_spin & (abs(r_now) > abs(yaw_pk)), r_now, yaw_pk))
    lane_put(
        st, R_SPIN_T, l, commit, select(no_spin & (abs(psi_now) >= 0.5 * math.pi), t + dt, spin_t)
    )
    check = sp_new + r_now + psi_now + itae + w0[1] + w0[3] + w0[0]
    diverged = check - check != 0.0
    hopeless = dist > kc[KC_HOPELESS]
    timeout = k + 1.0 >= kc[KC_NSTEPS]
    lane_put(
        st,
        R_STATUS,
        l,
        commit,
        select(
            diverged,
            STATUS_DIVERGED,
            select(stop, STATUS_STOPPED, select(hopeless, STATUS_HOPELESS, STATUS_TIMEOUT)),
        ),
    )
    lane_put(
        st,
        R_TEND,
        l,
        commit,
        select(diverged, t, select(stop, t + h, select(hopeless, t + dt, kc[KC_TTIMEOUT]))),
    )
    ended = diverged | stop | hopeless | timeout
    lane_put(st, R_ENDED, l, commit, select(ended, 1.0, 0.0))
    lane_put(st, R_SPEED, l, commit, sp_new)
    lane_put(st, R_DIST, l, commit, dist)
    lane_put(st, R_IAE, l, commit, iae)
    lane_put(st, R_ITAE, l, commit, itae)
    lane_put(st, R_ISE, l, commit, ise)
    lane_put(st, R_LOCKED, l, commit, locked)
    lane_put(st, R_STEP, l, commit, k + 1.0)
    put_state(st, 0, l, commit, at_stop(x0, x, stop, 1.0 - frac, dt, cp, sp))
    put_state(st, R_K4, l, commit, k4)
    return ended
