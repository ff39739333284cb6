"""Compiled closed-loop simulation of the single-wheel ABS (design.md 3.1) over a population, in
persistent SIMD lanes.

Plant (derlsp-ao-abs eqs. 1-4, 9-10; `sim.abs_wheel_model`), with Fz = lf M g the wheel load:
    M dv/dt = -mu(S) Fz,   I dw/dt = R mu(S) Fz - kq q  (w >= 0),   S = (v - w R)/v,
    T dr/dt = K u - r,   dq/dt = r with q held in [0, q_max].
Control u: the continuous PID of `controllers.pid` (filtered derivative, conditional integration)
with gains fixed (PID) or scheduled at each sample (fuzzy PID), plus a held command u0 of the
sampled laws (none, bang-bang, threshold, fuzzy immune PID), evaluated every `ts_s` (a whole
number of steps) so that the controller does not change when the step is refined.

Transient slip (docs/tires.md): with `relaxation_length_m` sigma > 0 the tire reads a lagged slip
S', a state, sigma dS'/dt = (v - w R) - v S' (`_relaxed_rates_at`), in one more vector loop
(`_relaxed_lane_steps_of`) that a run takes by a run-time test of sigma; sigma = 0 runs the
static loops below, unchanged.

Integration at a fixed step on (v, w, q, r, z, xf) (`sim.integrate`): Kutta's RK3 with explicit
fused multiply-adds for the PID and no ABS, classic RK4 for the sampled laws (bang-bang,
threshold, fuzzy PID, fuzzy immune PID). Measured against dt/100, RK3 at 1 ms is the
more accurate for the PID on every road of paper-derlsp-ao and in its tuning box (the error
comes from kinks, clipping and saturation, not from the order) and 1.3x faster; for the sampled
laws the comparison is mixed (threshold on ice: RK3 1.3e-3 against RK4 6.0e-4) and their cost is
in the ticks, so they keep RK4. Distance and the slip integrals (IAE, ITAE, ISE, mean slip) by
exact quadrature of the step-end values (fused, constant divisions as products); the stop at
v_stop located by linear interpolation inside the last step.

Lanes. Every per-candidate quantity lives in ONE flat array `st` of rows of LANES values (row r
of lane l at r * LANES + l: a compile-time-constant stride). Each iteration runs one fused RK
step for a whole number of 8-wide vectors of lanes (`_lane_steps`): straight-line code, no calls,
no branches (selects), every stage in registers, so that LLVM vectorizes across lanes (a test
checks the packed instructions). Rare events run in scalar passes outside the vector loop: a
sampled controller's tick (before the step) and a finished run (after it), whose lane is
refilled from the queue of candidates or, when the queue is empty, filled with the last live
lane (the live lanes stay packed at the front). Each lane has its own step counter, so t = k dt
is what a one-candidate loop computes, and every number is bitwise independent of the lane,
the population and the thread count.

Dependency chain. An iteration is bound by its longest chain of dependent operations (three
divisions and clips in the stages, then the metrics), not by the arithmetic count (llvm-mca:
258 cycles per 8 lanes against a throughput bound of 107). Two things keep it short without
changing a number: the first stage reads the slip the last step left (`R_S1`, the same
expression, no division), and a step adds its predecessor's error integrals (`R_EA` ... `R_EH`,
`_add_pending_integrals`), so that their division runs beside the integration; the run's end
adds the last step's (258 cycles per iteration for RK3, 377 for RK4).

No reference counting. The entry points are compiled without numba's runtime (`_nrt=False`):
the caller passes the lane array `st` and `lane_of` as scratch, and nothing is allocated. With
it, every inlined call that took an array (a sampled controller's tick, eight arrays) paid an
atomic increment and decrement for each: 40 ns per candidate-step, three quarters of the fuzzy
immune PID's time.

Per-row plant parameters. The plant vector `plant` is (1, N) for all candidates or (n, N), one
row per candidate (robust tuning): a lane takes its row when it is filled, and the vector loop
reads only lane rows (`R_RW` ... `R_HOPELESS`, the target slip `R_TARGET`: a row per candidate
under a tunable fixed target, `scenarios.road_knowledge`). dt, t_max and the tire are shared.
Per-row plant parameters cost nothing extra in the vector loop.

Entry point: one cached compiled function (`entry_point`) for every tire and control law;
`simulate_abs_wheel` allocates the scratch and calls it. The tire law is a runtime integer picked
once per iteration, outside the vector loop: the loop is compiled once per tire law and method,
each copy with its tire law a constant, so that the other laws fold away. The lane loop and each
vector loop compile as functions of their own (numba inlines a function by copying its IR, at a
cost that grows with what it inlines: inlined, each copy of the loop would be compiled again at
each level), and the vector loop copies its table nodes to its own stack (`local_table`). The
control law is a runtime integer, its kind (`controllers.laws`), run through
the one dispatch generated from the registry (`controllers.laws.dispatch`): its held values at a
run's start and, at each step, one call of its tick pass (`_tick_lanes_of`: a function of its
own per sampled law, its tick inlined in a loop over the lanes due), so that a tick costs its
arithmetic, not a call with the law's arguments unpacked into scalars (a fuzzy law's table
alone is about 50).
"""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np
from numba import njit, types
from numba.core.errors import TypingError
from numba.extending import overload, register_jitable

from chassistune._branchfree import clip, fmax, fmin, select, stack_copy
from chassistune._rows import read_rows, write_rows
from chassistune.controllers.laws import registry as laws
from chassistune.controllers.laws.dispatch import (
    continuous_groups,
    law_initial_state,
    law_sampled,
    law_start,
    tick_pass,
)
from chassistune.controllers.laws.forms import SIG_PRESSURE, SIG_WHEEL_SPEED
from chassistune.controllers.laws.held_pid import HELD_PID
from chassistune.controllers.laws.registry import ContinuousForm
from chassistune.plants.mf_curve import POLY_SIZE
from chassistune.plants.mf_relaxation import lagged_slip_rate_from_slip_speed_per_s
from chassistune.sim import abs_wheel_layout as L
from chassistune.sim.abs_wheel_model import step_end, wheel_rates, wheel_slip
from chassistune.sim.abs_wheel_tires import (
    KIND_BILINEAR,
    KIND_BURCKHARDT,
    KIND_MAGIC_FORMULA,
    KIND_TABLE,
    TABLE_CAP,
    local_poly,
    local_table,
    magic_formula_mu,
    table_tuples,
    tire_law_mu,
)
from chassistune.sim.inlined import INLINE, inlined
from chassistune.sim.integrate import (
    error_integrals,
    rk3_point2,
    rk3_point3,
    rk3_update,
    rk4_point,
    rk4_update,
    trapezoid,
)
from chassistune.sim.lanes import close_lane

