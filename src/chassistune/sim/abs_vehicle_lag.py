"""The tires' lagged slips on the vehicle (docs/tires.md, "Transient slip on the vehicle"): the
first-order relaxation-length model (Pacejka 2012, sec. 7.2.1, in the form of eq. 7.9 that stays
well posed as V -> 0; `plants.mf_relaxation`) for each wheel's longitudinal and lateral slip, in
the TIR files' ISO-W slips (`plants.vehicle_mf`), with (u, v) the wheel centre's velocity in the
wheel frame and s' = -kappa' (braking positive):

    sigma_kappa ds'/dt = (u - w R) - |u| s',      sigma_alpha dt'/dt = v - |u| t',

s' tending to (u - w R)/|u| and t' to tan(alpha) = v/|u| with the time constant sigma / |u|. The
tire reads (s', t') where the wheel's length is positive, the kinematic slip where it is 0, as
its slips (sx, v/|V|) = (s, t) cos(alpha), cos(alpha) = 1/sqrt(1 + t^2) (`tire_slips`); the wheel
laws still read the kinematic slip. A run with a length takes the general pass only, which
integrates the lag in its RK4 stages (`lag_stage`, `lag_end`); a run without one never reaches
this module's code."""

from __future__ import annotations

import math

import numba

from chassistune._branchfree import clip, select
from chassistune.plants.mf_relaxation import lagged_slip_rate_from_slip_speed_per_s
from chassistune.plants.vehicle_mf import magic_formula_slips
from chassistune.sim.abs_vehicle_lane import NO_REFCOUNT, lane_put
from chassistune.sim.abs_vehicle_layout import (
    KC_H6,
    KC_RW,
    KC_SIGMA_X,
    KC_SIGMA_Y,
    KC_VSTOP,
    LANES,
    N_TRACE_LAGGED,
    P_SIGMA_X,
    P_SIGMA_Y,
    R_GENERAL,
    R_KPREV,
    R_KSLIP,
    R_KSUM,
    R_SPEED,
    R_STEER_COS,
    R_STEER_SIN,
    R_SX,
    R_VR,
    S_LAG_X,
    S_LAG_Y,
    S_VX,
    S_VY,
    S_W,
    S_YR,
    T_LAG_X,
    T_LAG_Y,
    VECTOR,
    W_SX,
    W_VR,
)
from chassistune.sim.abs_vehicle_stop import rate_at_stop
from chassistune.sim.abs_vehicle_wheels import wheel_velocity
from chassistune.sim.inlined import INDEXING, inlined
from chassistune.sim.integrate import crossing_fraction


@inlined
def has_lengths(v, x0, y0):
    """Whether a wheel has a relaxation length: v[x0 + j] (longitudinal) or v[y0 + j] (lateral)
    positive for a wheel j (the kernel's constants, or the plant vector)."""
    on = False
    for j in range(4):
        on |= (v[x0 + j] > 0.0) | (v[y0 + j] > 0.0)
    return on


@inlined
def lagged(kc):
    """Whether the run's tires read lagged slips (the constants' relaxation lengths)."""
    return has_lengths(kc, KC_SIGMA_X, KC_SIGMA_Y)


@inlined
def tire_slips(s_lag, t_lag, sx, vr, sigma_x, sigma_y):
    """(s, t, sx', vr'): the longitudinal slip s (braking positive, over |u|) and tan(alpha) t the
    tire reads, the lagged ones where the wheel's length is positive, else the kinematic ones of
    the kernel's (sx, v/|V|) (`vehicle_mf.magic_formula_slips`); and the tire's inputs in the
    kernel's form, (sx', vr') = (s, t) cos(alpha), cos(alpha) = 1/sqrt(1 + t^2)."""
    kappa, tan_alpha = magic_formula_slips(sx, vr)
    s = select(sigma_x > 0.0, s_lag, -kappa)
    t = select(sigma_y > 0.0, t_lag, tan_alpha)
    cos = 1.0 / math.sqrt(1.0 + t * t)
    return s, t, s * cos, t * cos


