"""Compiled closed loop of the 7-DOF vehicle ABS (design.md 3.3) over a population of candidates.

One kernel serves every wheel controller (the law's kind selects it, through the one dispatch
generated from the registry, `controllers.laws.dispatch`) and both paths: a batch of
n gain rows, or one row with a trace (a single run is a batch of one).

Plant (`chassistune.plants.abs_vehicle`): body (vx, vy, r), position and heading (X, Y, psi), an
optional driver steering angle delta, and per wheel its spin w, brake pressure q and pressure
rate (K/(s(Ts+1)) actuator, q held in [0, q_max]); the load/force loop is solved exactly at every
evaluation (closed form in a straight line, Newton's method otherwise).
    m (dvx/dt - vy r) = sum Fx_i,  m (dvy/dt + vx r) = sum Fy_i,  Iz dr/dt = sum x_i Fy_i - y_i Fx_i
    J dw_i/dt = -R Fx_i - kq q_i   (w_i >= 0: held at 0 while the brake exceeds the tire torque)
Wheel laws on e_i = S*_i - S_i (S_i = (u_i - w_i R)/|V_i| clipped to [0, 1], S*_i the optimal
slip of the surface under wheel i): the continuous PID of the single wheel (filtered derivative,
conditional integration) u = u0 + kp e + ki z + kd N (e - xf), plus the sampled part u0 of the
switching laws (none, threshold) and the sampled gain schedule of the fuzzy PID (period ts_s).
Select-low: both rear channels get e = min(e_rl, e_rr) (the wheel with the larger slip), hence
bitwise equal pressures.

Integration: classic RK4 at a fixed step over all states; the CG path length and the slip
integrals by quadrature of step-end values (as the single wheel); the surfaces under the wheels
and their target slips switch at step ends from the contact points' global positions; the stop
at v_stop (CG speed) is located by linear interpolation inside the last step, and the end metrics
(stop_x_m, the end heading and lateral offset) and the trace's last row are the state there
(`abs_vehicle_stop`), on the surfaces of that step. A wheel's lock time is located the same way.

The stages, one module each: the layouts (`abs_vehicle_layout`), a lane's rows
(`abs_vehicle_lane`), the wheels (`abs_vehicle_wheels`), the straight path
(`abs_vehicle_straight`), the general path (`abs_vehicle_general`), the tires' lagged slips
(`abs_vehicle_lag`: a run with a relaxation length takes the general path at every step), the
step's end (`abs_vehicle_step_end`), instants inside a step (`abs_vehicle_stop`), the wheel laws
(`abs_vehicle_ticks`); here the lane loop and the entry point.

Lanes (the design of `abs_wheel_kernel`). Every per-candidate quantity lives in ONE flat array `st`
of rows of LANES values. Each iteration runs one fused RK4 step per lane for a whole number of
VECTOR-wide blocks (`abs_vehicle_straight.lane_steps`): the straight-line case, all four stages in
registers, branch-free, stored by select only where every stage and the step's end were straight.
Lanes where that case does not hold (split-mu, a driver steering, a wheel unloaded), and the step in
which a run stops, are stepped by the general pass (`abs_vehicle_general.general_steps`), on lanes
too: each stage over all lanes in vector loops, the Newton load solve iterated while a lane's has
not returned, in the same formulas and order, so that a lane's numbers do not depend on the path,
the lane or the population. While every live lane took the general pass in the last step and no run
ended, the straight pass is skipped (the general pass gives a straight step the same numbers).
Sampled laws tick in a scalar pass before the step at each lane's own sample instants; a finished
lane is refilled from the queue or, when it is empty, filled with the last live lane (live lanes
stay packed in front).

Compilation: the entry point (`entry_point`) is a closure over the registry's fingerprint (on
which numba keys its disk cache); it passes the fingerprint to the lane loop (`_simulate`) as a
literal argument, so that the loop, with the ticks that dispatch on the laws inlined into it
(calls there slow the ticking laws), and the lane fill (`fill_lane`, a call: once per run)
compile as cached functions of their own, keyed on the registered laws. The vector loop and the
general pass compile once per continuous form of the registered laws (`by_continuous_form`); the
trace row, which reads no law, once. Their helpers are functions of their own that LLVM inlines
(`sim.inlined`), each compiled once rather than copied by numba into every call site.

No reference counting. The entry point and its scalar passes (the functions not inlined) are
compiled without numba's runtime (`_nrt=False`): the caller passes every array the kernel works
in as one tuple (`scratch()`), the kernel resets it, and nothing is allocated.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from chassistune.controllers.laws import registry as laws
from chassistune.controllers.laws.dispatch import by_continuous_form, law_sampled
from chassistune.sim.abs_vehicle_general import general_steps, trace_row
from chassistune.sim.abs_vehicle_lag import lagged
from chassistune.sim.abs_vehicle_lane import (
    NO_REFCOUNT,
    constants,
    lane_get,
    magic_formula,
    surfaces,
)
from chassistune.sim.abs_vehicle_layout import (
    KC_DT,
    KC_VSTOP,
    LANES,
    M_ALL_D,
    M_ALL_T,
    M_ALL_V,
    M_DIST,
    M_IAE,
    M_ISE,
    M_ITAE,
    M_ITER,
    M_LOCK_T,
    M_LOCKED,
    M_MEAN_SLIP,
    M_NTRACE,
    M_PSI1,
    M_PSI_END,
    M_SPIN_T,
    M_SPUN,
    M_STATUS,
    M_TIME,
    M_XSTOP,
    M_Y1,
    M_Y_END,
    M_YAWPK,
    M_YAWPK1,
    METRIC_LAYOUT,
    N_ROWS,
    N_SCRATCH,
    N_STATE,
    P_AXLE,
    P_V0,
    PLANT_LAYOUT,
    Q_TS,
    R_ALL_D,
    R_ALL_T,
    R_ALL_V,
    R_DIST,
    R_DONE,
    R_ENDED,
    R_IAE,
    R_ISE,
    R_ITAE,
    R_ITER,
    R_LOCKED,
    R_PSI1,
    R_SINT,
    R_SPIN_T,
    R_STATUS,
    R_STEP,
    R_TEND,
    R_Y1,
    R_YAWPK,
    R_YAWPK1,
    S_PSI,
    S_X,
    S_Y,
    STATUS_STOPPED,
    T_SPEED,
    TRACE_LAYOUT,
    VECTOR,
)
from chassistune.sim.abs_vehicle_stop import lock_time
from chassistune.sim.abs_vehicle_straight import lane_steps
from chassistune.sim.abs_vehicle_ticks import fill_lane, tick
from chassistune.sim.lanes import close_lane

__all__ = [
    "METRIC_LAYOUT",
    "PLANT_LAYOUT",
    "TRACE_LAYOUT",
    "entry_point",
    "scratch",
    "simulate_abs_vehicle",
]
"""The kernel's interface: its entry point, its scratch and the layouts of its plant vector,
metrics and trace rows (declared in `abs_vehicle_layout`, with the other slots)."""


_straight_pass = by_continuous_form(lane_steps)
_general_pass = by_continuous_form(general_steps)
"""The passes of the law's continuous form (one compiled pass per form of the registered laws,
`dispatch.rate_groups`), by kind (in compiled code); a trace row reads no law."""


@numba.njit(**NO_REFCOUNT)
def _finish_lane(st, l, out_row, dt):
    """Write the metrics row of the run that ended in lane l (step dt)."""
    t_end = lane_get(st, R_TEND, l)
    psi1 = lane_get(st, R_PSI1, l)
    y1 = lane_get(st, R_Y1, l)
    spin_t = lane_get(st, R_SPIN_T, l)
    out_row[:] = 0.0
    out_row[M_STATUS] = lane_get(st, R_STATUS, l)
    out_row[M_TIME] = t_end
    out_row[M_DIST] = lane_get(st, R_DIST, l)
    out_row[M_XSTOP] = lane_get(st, S_X, l)
    out_row[M_IAE] = lane_get(st, R_IAE, l)
    out_row[M_ITAE] = lane_get(st, R_ITAE, l)
    out_row[M_ISE] = lane_get(st, R_ISE, l)
    out_row[M_LOCKED] = lane_get(st, R_LOCKED, l)
    out_row[M_YAWPK1] = lane_get(st, R_YAWPK1, l)
    out_row[M_PSI1] = math.degrees(psi1 if psi1 == psi1 else lane_get(st, S_PSI, l))
    out_row[M_Y1] = y1 if y1 == y1 else lane_get(st, S_Y, l)
    out_row[M_YAWPK] = lane_get(st, R_YAWPK, l)
    out_row[M_SPUN] = 0.0 if spin_t != spin_t else 1.0
    out_row[M_SPIN_T] = spin_t
    out_row[M_PSI_END] = math.degrees(lane_get(st, S_PSI, l))
    out_row[M_Y_END] = lane_get(st, S_Y, l)
    out_row[M_ALL_T] = lane_get(st, R_ALL_T, l)
    out_row[M_ALL_V] = lane_get(st, R_ALL_V, l)
    out_row[M_ALL_D] = lane_get(st, R_ALL_D, l)
    for j in range(4):
        out_row[M_MEAN_SLIP + j] = lane_get(st, R_SINT + j, l) / t_end if t_end > 0.0 else 0.0
        out_row[M_LOCK_T + j] = lock_time(st, j, l, dt)
    out_row[M_ITER] = lane_get(st, R_ITER, l)


@numba.njit(**NO_REFCOUNT)
def _simulate(laws_key, gains, p, geo, surfs, ctrl_kind, c, table, trace, out, scratch):
    """Simulate every row of `gains` (n, G): the wheel law's gains in catalogue order, twice
    (front, then rear) when p[axle_gains] is 1.

    p: PLANT_LAYOUT vector; geo: GEOMETRY_LAYOUT rows x 4 wheels; surfs: surface rows (SF_*
    columns of `plants.abs_vehicle`), index 0 and 1; c: the single wheel's controller vector
    (ts_s, amplitude, thresholds); table: a compiled fuzzy surface (any surface for other laws).
    Writes each candidate's METRIC_LAYOUT row into out (n, N_METRICS); when `trace` has rows
    (n must be 1), also the TRACE_LAYOUT time series, one row per step. `scratch`: the arrays
    of `scratch()` (any contents: reset here; nothing is allocated).
    """
    y, sidx, guess, sc, wbuf, st, lane_of, col0 = scratch
    n = gains.shape[0]
    kc = constants(p, geo)
    srf = surfaces(surfs)
    mf = magic_formula(srf)
    relaxed = lagged(kc)
    dt = kc[KC_DT]
    n_g = gains.shape[1] // 2 if p[P_AXLE] != 0.0 else gains.shape[1]
    col0[:] = 0  # first gain column of each wheel
    for j in range(2, 4):
        col0[j] = n_g if p[P_AXLE] != 0.0 else 0
    steps_per_sample = max(1, round(c[Q_TS] / dt))
    ts = steps_per_sample * dt
    sampled = law_sampled(laws_key, ctrl_kind)
    # scratch of the trace row
    y[:] = 0.0
    sidx[:] = 0
    guess[:] = 0.0
    sc[:] = 0.0
    wbuf[:] = 0.0
    st[:] = 0.0
    lane_of[:] = -1  # candidate in each lane
    live = min(n, LANES)
    for l in range(live):
        fill_lane(st, l, l, gains, col0, laws_key, ctrl_kind, c, kc, srf, p[P_V0])
        lane_of[l] = l
    queued = live  # next candidate to start
    n_trace = trace.shape[0]
    work = (p, geo, surfs, sidx, guess, sc, y, wbuf)  # of a trace row
    rows = 0
    all_general = False  # every live lane took the general pass in the last step (no run ended)
    if n_trace > 0 and n > 0:
        trace_row(trace[rows], rows == 0, 0.0, st, 0, work)
        rows = 1
    while live > 0:
        if sampled:  # at each lane's own sample instants
            for l in range(live):
                k = int(lane_get(st, R_STEP, l))
                if k % steps_per_sample == 0:
                    i = lane_of[l]
                    tick(st, l, i, k, gains, col0, laws_key, ctrl_kind, c, table, kc, ts)
        width = -(-live // VECTOR) * VECTOR
        ended = False
        if all_general or mf or relaxed:  # skip the straight pass (the general one gives the
            # same numbers; the Magic Formula's loads have no closed form; the lag is the
            # general pass's)
            for l in range(width):
                st[R_DONE * LANES + l] = 0.0
        else:
            ended = _straight_pass(laws_key, ctrl_kind, (st, width, kc, srf, c, live))
        general = False
        all_general = True
        for l in range(live):
            general |= lane_get(st, R_DONE, l) == 0.0
            all_general &= lane_get(st, R_DONE, l) == 0.0
        if general:
            ended |= _general_pass(laws_key, ctrl_kind, (st, width, kc, srf, c, live))
        if n_trace > 0 and rows < n_trace:  # one candidate, in lane 0
            t = (lane_get(st, R_STEP, 0) - 1.0) * dt
            t_row = min(t + dt, lane_get(st, R_TEND, 0))
            trace_row(trace[rows], rows == 0, t_row, st, 0, work)
            if lane_get(st, R_STATUS, 0) == STATUS_STOPPED:  # the row at the stop
                trace[rows, T_SPEED] = kc[KC_VSTOP]
            rows += 1
        if ended:  # new runs in the lanes: the straight pass tries them again
            all_general = False
            for l in range(live - 1, -1, -1):  # high to low: lanes moved down are done
                if lane_get(st, R_ENDED, l) == 0.0:
                    continue
                i = lane_of[l]
                _finish_lane(st, l, out[i], dt)
                if queued < n:
                    fill_lane(st, l, queued, gains, col0, laws_key, ctrl_kind, c, kc, srf, p[P_V0])
                    lane_of[l] = queued
                    queued += 1
                else:
                    live = close_lane(st, l, live, lane_of, N_ROWS, LANES)
    if n_trace > 0 and n > 0:
        out[0, M_NTRACE] = rows


def _entry_point(laws_key):
    """The cached entry point for the registered control laws named by `laws_key`
    (`controllers.laws.registry.fingerprint`, as an integer: a closure variable, on which numba
    keys the disk cache; the law dispatch is generated from the registry when it compiles)."""

    def simulate_abs_vehicle(gains, p, geo, surfs, ctrl_kind, c, table, trace, out, scratch):
        _simulate(laws_key, gains, p, geo, surfs, ctrl_kind, c, table, trace, out, scratch)

    simulate_abs_vehicle.__doc__ = _simulate.__doc__
    return numba.njit(**NO_REFCOUNT)(simulate_abs_vehicle)


entry_point = laws.per_fingerprint(_entry_point)
"""The compiled entry point for the laws registered now."""


def simulate_abs_vehicle(
    gains: np.ndarray,
    p: np.ndarray,
    geo: np.ndarray,
    surfs: np.ndarray,
    ctrl_kind: int,
    c: np.ndarray,
    table: tuple[np.ndarray, ...],
    trace: np.ndarray,
    out: np.ndarray,
    scratch: tuple[np.ndarray, ...],
) -> None:
    """`_simulate` through the entry point of the registered laws (`entry_point`)."""
    entry_point()(gains, p, geo, surfs, ctrl_kind, c, table, trace, out, scratch)


def scratch() -> tuple[np.ndarray, ...]:
    """The scratch arrays `simulate_abs_vehicle` works in (it allocates nothing: compiled
    without reference counting), one tuple per call (a call on another thread needs its own):
    the trace row's state, surface indices, load guess, evaluation scratch and wheel speeds, then
    the lane rows `st`, the candidate in each lane and each wheel's first gain column."""
    return (
        np.empty(N_STATE),
        np.empty((4, 1), dtype=np.int64),
        np.empty((2, 1)),
        np.empty((N_SCRATCH, 4)),
        np.empty(4),
        np.empty(N_ROWS * LANES),
        np.empty(LANES, dtype=np.int64),
        np.empty(4, dtype=np.int64),
    )