# slots of the declared layouts (numba freezes these module integers as constants)
P_MASS, P_INERTIA, P_RADIUS, P_V0 = (
    L.PLANT[n] for n in ("mass_kg", "wheel_inertia_kg_m2", "wheel_radius_m", "v0_m_s")
)
P_G, P_K, P_TAU, P_KQ, P_QMAX = (
    L.PLANT[n] for n in ("g_m_s2", "actuator_gain", "actuator_tau_s", "brake_gain", "q_max")
)
P_VSTOP, P_TMAX, P_DT, P_LOAD, P_TARGET = (
    L.PLANT[n] for n in ("v_stop_m_s", "t_max_s", "dt_s", "load_fraction", "target_slip")
)
P_HOPELESS_M, P_LOCK_RATIO, P_NFILTER, P_SIGMA = (
    L.PLANT[n] for n in ("hopeless_distance_m", "lock_ratio", "n_filter", "relaxation_length_m")
)

Q_TS = L.CONTROLLER["ts_s"]

M_NTRACE = L.METRICS["trace_rows"]
METRIC_SLOTS = tuple(L.METRICS[n] for n in L.METRICS.names if n != "trace_rows")
"""The slots `write_metrics` fills, in the layout's order (status, stop time, distance, lock time,
IAE, ITAE, ISE, mean slip, peak slip, locked time, largest clip, smallest unclipped slip)."""
N_METRICS = len(L.METRICS)
STATUS_STOPPED, STATUS_HOPELESS, STATUS_TIMEOUT, STATUS_DIVERGED = (
    L.STATUS_NAMES.index(n) for n in ("stopped", "hopeless", "timeout", "diverged")
)

(T_TIME, T_V, T_WHEEL_V, T_SLIP, T_TARGET, T_Q, T_TB, T_U, T_X, T_MU) = (
    L.TRACE[n]
    for n in (
        "time_s",
        "vehicle_speed_m_s",
        "wheel_speed_m_s",
        "slip",
        "target_slip",
        "pressure",
        "brake_torque_n_m",
        "command",
        "distance_m",
        "mu",
    )
)
N_TRACE = len(L.TRACE)

LANES = 32
"""Candidates in flight per kernel call (a multiple of VECTOR)."""
VECTOR = 8
"""Lanes per vector iteration (8 doubles: one zmm register; two ymm)."""

RK3, RK4 = 3, 4
"""Integration methods (`_lane_step`): RK3 for the PID and no ABS, RK4 for the sampled laws."""

# Lane rows: states, metrics, bookkeeping, controller state, the lane's plant parameters.
(
    R_V,
    R_W,
    R_Q,
    R_R,
    R_SLIP,
    R_DIST,
    R_IAE,
    R_ITAE,
    R_ISE,
    R_SINT,
    R_CLIP,
    R_MINSLIP,
    R_PEAK,
    R_LOCKED,
    R_LOCK_T,
    R_STEP,
    R_STATUS,
    R_TEND,
    R_ENDED,
    R_U1,
    R_KP,
    R_KI,
    R_KD,
    R_U0,
    R_WS,
    R_RW,
    R_FZ,
    R_INV_M,
    R_INV_I,
    R_KQ,
    R_GAIN,
    R_INV_TAU,
    R_QMAX,
    R_NF,
    R_VSTOP,
    R_LOCK_RATIO,
    R_HOPELESS,
    R_S1,
    R_EA,
    R_EB,
    R_ET,
    R_EH,
    R_QS,
    R_TARGET,
    R_LAG,
    R_SIGMA,
    R_MEM,
) = range(47)
MEMORY = laws.slots("memory")
"""Rows of the law's memory (`Law.state`): the most any registered law keeps."""
R_X = R_MEM + MEMORY
"""The law's continuous state (`ContinuousForm.state`): `CONTINUOUS` rows after its memory."""
_MEMORY_ZEROS = (0.0,) * MEMORY
N_ROWS = R_X + laws.CONTINUOUS
"""Rows of a lane; the last `MEMORY` + `CONTINUOUS` hold the law's memory (`Law.state`) and its
continuous state."""
R_XF = R_X + HELD_PID.state.index("xf")
"""The held PID's derivative filter state, of which the sampled laws read de/dt."""


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def tire_mu(law, s, tire):
    """`tire_law_mu` at slip s of the tire tire = (c0, c1, c2, c3, xc, xs, ys)."""
    c0, c1, c2, c3, xc, xs, ys = tire
    return tire_law_mu(law, s, c0, c1, c2, c3, xc, xs, ys)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def wheel_tire_mu(law, s, tire):
    """`tire_mu` or, for KIND_MAGIC_FORMULA, `magic_formula_mu` at slip s of the wheel's tire
    (c0, c1, c2, c3, xc, xs, ys, poly), the law known at run time."""
    if law == KIND_MAGIC_FORMULA:
        return magic_formula_mu(s, tire[0], tire[1], tire[2], tire[3], tire[7])
    return tire_mu(law, s, tire[:7])