@inlined
def lag_rate(slip_speed, speed, lag, sigma):
    """d(lag)/dt = (V_s - |V| lag) / sigma where sigma > 0, else 0
    (`mf_relaxation.lagged_slip_rate_from_slip_speed_per_s`)."""
    on = sigma > 0.0
    rate = lagged_slip_rate_from_slip_speed_per_s(slip_speed, lag, speed, select(on, sigma, 1.0))
    return select(on, rate, 0.0)


@numba.njit(**INDEXING)
def point(st, row, l, c):
    """Row `row` of lane l at the stage point x + c k_prev (`abs_vehicle_general.stage_point`)."""
    return st[row * LANES + l] + c * st[(R_KPREV + row) * LANES + l]


@numba.njit(**INDEXING)
def put_rate(st, row, l, k, first, weight):
    """State row `row`'s stage derivative k of lane l becomes its k_prev and enters the RK4 sum
    (`abs_vehicle_general.stage_end`)."""
    st[(R_KPREV + row) * LANES + l] = k
    total = st[(R_KSUM + row) * LANES + l]
    st[(R_KSUM + row) * LANES + l] = select(first, k, total + weight * k)


@numba.njit(**INDEXING)
def lag_wheel(st, l, j, b, cd, sd, c, first, weight, kc):
    """Wheel j's lag in lane l at the stage point x + c k_prev (body b = (vx, vy, r) there,
    steering (cos, sin) = (cd, sd)), after `abs_vehicle_general.stage_start` left its kinematic
    slips in the rows R_SX, R_VR: the tire's inputs into R_SX, R_VR (`tire_slips`), the
    kinematic slip clipped to [0, 1] into R_KSLIP (`kinematic_slips_back`), the lag's
    derivatives into k_prev and the RK4 sum (weight 2 for stages 2 and 3; `first`: stage 1)."""
    u, v, _ = wheel_velocity(b, cd, sd, j, kc)
    w = point(st, S_W + j, l, c)
    s_lag = point(st, S_LAG_X + j, l, c)
    t_lag = point(st, S_LAG_Y + j, l, c)
    sx = st[(R_SX + j) * LANES + l]
    sigma_x = kc[KC_SIGMA_X + j]
    sigma_y = kc[KC_SIGMA_Y + j]
    _, _, sx_tire, vr_tire = tire_slips(
        s_lag, t_lag, sx, st[(R_VR + j) * LANES + l], sigma_x, sigma_y
    )
    st[(R_KSLIP + j) * LANES + l] = clip(sx, 0.0, 1.0)
    st[(R_SX + j) * LANES + l] = sx_tire
    st[(R_VR + j) * LANES + l] = vr_tire
    put_rate(st, S_LAG_X + j, l, lag_rate(u - w * kc[KC_RW], u, s_lag, sigma_x), first, weight)
    put_rate(st, S_LAG_Y + j, l, lag_rate(v, u, t_lag, sigma_y), first, weight)


@inlined
def lag_stage(st, l, c, first, weight, kc):
    """A stage's lag in lane l (`lag_wheel` of its four wheels). Branch-free."""
    b = (point(st, S_VX, l, c), point(st, S_VY, l, c), point(st, S_YR, l, c))
    cd = st[R_STEER_COS * LANES + l]
    sd = st[R_STEER_SIN * LANES + l]
    lag_wheel(st, l, 0, b, cd, sd, c, first, weight, kc)
    lag_wheel(st, l, 1, b, cd, sd, c, first, weight, kc)
    lag_wheel(st, l, 2, b, cd, sd, c, first, weight, kc)
    lag_wheel(st, l, 3, b, cd, sd, c, first, weight, kc)