@functools.cache
def _mu_of_law(law: int) -> Any:
    """mu_of(s, tire): `tire_mu` of the constant tire law `law`, for its vector loops (not
    cached: the entry point's cache holds it). A loop then holds its own law's code alone: a
    branch on the law in every stage of every loop, even one LLVM folds, cost about 2 s of
    compile time per loop."""
    if law == KIND_MAGIC_FORMULA:

        def mu_of(s, tire):
            return magic_formula_mu(s, tire[0], tire[1], tire[2], tire[3], tire[7])

    else:

        def mu_of(s, tire):
            return tire_mu(law, s, tire[:7])

    mu_of.__qualname__ = f"mu_of_tire_law_{law}"
    return njit(nogil=True, error_model="numpy", inline="always")(mu_of)


_FORMS: list[ContinuousForm] = []
"""The continuous forms the vector loops were built for, by key (`_form_key`)."""


def _form_key(form: ContinuousForm) -> int:
    """The integer that names `form` in compiled code (`_form_rate`)."""
    if form not in _FORMS:
        _FORMS.append(form)
    return _FORMS.index(form)


def _form_rate(form, e, x, held, c, n_filter, at_max, at_min):
    """(u, dx) of the continuous form of key `form` (`ContinuousForm`; in compiled code)."""
    raise NotImplementedError("_form_rate runs in compiled code only")


@overload(_form_rate, prefer_literal=True, inline="always")
def _form_rate_inline(form, e, x, held, c, n_filter, at_max, at_min):
    if not isinstance(form, types.IntegerLiteral):
        raise TypingError("the continuous form's key must be a compile-time constant")
    rate = _FORMS[form.literal_value].forms()[1]

    def impl(form, e, x, held, c, n_filter, at_max, at_min):
        return rate(e, x, held, c, n_filter, at_max, at_min)

    return impl


@njit(**INLINE)
def _plant_rates(mu_of, form, x, s, s_tire, p, tire):
    """Derivatives of the state x = (v, w, q, r, xc) at its slip s, xc the continuous law's
    state, and the command u of its form of key `form` (`_form_rate`), with the lane's
    parameters p (`_lane_params`) and the tire (c0, c1, c2, c3, xc, xs, ys, poly) read at the
    slip s_tire."""
    _, w, q, r, xc = x
    held, c, target, r_w, fz, inv_m, inv_i, kq, gain, inv_tau, q_max, nf = p
    e = target - s
    fx = mu_of(s_tire, tire) * fz
    u, dxc = _form_rate(form, e, xc, held, c, nf, q >= q_max, q <= 0.0)
    dv, dw, dq, dr, _, _ = wheel_rates(w, q, r, fx, u, r_w, inv_m, inv_i, kq, gain, inv_tau, q_max)
    return (dv, dw, dq, dr, dxc), u


@njit(**INLINE)
def _rates_at(mu_of, form, x, s, p, tire):
    """`_plant_rates` of the static tire, which reads the slip s of x."""
    return _plant_rates(mu_of, form, x, s, s, p, tire)


@njit(**INLINE)
def _rates(mu_of, form, x, p, tire):
    """`_rates_at` at the slip of x."""
    return _rates_at(mu_of, form, x, wheel_slip(x[0], x[1], p[3]), p, tire)


@njit(**INLINE)
def _relaxed_rates_at(mu_of, form, x, s, p_sigma, tire):
    """Derivatives of x = (v, w, q, r, xc, S') at its kinematic slip s (clipped, what the law
    reads), the tire read at the lagged slip S' (`mu_of`: `odd_tire_mu`), and
    sigma dS'/dt = (v - w R) - v S' (`mf_relaxation.lagged_slip_rate_from_slip_speed_per_s`;
    docs/tires.md, transient slip); p_sigma = (the lane's parameters, sigma)."""
    v, w, q, r, xc, lag = x
    p, sigma = p_sigma
    k, u = _plant_rates(mu_of, form, (v, w, q, r, xc), s, lag, p, tire)
    dlag = lagged_slip_rate_from_slip_speed_per_s(v - w * p[3], lag, v, sigma)
    return k + (dlag,), u  # noqa: RUF005 (numba)


@njit(**INLINE)
def _relaxed_rates(mu_of, form, x, p_sigma, tire):
    """`_relaxed_rates_at` at the kinematic slip of x."""
    s = wheel_slip(x[0], x[1], p_sigma[0][3])
    return _relaxed_rates_at(mu_of, form, x, s, p_sigma, tire)


@register_jitable
def _get(st, row, l):
    """Row `row` of lane l (a call that LLVM inlines: `abs_vehicle_lane.lane_get`)."""
    return st[row * LANES + l]


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _lane_params(st, l, c):
    """The parameters of `_rates` in lane l: its held values, the controller vector c, the
    target slip and its plant row."""
    return (
        (_get(st, R_U0, l), _get(st, R_KP, l), _get(st, R_KI, l), _get(st, R_KD, l)),
        c,
        _get(st, R_TARGET, l),
        _get(st, R_RW, l),
        _get(st, R_FZ, l),
        _get(st, R_INV_M, l),
        _get(st, R_INV_I, l),
        _get(st, R_KQ, l),
        _get(st, R_GAIN, l),
        _get(st, R_INV_TAU, l),
        _get(st, R_QMAX, l),
        _get(st, R_NF, l),
    )


@njit(**INLINE)
def _rk_step(rates_at, rates, mu_of, form, method, x, s, dt, hs, h6, p, tire):
    """One RK step (`method` RK3 or RK4, a constant at each call site) of the state tuple x
    whose slip is s, by its right side `rates_at` (`_rates_at` or `_relaxed_rates_at`; `rates`
    the same at the slip of its state): (the new state, the command u at its start). Each
    stage is one tuple operation."""
    k1, u1 = rates_at(mu_of, form, x, s, p, tire)
    if method == RK4:
        k2, _ = rates(mu_of, form, rk4_point(x, hs, k1), p, tire)
        k3, _ = rates(mu_of, form, rk4_point(x, hs, k2), p, tire)
        k4, _ = rates(mu_of, form, rk4_point(x, dt, k3), p, tire)
        return rk4_update(x, h6, k1, k2, k3, k4), u1
    k2, _ = rates(mu_of, form, rk3_point2(x, hs, k1), p, tire)
    k3, _ = rates(mu_of, form, rk3_point3(x, -dt, dt + dt, k1, k2), p, tire)
    return rk3_update(x, h6, k1, k2, k3), u1


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _add_pending_integrals(st, l):
    """Add to lane l's IAE, ITAE and ISE those of its last step, whose slip errors a (at its
    start t) and b (at its end t + h) it left in rows R_EA, R_EB, R_ET, R_EH (zero at a
    start: nothing). Each step adds its predecessor's, so the division and fused chain of
    `error_integrals` runs beside the step's own integration instead of after it; the run's
    end adds its last step's (`_finish_lane`): the same sums in the same order."""
    d_iae, d_itae, d_ise = error_integrals(
        _get(st, R_EA, l), _get(st, R_EB, l), _get(st, R_ET, l), _get(st, R_EH, l)
    )
    st[R_IAE * LANES + l] += d_iae
    st[R_ITAE * LANES + l] += d_itae
    st[R_ISE * LANES + l] += d_ise


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _lane_step(st, l, xc, mu_of, form, method, dt, hs, h6, n_steps, t_timeout, live, tire, c):
    """One fused step (`method` RK3 or RK4, a constant at each call site) of lane l, whose
    control law's continuous state is xc and its form's key `form` (`_form_rate`), with its
    metrics and end flags (`_end_lane_step`); returns 1 if a live lane ended. Straight-line
    code: the body of the vector loop."""
    x = (_get(st, R_V, l), _get(st, R_W, l), _get(st, R_Q, l), _get(st, R_R, l), xc)
    p = _lane_params(st, l, c)
    s1 = _get(st, R_S1, l)  # the slip of x, kept from the last step: no division on the path
    xn, u1 = _rk_step(_rates_at, _rates, mu_of, form, method, x, s1, dt, hs, h6, p, tire)
    return _end_lane_step(st, l, x[0], xn, u1, p, dt, n_steps, t_timeout, live)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _relaxed_lane_step(st, l, xc, mu_of, form, dt, hs, h6, n_steps, t_timeout, live, tire, c):
    """`_lane_step` (RK3) with the tire's lagged slip S' a state (row R_LAG,
    `_relaxed_rates_at`)."""
    x = (_get(st, R_V, l), _get(st, R_W, l), _get(st, R_Q, l), _get(st, R_R, l), xc)
    p_sigma = (_lane_params(st, l, c), _get(st, R_SIGMA, l))
    s1 = _get(st, R_S1, l)
    xn, u1 = _rk_step(
        _relaxed_rates_at,
        _relaxed_rates,
        mu_of,
        form,
        RK3,
        x + (_get(st, R_LAG, l),),  # noqa: RUF005 (numba)
        s1,
        dt,
        hs,
        h6,
        p_sigma,
        tire,
    )
    st[R_LAG * LANES + l] = xn[5]
    return _end_lane_step(st, l, x[0], xn[:5], u1, p_sigma[0], dt, n_steps, t_timeout, live)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _end_lane_step(st, l, v, xn, u1, p, dt, n_steps, t_timeout, live):
    """Lane l after its step from speed v to the state xn = (v, w, q, r, xc) (w >= 0, q in
    [0, q_max]), the command u1 at its start: its metrics, end flags and new state; 1 if a
    live lane ended."""
    vn, wn, qn, rn, xcn = xn
    target = p[2]
    r_w = p[3]
    q_max = p[10]
    v_stop = _get(st, R_VSTOP, l)
    k = _get(st, R_STEP, l)
    t = k * dt
    wn = fmax(wn, 0.0)
    qn = clip(qn, 0.0, q_max)

    slip = st[R_SLIP * LANES + l]
    s_raw, s_new, stop, h, s_end = step_end(v, vn, wn, r_w, v_stop, slip, dt)
    dist = st[R_DIST * LANES + l] + trapezoid(v, select(stop, v_stop, vn), h)
    _add_pending_integrals(st, l)  # the last step's, off this step's dependency chain
    st[R_EA * LANES + l] = target - slip
    st[R_EB * LANES + l] = target - s_end
    st[R_ET * LANES + l] = t
    st[R_EH * LANES + l] = h
    st[R_SINT * LANES + l] += trapezoid(slip, s_end, h)
    st[R_CLIP * LANES + l] = fmax(st[R_CLIP * LANES + l], abs(s_raw - s_new))
    st[R_MINSLIP * LANES + l] = fmin(st[R_MINSLIP * LANES + l], s_raw)
    st[R_PEAK * LANES + l] = fmax(st[R_PEAK * LANES + l], s_new)
    locked = (vn > v_stop) & (wn * r_w < st[R_LOCK_RATIO * LANES + l] * vn)
    st[R_LOCKED * LANES + l] += select(locked, dt, 0.0)
    lock_t = st[R_LOCK_T * LANES + l]
    st[R_LOCK_T * LANES + l] = select(locked & (lock_t != lock_t), t + dt, lock_t)

    xc0, xc1 = (xcn + (0.0, 0.0))[:2]  # noqa: RUF005 (numba) the continuous state, two rows
    check = vn + wn + rn + xc0 + xc1
    diverged = check - check != 0.0
    hopeless = dist > st[R_HOPELESS * LANES + l]
    timeout = k + 1.0 >= n_steps
    st[R_STATUS * LANES + l] = select(
        diverged,
        STATUS_DIVERGED,
        select(stop, STATUS_STOPPED, select(hopeless, STATUS_HOPELESS, STATUS_TIMEOUT)),
    )
    st[R_TEND * LANES + l] = select(
        diverged, t, select(stop, t + h, select(hopeless, t + dt, t_timeout))
    )
    ended = diverged | stop | hopeless | timeout
    st[R_ENDED * LANES + l] = select(ended, 1.0, 0.0)
    st[R_V * LANES + l] = vn
    st[R_W * LANES + l] = wn
    st[R_Q * LANES + l] = qn
    st[R_R * LANES + l] = rn
    st[R_X * LANES + l] = xc0
    st[(R_X + 1) * LANES + l] = xc1
    st[R_SLIP * LANES + l] = s_new
    st[R_S1 * LANES + l] = s_new
    st[R_DIST * LANES + l] = dist
    st[R_STEP * LANES + l] = k + 1.0
    st[R_U1 * LANES + l] = u1
    return ended & (l < live)