@numba.njit(**INDEXING)
def slip_back(st, l, j):
    st[(R_SX + j) * LANES + l] = st[(R_KSLIP + j) * LANES + l]


@numba.njit(**NO_REFCOUNT)
def kinematic_slips_back(st, blocks):
    """After a stage's load solve at the lagged slips, in the lanes of `blocks` vectors: R_SX
    holds the kinematic slip clipped to [0, 1] again (R_KSLIP), which the wheel laws' errors
    read (`stage_end`: clipping it again changes nothing)."""
    for blk in range(blocks):
        for i in range(VECTOR):
            l = blk * VECTOR + i
            slip_back(st, l, 0)
            slip_back(st, l, 1)
            slip_back(st, l, 2)
            slip_back(st, l, 3)


@numba.njit(**INDEXING)
def lag_update(st, row, l, general, stop, back, h6):
    """Lag row `row` of lane l after the step where `general` (`lag_end`)."""
    a = st[row * LANES + l]
    b = a + h6 * st[(R_KSUM + row) * LANES + l]
    lane_put(st, row, l, general, rate_at_stop(a, b, stop, back))


@numba.njit(**INDEXING)
def wheel_lag_update(st, j, l, general, stop, back, h6):
    """Wheel j's lag rows of lane l after the step (`lag_update`)."""
    lag_update(st, S_LAG_X + j, l, general, stop, back, h6)
    lag_update(st, S_LAG_Y + j, l, general, stop, back, h6)


@numba.njit(**NO_REFCOUNT)
def lag_end(st, blocks, kc):
    """The lag's RK4 update x + dt/6 (k1 + 2 k2 + 2 k3 + k4) in the lanes of `blocks` vectors that
    the general pass steps, before the step's end (`abs_vehicle_general.general_end`) moves the
    speed row: at a stop, the lag at the stop instant, linear over the step as the other states
    (`abs_vehicle_stop.at_stop`). Branch-free."""
    h6 = kc[KC_H6]
    v_stop = kc[KC_VSTOP]
    for blk in range(blocks):
        for i in range(VECTOR):
            l = blk * VECTOR + i
            vx = st[S_VX * LANES + l] + h6 * st[(R_KSUM + S_VX) * LANES + l]
            vy = st[S_VY * LANES + l] + h6 * st[(R_KSUM + S_VY) * LANES + l]
            sp_new = math.sqrt(vx * vx + vy * vy)
            stop = sp_new <= v_stop
            back = 1.0 - crossing_fraction(st[R_SPEED * LANES + l], sp_new, v_stop, stop)
            general = st[R_GENERAL * LANES + l] != 0.0
            wheel_lag_update(st, 0, l, general, stop, back, h6)
            wheel_lag_update(st, 1, l, general, stop, back, h6)
            wheel_lag_update(st, 2, l, general, stop, back, h6)
            wheel_lag_update(st, 3, l, general, stop, back, h6)


@numba.njit(**NO_REFCOUNT)
def lag_trace(trace_row, st, l, p, sc):
    """A trace row's slips where the run has relaxation lengths: the tire's inputs in the scratch
    rows (W_SX, W_VR: the loads and forces re-evaluated at them) from lane l's lagged slips and
    the kinematic ones there, and the slips the tire reads into the lagged columns when the
    trace has them (`LAG_TRACE_LAYOUT`)."""
    for j in range(4):
        s, t, sx, vr = tire_slips(
            st[(S_LAG_X + j) * LANES + l],
            st[(S_LAG_Y + j) * LANES + l],
            sc[W_SX, j],
            sc[W_VR, j],
            p[P_SIGMA_X + j],
            p[P_SIGMA_Y + j],
        )
        sc[W_SX, j] = sx
        sc[W_VR, j] = vr
        if trace_row.shape[0] >= N_TRACE_LAGGED:
            trace_row[T_LAG_X + j] = s
            trace_row[T_LAG_Y + j] = t