_NO_NRT: dict[str, Any] = {"_nrt": False}
"""No reference counting (module docstring); numba's stubs omit the flag."""


@functools.cache
def _lane_steps_of(law: int, method: int, form: ContinuousForm) -> Any:
    """The vector loop (`_lanes_loop`) of tire law `law`, `method` and the control laws'
    continuous form `form` (constants inside: numba freezes a closure's variables), compiled once
    per entry point compilation."""
    key = _form_key(form)
    mu_of = _mu_of_law(law)

    @njit(**_LINK)
    def step(st, l, xc, dt, hs, h6, n_steps, t_timeout, live, tire, c):
        return _lane_step(
            st, l, xc, mu_of, key, method, dt, hs, h6, n_steps, t_timeout, live, tire, c
        )

    name = f"lane_steps_tire_law_{law}_rk{method}_{'_'.join(form.state)}"
    return _lanes_loop(step, len(form.state), name)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def odd_tire_mu(law, s, tire):
    """`wheel_tire_mu` extended to S < 0 as an odd function, its slip capped at 1 (on [0, 1]
    the law itself, bit for bit): the lagged slip turns negative while the wheel spins faster
    than the road, and the tire then drives it back (the tire curves are braking curves, S in
    [0, 1])."""
    mu = wheel_tire_mu(law, fmin(abs(s), 1.0), tire)
    return select(s < 0.0, -mu, mu)


@njit(nogil=True, error_model="numpy", **_NO_NRT)
def odd_tire_mu_of_runtime_law(s, tire):
    """`odd_tire_mu` of the tire law that follows the tire's constants, tire[8]: a call, not
    inlined (the four tire laws inlined at each stage doubled the relaxed loop's compile time,
    for a loop 1.2x (bilinear) to 1.6x (Magic Formula) faster)."""
    return odd_tire_mu(tire[8], s, tire)


@functools.cache
def _relaxed_lane_steps_of(form: ContinuousForm) -> Any:
    """The vector loop with the lagged slip (`_relaxed_lane_step`) of the control laws'
    continuous form `form`, RK3 for every law, its tire law a run-time value (the last of the
    caller's tire tuple): one loop for every tire law and group of laws, so that relaxation adds
    one loop, not one per tire law and method, to the entry point's compile time."""
    key = _form_key(form)

    @njit(**_LINK)
    def step(st, l, xc, dt, hs, h6, n_steps, t_timeout, live, tire, c):
        mu_of = odd_tire_mu_of_runtime_law
        return _relaxed_lane_step(
            st, l, xc, mu_of, key, dt, hs, h6, n_steps, t_timeout, live, tire, c
        )

    return _lanes_loop(step, len(form.state), f"relaxed_lane_steps_{'_'.join(form.state)}")


def _lanes_loop(step: Any, n_state: int, name: str) -> Any:
    """One step of lanes 0 .. width - 1 (a whole number of vectors) by `step` (`_lane_step`
    with its constants), compiled as a function of its own (not cached: the entry point's cache
    holds it); 1 if a live lane ended. The caller's tire tuple (c0, c1, c2, c3, xc, xs, ys,
    poly, ...) is copied to the loop's stack (`local_table`)."""

    def lane_steps(st, width, dt, hs, h6, n_steps, t_timeout, live, tire_of_caller, c):
        own = local_table(tire_of_caller[:7]) + (local_poly(tire_of_caller[7]),)  # noqa: RUF005
        tire = own + tire_of_caller[8:]
        any_end = 0
        for b in range(width // VECTOR):
            for j in range(VECTOR):
                l = b * VECTOR + j
                xc = (st[R_X * LANES + l], st[(R_X + 1) * LANES + l])[:n_state]  # CONTINUOUS rows
                any_end |= step(st, l, xc, dt, hs, h6, n_steps, t_timeout, live, tire, c)
        return any_end

    lane_steps.__qualname__ = name
    return njit(nogil=True, error_model="numpy", **_NO_NRT)(lane_steps)


def _vector_loop(laws_key, kind, law, st, width, dt, hs, h6, n_steps, t_timeout, live, tire, c):
    """One step of lanes 0 .. width - 1 by the vector loop (`_lane_steps_of`) of tire law `law`
    and of the continuous form and method of control law `kind` (in compiled code)."""
    raise NotImplementedError("_vector_loop runs in compiled code only")


def _relaxed_vector_loop(
    laws_key, kind, law, st, width, dt, hs, h6, n_steps, t_timeout, live, tire, c
):
    """`_vector_loop` with the tire's lagged slip (`_relaxed_lane_steps_of`; in compiled code)."""
    raise NotImplementedError("_relaxed_vector_loop runs in compiled code only")


_LINK: dict[str, Any] = {"nogil": True, "error_model": "numpy", "inline": "always"}
"""A link of the loop's chain is built per compilation (a closure over its loops): not cached."""


def _tire_switch(form: ContinuousForm, sampled: bool) -> Any:
    """The vector loops of `form` (RK4 for the sampled laws), one per tire law, by `law`; the
    Magic Formula's is RK3 for every law (one loop for both groups of laws: a second would add
    its compile time to the warmup's)."""
    method = RK4 if sampled else RK3
    bilinear, burckhardt, table = (
        _lane_steps_of(k, method, form) for k in (KIND_BILINEAR, KIND_BURCKHARDT, KIND_TABLE)
    )
    magic_formula = _lane_steps_of(KIND_MAGIC_FORMULA, RK3, form)

    @njit(**_LINK)
    def steps(kind, law, args):
        if law == KIND_BILINEAR:
            return bilinear(*args)
        if law == KIND_BURCKHARDT:
            return burckhardt(*args)
        if law == KIND_MAGIC_FORMULA:
            return magic_formula(*args)
        return table(*args)

    return steps


def _relaxed_switch(form: ContinuousForm, sampled: bool) -> Any:
    """The relaxed vector loop of `form` (`_relaxed_lane_steps_of`) for every tire law `law` and
    method, the law passed as the last of the tire tuple."""
    relaxed = _relaxed_lane_steps_of(form)

    @njit(**_LINK)
    def steps(kind, law, args):
        st, width, dt, hs, h6, n_steps, t_timeout, live, tire, c = args
        return relaxed(st, width, dt, hs, h6, n_steps, t_timeout, live, tire + (law,), c)  # noqa: RUF005

    return steps


def _kinds_link(kinds: tuple[int, ...], steps: Any, rest: Any) -> Any:
    @njit(**_LINK)
    def link(kind, law, args):
        hit = False
        for k in kinds:
            hit |= kind == k
        if hit:
            return steps(kind, law, args)
        return rest(kind, law, args)

    return link


def _law_chain(laws_key: Any, switch_of: Any) -> Any:
    """An if-chain over the registry's groups of laws by continuous form and method
    (`continuous_groups`), each branch `switch_of(form, sampled)` (a switch over the tire laws);
    a kind no law holds runs the first group's loops (the held PID, whose held values are then
    NaN: the run diverges): the implementation of `_vector_loop` or `_relaxed_vector_loop`."""
    if not isinstance(laws_key, types.IntegerLiteral):
        raise TypingError("laws_key must be a compile-time constant (the registry's fingerprint)")
    groups = continuous_groups()
    chain = switch_of(*groups[0][:2])
    for form, sampled, kinds in reversed(groups):
        if kinds:
            chain = _kinds_link(kinds, switch_of(form, sampled), chain)

    def impl(laws_key, kind, law, st, width, dt, hs, h6, n_steps, t_timeout, live, tire, c):
        return chain(kind, law, (st, width, dt, hs, h6, n_steps, t_timeout, live, tire, c))

    return impl


@overload(_vector_loop, prefer_literal=True)
def _vector_loop_chain(
    laws_key, kind, law, st, width, dt, hs, h6, n_steps, t_timeout, live, tire, c
):
    """`_law_chain` of the static tire's loops (`_tire_switch`)."""
    return _law_chain(laws_key, _tire_switch)


@overload(_relaxed_vector_loop, prefer_literal=True)
def _relaxed_vector_loop_chain(
    laws_key, kind, law, st, width, dt, hs, h6, n_steps, t_timeout, live, tire, c
):
    """`_law_chain` of the relaxed loops (`_relaxed_switch`)."""
    return _law_chain(laws_key, _relaxed_switch)


@njit(**INLINE)
def _fill_lane(st, l, i, gains, plant, laws_key, ctrl_kind, c):
    """Start candidate i in lane l: initial state, zero metrics, the law's held values at the
    start (`Law.forms`), its plant row."""
    p = plant[min(i, plant.shape[0] - 1)]
    for row in range(N_ROWS):
        st[row * LANES + l] = 0.0
    r_w = p[P_RADIUS]
    st[R_V * LANES + l] = p[P_V0]
    st[R_W * LANES + l] = p[P_V0] / r_w
    st[R_WS * LANES + l] = p[P_V0] / r_w  # wheel speed at the last sample
    st[R_LOCK_T * LANES + l] = np.nan
    x0 = law_initial_state(laws_key, ctrl_kind, p[P_TARGET])
    for j in range(len(x0)):
        st[(R_X + j) * LANES + l] = x0[j]
    u0, kp, ki, kd = law_start(laws_key, ctrl_kind, gains[i], 0, c)
    st[R_U0 * LANES + l] = u0
    st[R_KP * LANES + l] = kp
    st[R_KI * LANES + l] = ki
    st[R_KD * LANES + l] = kd
    st[R_RW * LANES + l] = r_w
    st[R_FZ * LANES + l] = p[P_LOAD] * p[P_MASS] * p[P_G]
    st[R_INV_M * LANES + l] = 1.0 / p[P_MASS]
    st[R_INV_I * LANES + l] = 1.0 / p[P_INERTIA]
    st[R_KQ * LANES + l] = p[P_KQ]
    st[R_GAIN * LANES + l] = p[P_K]
    st[R_INV_TAU * LANES + l] = 1.0 / p[P_TAU]
    st[R_QMAX * LANES + l] = p[P_QMAX]
    st[R_NF * LANES + l] = p[P_NFILTER]
    st[R_VSTOP * LANES + l] = p[P_VSTOP]
    st[R_LOCK_RATIO * LANES + l] = p[P_LOCK_RATIO]
    st[R_HOPELESS * LANES + l] = p[P_HOPELESS_M]
    st[R_S1 * LANES + l] = wheel_slip(p[P_V0], p[P_V0] / r_w, r_w)
    st[R_LAG * LANES + l] = st[R_S1 * LANES + l]
    st[R_SIGMA * LANES + l] = p[P_SIGMA]
    st[R_TARGET * LANES + l] = p[P_TARGET]


TRACE_SLOTS = (T_TIME, T_V, T_WHEEL_V, T_SLIP, T_TARGET, T_Q, T_TB, T_U, T_X, T_MU)


@inlined
def _put(row, slots, values):
    """row[slots[j]] = values[j] for a tuple of slots and a tuple of as many floats."""
    for j in range(len(slots)):
        row[slots[j]] = values[j]


@inlined
def write_metrics(out_row, end, integrals, extremes):
    """A run's METRICS row (trace rows 0) from end = (status, stop time, distance, lock time),
    integrals = (IAE, ITAE, ISE, integral of the slip) and extremes = (peak slip, locked time,
    largest clip, smallest unclipped slip)."""
    status, t_end, dist, lock_t = end
    iae, itae, ise, sint = integrals
    peak, locked, clip_max, min_slip = extremes
    mean_slip = sint / t_end if t_end > 0.0 else 0.0
    values = (float(status), t_end, dist, lock_t, iae, itae, ise, mean_slip, peak, locked)
    out_row[:] = 0.0
    _put(out_row, METRIC_SLOTS, (*values, clip_max, min_slip))


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def write_trace_row(row, t, v, wheel_v, slip, target, q, tb, u, x, mu):
    """The TRACE columns of one trace row."""
    _put(row, TRACE_SLOTS, (t, v, wheel_v, slip, target, q, tb, u, x, mu))


@inlined
def _finish_lane(st, l, out_row):
    """Write the metrics row of the run that ended in lane l."""
    _add_pending_integrals(st, l)
    r = st[l::LANES]  # lane l's rows
    write_metrics(
        out_row,
        (r[R_STATUS], r[R_TEND], r[R_DIST], r[R_LOCK_T]),
        (r[R_IAE], r[R_ITAE], r[R_ISE], r[R_SINT]),
        (r[R_PEAK], r[R_LOCKED], r[R_CLIP], r[R_MINSLIP]),
    )


@inlined
def _tick_inputs(st, l, t):
    """What a sampled law's tick at time t reads in lane l: its signals
    (`controllers.laws.forms.SIGNALS`), held values and memory (`MEMORY` rows)."""
    slip = st[R_SLIP * LANES + l]
    target = st[R_TARGET * LANES + l]
    e = target - slip
    ec = st[R_NF * LANES + l] * (e - st[R_XF * LANES + l])  # filtered de/dt
    sig = (
        e,
        slip,
        target,
        _get(st, R_W, l),
        _get(st, R_WS, l),
        _get(st, R_RW, l),
        ec,
        _get(st, R_V, l),
        _get(st, R_Q, l),
        _get(st, R_QS, l),
        t,
    )
    held = (_get(st, R_U0, l), _get(st, R_KP, l), _get(st, R_KI, l), _get(st, R_KD, l))
    mem = read_rows(st, R_MEM * LANES + l, LANES, _MEMORY_ZEROS)
    return sig, held, mem


@inlined
def _tick_store(st, l, held, mem, w, q):
    """Lane l after a sampled law's tick: its held values, its memory (the slots its tick
    returns) and the wheel speed w and pressure q at this sample."""
    st[R_U0 * LANES + l], st[R_KP * LANES + l], st[R_KI * LANES + l], st[R_KD * LANES + l] = held
    write_rows(st, R_MEM * LANES + l, LANES, mem)
    st[R_WS * LANES + l] = w
    st[R_QS * LANES + l] = q


@functools.cache
def _tick_lanes_of(tick: Any) -> Any:
    """The tick pass of the sampled law whose tick is `tick` (inlined: numba inlines a closure's
    function), compiled as a function of its own once per entry point compilation (not cached:
    the entry point's cache holds it): the law's update (`Law.forms`) in each of lanes
    0 .. live - 1 whose step is one of its own sample instants."""

    def tick_lanes(st, live, lane_of, gains, c, table, ts, steps_per_sample, dt):
        for l in range(live):
            k = int(st[R_STEP * LANES + l])
            if steps_per_sample == 1 or k % steps_per_sample == 0:
                sig, held, mem = _tick_inputs(st, l, k * dt)
                held, mem = tick(sig, held, mem, gains[lane_of[l]], 0, c, table, ts, k == 0)
                _tick_store(st, l, held, mem, sig[SIG_WHEEL_SPEED], sig[SIG_PRESSURE])

    tick_lanes.__qualname__ = f"tick_lanes_{tick.py_func.__module__.rsplit('.', 1)[-1]}"
    return njit(nogil=True, error_model="numpy", **_NO_NRT)(tick_lanes)


_tick_lanes = tick_pass(_tick_lanes_of)
"""The sampled law's tick in every lane due (`_tick_lanes_of`), by kind (in compiled code)."""


def _simulate(
    laws_key,
    law,
    gains,
    plant,
    coef,
    xc_tuple,
    xs_tuple,
    ys_tuple,
    poly,
    ctrl_kind,
    c,
    table,
    trace,
    out,
    st,
    lane_of,
):
    """The lane loop (see the module docstring) on the tire of law `law`; `laws_key` (the
    registered control laws, `_entry_point`) is a constant of the entry point."""
    xc = stack_copy(xc_tuple)
    xs = stack_copy(xs_tuple)
    ys = stack_copy(ys_tuple)
    n = gains.shape[0]
    p0 = plant[0]
    dt = p0[P_DT]
    hs = 0.5 * dt
    h6 = dt / 6.0
    n_steps = math.ceil(p0[P_TMAX] / dt - 1e-9)
    t_timeout = n_steps * dt
    steps_per_sample = max(1, round(c[Q_TS] / dt))
    ts = steps_per_sample * dt
    tire = (coef[0], coef[1], coef[2], coef[3], xc, xs, ys, poly)
    sampled = law_sampled(laws_key, ctrl_kind)
    relaxed = p0[P_SIGMA] > 0.0  # the same in every row (`simulate_abs_wheel`)
    st[:] = 0.0
    lane_of[:] = -1  # candidate in each lane
    live = min(n, LANES)
    for l in range(live):
        _fill_lane(st, l, l, gains, plant, laws_key, ctrl_kind, c)
        lane_of[l] = l
    queued = live  # next candidate to start
    n_trace = trace.shape[0]
    rows = 1
    if n_trace > 0:
        trace[0, :] = 0.0
        trace[0, T_V] = p0[P_V0]
        trace[0, T_WHEEL_V] = p0[P_V0]
        trace[0, T_TARGET] = p0[P_TARGET]
    trace_status = float(STATUS_TIMEOUT)
    trace_t_end = t_timeout
    while live > 0:
        if sampled:  # each lane at its own sample instants
            args = (st, live, lane_of, gains, c, table, ts, steps_per_sample, dt)
            _tick_lanes(laws_key, ctrl_kind, args)
        width = -(-live // VECTOR) * VECTOR
        if relaxed:  # laws_key passed as it is: a literal
            ended = _relaxed_vector_loop(
                laws_key, ctrl_kind, law, st, width, dt, hs, h6, n_steps, t_timeout, live, tire, c
            )
        else:
            ended = _vector_loop(
                laws_key, ctrl_kind, law, st, width, dt, hs, h6, n_steps, t_timeout, live, tire, c
            )
        if ended:
            for l in range(live - 1, -1, -1):  # high to low: lanes moved down are done
                if st[R_ENDED * LANES + l] == 0.0:
                    continue
                i = lane_of[l]
                _finish_lane(st, l, out[i])
                if i == 0:
                    trace_status = st[R_STATUS * LANES + l]
                    trace_t_end = st[R_TEND * LANES + l]
                if queued < n:
                    _fill_lane(st, l, queued, gains, plant, laws_key, ctrl_kind, c)
                    lane_of[l] = queued
                    queued += 1
                else:
                    live = close_lane(st, l, live, lane_of, N_ROWS, LANES)
        if n_trace > 0 and rows < n_trace:  # one candidate, in lane 0
            t = (st[R_STEP * LANES] - 1.0) * dt
            r = st[0::LANES]  # lane 0's rows
            v = r[R_V]
            s_tire = r[R_LAG] if relaxed else r[R_SLIP]  # S' of `odd_tire_mu`, or S
            write_trace_row(
                trace[rows],
                min(t + dt, trace_t_end),
                max(v, p0[P_VSTOP]) if trace_status == STATUS_STOPPED else v,
                r[R_W] * r[R_RW],
                r[R_SLIP],
                r[R_TARGET],
                r[R_Q],
                r[R_KQ] * r[R_Q],
                r[R_U1],
                r[R_DIST],
                odd_tire_mu(law, s_tire, tire),
            )
            rows += 1
    if n_trace > 0:
        out[0, M_NTRACE] = rows


_ENTRY_OPTIONS: dict[str, Any] = {"cache": True, "nogil": True, "error_model": "numpy", **_NO_NRT}
_simulate = njit(**_ENTRY_OPTIONS)(_simulate)


def _entry_point(laws_key):
    """The cached entry point for the registered control laws named by `laws_key`
    (`controllers.laws.registry.fingerprint`, as an integer: a closure variable, on which numba
    keys its disk cache; the law dispatch is generated from the registry when it compiles)."""

    def simulate_abs_wheel(
        law, gains, plant, coef, xc, xs, ys, poly, kind, c, table, trace, out, st, lane_of
    ):
        _simulate(
            laws_key,
            law,
            gains,
            plant,
            coef,
            xc,
            xs,
            ys,
            poly,
            kind,
            c,
            table,
            trace,
            out,
            st,
            lane_of,
        )

    simulate_abs_wheel.__doc__ = _simulate.__doc__
    return njit(**_ENTRY_OPTIONS)(simulate_abs_wheel)


entry_point = laws.per_fingerprint(_entry_point)
"""`simulate_abs_wheel`'s compiled loop, for the laws registered now."""


_NO_TABLE = table_tuples(np.array([0.0, 1.0]), np.array([0.0, 0.0]))
_NO_POLY = np.zeros(POLY_SIZE)


def tire_arguments(
    tire_kind: int, tire_coef: np.ndarray, tire_xs: np.ndarray, tire_ys: np.ndarray
) -> tuple[np.ndarray, tuple[float, ...], tuple[float, ...], tuple[float, ...], np.ndarray]:
    """The single-wheel kernels' tire arguments (coef, xc, xs, ys, poly) from
    `TireCurve.kernel_data()`: the four constants, the table's nodes (a table tire's; else
    unused ones) and the Magic Formula's piecewise polynomial (its xs; else unused zeros)."""
    coef4 = np.zeros(4)
    coef4[: len(tire_coef)] = tire_coef
    xc, xs, ys = table_tuples(tire_xs, tire_ys) if tire_kind == KIND_TABLE else _NO_TABLE
    poly = _NO_POLY
    if tire_kind == KIND_MAGIC_FORMULA:
        poly = np.ascontiguousarray(tire_xs, dtype=np.float64)
        if poly.shape != (POLY_SIZE,):
            raise ValueError(f"a Magic Formula tire has {POLY_SIZE} coefficients")
    return coef4, xc, xs, ys, poly


def simulate_abs_wheel(
    gains: np.ndarray,
    plant: np.ndarray,
    tire_kind: int,
    tire_coef: np.ndarray,
    tire_xs: np.ndarray,
    tire_ys: np.ndarray,
    ctrl_kind: int,
    c: np.ndarray,
    table: tuple[np.ndarray, ...],
    trace: np.ndarray,
    out: np.ndarray,
) -> None:
    """Simulate every row of `gains` (n, G: the controller's gains in registry order).

    `plant`: the PLANT vector (N,) or rows (1 or n, N); `tire_*`: `TireCurve.kernel_data()`;
    `ctrl_kind`: the law's kind (`controllers.laws.kind`); `c`: the CONTROLLER vector; `table`:
    a compiled fuzzy surface (`CompiledSurface.table`) for the fuzzy laws, any surface
    otherwise. Fuzzy PID gains: ke, kec, ku_p, ku_i, ku_d, kp0, ki0, kd0; fuzzy immune PID
    gains: k_immune, eta, ki, kd, ke, kec. Writes the metrics row of each candidate into `out`
    (n, N_METRICS); when `trace` has rows (n must be 1), also the time series (TRACE columns),
    one row per step.
    """
    coef4, xc, xs, ys, poly = tire_arguments(tire_kind, tire_coef, tire_xs, tire_ys)
    rows = np.ascontiguousarray(np.atleast_2d(plant), dtype=np.float64)
    relaxed = rows[:, L.PLANT["relaxation_length_m"]] > 0.0
    if relaxed.any() and not relaxed.all():
        raise ValueError("relaxation_length_m must be 0 in every plant row or in none")
    st = np.empty(N_ROWS * LANES)
    lane_of = np.empty(LANES, dtype=np.int64)
    entry_point()(
        tire_kind,
        gains,
        rows,
        coef4,
        xc,
        xs,
        ys,
        poly,
        ctrl_kind,
        c,
        table,
        trace,
        out,
        st,
        lane_of,
    )


__all__ = ["LANES", "TABLE_CAP", "entry_point", "simulate_abs_wheel"]
