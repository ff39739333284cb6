"""Compiled closed loop of the single-wheel ABS with an ECU-realistic controller
(docs/ecu.md), over a population, in persistent lanes like the ideal kernel's
(`sim.abs_wheel_kernel`: one flat array `st` of rows of LANES values, declared by name in
`abs_wheel_ecu_layout.LANE`; the live lanes packed at the front, refilled from the queue).

Plant: the ideal kernel's (`sim.abs_wheel_model.wheel_rates`, `sim.abs_wheel_tires`), RK4 at
the fixed step dt (`sim.integrate`), plus the wheel angle (dtheta/dt = w, RK4 on the stage
speeds) for the toothed sensor. With three-state valves the pressure is not integrated: it is
the exact orifice solution (`controllers.ecu.modulator_advance`) at the stage times. With a
relaxation length sigma > 0 (docs/tires.md, transient slip) the tire reads a lagged slip S', a
fifth state, sigma dS'/dt = (v - w R) - |v| S', in one more vector loop for every tire law
(`lagged_plant_step`), which a run takes by a run-time test of sigma; sigma = 0 runs the
loops above, unchanged.

Each iteration of the lane loop, per lane, in the order of docs/ecu.md "The realistic kernel":
- the ECU tick (every ecu_ts_s = m dt, before the step at t = k dt, k a multiple of m), one named
  stage after the other: `sensor` (true wheel speed, or the toothed wheel's last edge period,
  held or bounded), `reference_speed` (true, slew-limited or accelerometer), `ecu_slip`
  ((vref - w_est R) / vref in [0, 1]), `cutout`, `schedule` (kp, kd times max(vref / v0,
  floor)), `law` (the law's ECU form from the registry, `controllers.laws.dispatch`: the
  discrete form `export` ships; none and bang-bang as in the ideal kernel), `delay_line` (the
  command of tick j applied at tick j + delay), `valves` (continuous: the held command u into
  K/(s(Ts+1)); three-state: a pulse, `duty_pulse` for a law whose command is a pressure rate
  K u (the PID laws), `switching_pulse` for the switching laws, the driver's demand after the
  cut-out);
- three-state valves: whether a valve switches inside the step (`switch_within`: after a tick
  here, `valve_switches`; else the flag the last step's metrics left), and then the exact
  pressures through the switch (`switch_pressures`, `modulator_advance`);
- `plant_step`: one RK4 step (three-state valves: the stages read the one-state orifice solution, or
  the pressures of a step with a switch), then `step_metrics`: its metrics, end flags and the next
  step's switch flag; straight-line code (selects, no calls, no branches) in two vector loops of 8
  lanes, each a function of its own: the step's (`_plant_steps_of`) compiled once per tire law (a
  constant in each copy, picked by the lane loop), the metrics' (`_metric_steps`) once (numba
  inlines a function by copying its IR, at a cost that grows with what it inlines: inlined into the
  lane loop, each copy would be compiled again there);
- `sensor_edges`: the toothed sensor, for the lanes whose wheel passed an edge in the step
  (`sensor_step` in its pieces, the edge-time searches of all those lanes in lockstep);
- a finished run writes its metrics, and its lane takes the next candidate.
The law is the registry's kind in the ECU vector; the entry point is compiled per registry
fingerprint (`entry_point`), like the ideal kernels'.
The tick, the switch test and the edges are scalar passes over the lanes; each lane keeps its
own step counter, so every number is what a one-candidate loop computes, bitwise independent of
the lane, the population and the thread count.

No reference counting: the entry point is compiled without numba's runtime (`_nrt=False`); the
caller passes the lane array `st`, `lane_of`, the per-lane scratch rows `aux` (the law's
state, scheduled parameters and inputs, the delay line) and the edge scratch `edges`, and
nothing is allocated.

Metrics: the ideal kernel's slots (same quadrature), the slip integrals and the lock time
counting only before the cut-out; distance and time to v_stop; plus the ECU's (`ECU_METRICS`).
dt and t_max are shared by the population (plant row 0); the other plant parameters and the
target slip are per row.
"""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np
from numba import njit

from chassistune._branchfree import clip, fmax, fmin, select, stack_copy
from chassistune.controllers import discrete as D
from chassistune.controllers import ecu as E
from chassistune.controllers.laws import registry as laws
from chassistune.controllers.laws.dispatch import law_ecu_rate, law_ecu_schedule, law_ecu_step
from chassistune.controllers.laws.forms import ECU_SIGNALS
from chassistune.plants.mf_relaxation import lagged_slip_rate_from_slip_speed_per_s
from chassistune.sim import abs_wheel_ecu_layout as EL
from chassistune.sim import abs_wheel_layout as KL
from chassistune.sim.abs_wheel_kernel import (
    M_NTRACE,
    P_DT,
    P_G,
    P_HOPELESS_M,
    P_INERTIA,
    P_K,
    P_KQ,
    P_LOAD,
    P_LOCK_RATIO,
    P_MASS,
    P_QMAX,
    P_RADIUS,
    P_SIGMA,
    P_TARGET,
    P_TAU,
    P_TMAX,
    P_V0,
    P_VSTOP,
    STATUS_DIVERGED,
    STATUS_HOPELESS,
    STATUS_STOPPED,
    STATUS_TIMEOUT,
    T_TARGET,
    T_V,
    T_WHEEL_V,
    odd_tire_mu,
    odd_tire_mu_of_runtime_law,
    tire_arguments,
    wheel_tire_mu,
    write_metrics,
    write_trace_row,
)
from chassistune.sim.abs_wheel_model import step_end, wheel_rates, wheel_slip
from chassistune.sim.abs_wheel_tires import (
    KIND_BILINEAR,
    KIND_BURCKHARDT,
    KIND_MAGIC_FORMULA,
    KIND_TABLE,
    local_poly,
    local_table,
)
from chassistune.sim.inlined import INLINE, inlined
from chassistune.sim.integrate import error_integrals, rk4_point, rk4_update, trapezoid
from chassistune.sim.lanes import close_lane

(
    X_LAW,
    X_M,
    X_DELAY,
    X_TOOTHED,
    X_TEETH,
    X_TIMER,
    X_BOUND,
    X_VREF,
    X_AMAX,
    X_BIAS,
    X_AGREE,
    X_PFREE,
    X_AGREE_A,
    X_ANCHOR,
    X_VALVES,
    X_KB,
    X_KD,
    X_DEAD,
    X_MINON,
    X_CUTOUT,
    X_SCHED,
    X_FLOOR,
    X_AMP,
) = (EL.ECU[n] for n in EL.ECU.names)

if ECU_SIGNALS.names != (  # pragma: no cover
    "slip",
    "wheel_speed_rad_s",
    "pressure_at_max",
    "pressure_at_min",
    "target_slip",
    "amplitude",
    "reference_speed_m_s",
    "pressure",
    "pressure_prev",
    "wheel_speed_prev_rad_s",
    "time_s",
):
    raise RuntimeError("the ECU tick builds the law signals in ECU_SIGNALS order")

# the ideal kernel's metric and trace slots come first, at the same columns (ECU layouts)
M_ECU_IAE = EL.METRICS["ecu_slip_iae"]
if len(KL.METRICS) != M_ECU_IAE:  # pragma: no cover
    raise RuntimeError("the ECU metrics must follow the ideal kernel's")
T_VREF, T_WEST, T_ECU_SLIP, T_VALVE, T_EDGE_PREV, T_EDGE_LAST = (
    EL.TRACE[n] for n in EL.TRACE.names[len(KL.TRACE) :]
)
N_ECU_METRICS = len(EL.METRICS) - M_ECU_IAE

# lane rows (EL.LANE), in its order
(
    R_V,
    R_W,
    R_Q,
    R_R,
    R_THETA,
    R_SLIP,
    R_S1,
    R_STEP,
    R_TICK,
    R_V_START,
    R_THETA0,
    R_W0,
    R_H,
    R_STOP,
    R_STATUS,
    R_TEND,
    R_ENDED,
    R_KNEXT,
    R_EDGE_NEXT,
    R_TLAST,
    R_TPREV,
    R_WEST,
    R_READ_LAST,
    R_READ_PREV,
    R_VREF,
    R_VW_PREV,
    R_VW,
    R_HELD,
    R_ECU_SLIP,
    R_CUT,
    R_U0,
    R_CMD,
    R_RESID,
    R_W_PREV,
    R_Q_PREV,
    R_PM0,
    R_PS0,
    R_PO0,
    R_PM1,
    R_PS1,
    R_PO1,
    R_QSWITCH,
    R_QA,
    R_QB,
    R_VALVE,
    R_LAST_CHANGE,
    R_DIST,
    R_IAE,
    R_ITAE,
    R_ISE,
    R_SINT,
    R_ECU_IAE,
    R_CUT_T,
    R_NSW,
    R_MIN_IV,
    R_GAP,
    R_QLO,
    R_QHI,
    R_LOW_ERR,
    R_CLIP,
    R_MINSLIP,
    R_PEAK,
    R_LOCKED,
    R_LOCK_T,
    R_RW,
    R_FZ,
    R_INV_M,
    R_INV_I,
    R_KQ,
    R_GAIN,
    R_INV_TAU,
    R_QMAX,
    R_V0,
    R_VSTOP,
    R_TARGET,
    R_LOCK_RATIO,
    R_HOPELESS,
    R_LAG,
    R_SIGMA,
) = range(len(EL.LANE))
N_ROWS = len(EL.LANE)

LANES = 32
"""Candidates in flight per kernel call (a multiple of VECTOR)."""
VECTOR = 8
"""Lanes per vector iteration of `_plant_steps_of`."""

ECU_INPUTS = laws.slots("ecu_inputs")
"""Slots of a law's inputs in a lane's scratch row: the most any registered law reads."""

LOW_SPEED_BAND_M_S = (1.0, 9.0)
"""Speed band of `low_speed_slip_error` (fixed gains fail below about 9 m/s)."""

_inline = njit(cache=True, nogil=True, error_model="numpy", inline="always")
_jit = njit(cache=True, nogil=True, error_model="numpy")


@njit(**INLINE)
def _rates_at(law, x, s, u, p, tire):
    """Derivatives of x = (v, w, q, r) of the wheel, whose slip is s, under the held command u,
    with the plant p = (r_w, fz, inv_m, inv_i, kq, gain, inv_tau, q_max) and the tire
    (c0 .. c3, xc, xs, ys, poly) (design.md 3.1)."""
    _, w, q, r = x
    r_w, fz, inv_m, inv_i, kq, gain, inv_tau, q_max = p
    fx = wheel_tire_mu(law, s, tire) * fz
    dv, dw, dq, dr, _, _ = wheel_rates(w, q, r, fx, u, r_w, inv_m, inv_i, kq, gain, inv_tau, q_max)
    return dv, dw, dq, dr


@njit(**INLINE)
def _rates(law, x, u, p, tire):
    """`_rates_at` at the slip of x."""
    return _rates_at(law, x, wheel_slip(x[0], x[1], p[0]), u, p, tire)


@njit(**INLINE)
def _lagged_rates_at(law, x, s, u, p_sigma, tire):
    """Derivatives of x = (v, w, q, r, S') with the tire read at the lagged slip S' (its law
    tire[8], `odd_tire_mu_of_runtime_law`: a call) and sigma dS'/dt = (v - w R) - |v| S'
    (`mf_relaxation.lagged_slip_rate_from_slip_speed_per_s`; docs/tires.md, transient slip);
    p_sigma = (`_rates_at`'s p, sigma). The slip s and the law are not read (the ECU's law
    runs at its ticks)."""
    v, w, q, r, lag = x
    p, sigma = p_sigma
    r_w, fz, inv_m, inv_i, kq, gain, inv_tau, q_max = p
    fx = odd_tire_mu_of_runtime_law(lag, tire) * fz
    dv, dw, dq, dr, _, _ = wheel_rates(w, q, r, fx, u, r_w, inv_m, inv_i, kq, gain, inv_tau, q_max)
    return dv, dw, dq, dr, lagged_slip_rate_from_slip_speed_per_s(v - w * r_w, lag, v, sigma)


@njit(**INLINE)
def _lagged_rates(law, x, u, p_sigma, tire):
    """`_lagged_rates_at` (which reads no slip)."""
    return _lagged_rates_at(law, x, 0.0, u, p_sigma, tire)


@inlined
def _friction(st, l, tire, tc):
    """The friction coefficient the tire of lane l gives now: at its lagged slip S' with a
    relaxation length (`odd_tire_mu`), else at its slip."""
    if st[R_SIGMA * LANES + l] > 0.0:
        return odd_tire_mu(tire, st[R_LAG * LANES + l], tc)
    return wheel_tire_mu(tire, st[R_S1 * LANES + l], tc)


@inlined
def _stage(y, three_state, q):
    """The stage point y = (v, w, q, r, ...), with three-state valves at the exact pressure q."""
    return (y[0], y[1], select(three_state, q, y[2])) + y[3:]  # noqa: RUF005 (numba)


@_jit
def _valve_change(mode, t, cur, last_t, n_sw, min_iv):
    """Account a valve state `mode` from time t: (state, time of the last change, changes,
    shortest interval between changes)."""
    if mode == cur:
        return cur, last_t, n_sw, min_iv
    if last_t == last_t:
        min_iv = min(min_iv, t - last_t)
    return mode, t, n_sw + 1.0, min_iv


@_jit
def _retire_pulse(mode, start, on, ts, t_lim, cur, last_t, n_sw, min_iv):
    """Account the state changes of a pulse (mode for `on` seconds from `start`, then hold) that
    happen up to t_lim."""
    if start <= t_lim:
        cur, last_t, n_sw, min_iv = _valve_change(
            mode if on > 0.0 else E.VALVE_HOLD, start, cur, last_t, n_sw, min_iv
        )
    if start + on <= t_lim:
        cur, last_t, n_sw, min_iv = _valve_change(
            E.VALVE_HOLD if on < ts else mode, start + on, cur, last_t, n_sw, min_iv
        )
    return cur, last_t, n_sw, min_iv


@inlined
def _account_pulse(st, l, ts, t_lim):
    """Account lane l's current pulse's valve state changes up to t_lim (`_retire_pulse`)."""
    valve, last_change, n_sw, min_iv = _retire_pulse(
        st[R_PM1 * LANES + l],
        st[R_PS1 * LANES + l],
        st[R_PO1 * LANES + l],
        ts,
        t_lim,
        st[R_VALVE * LANES + l],
        st[R_LAST_CHANGE * LANES + l],
        st[R_NSW * LANES + l],
        st[R_MIN_IV * LANES + l],
    )
    st[R_VALVE * LANES + l] = valve
    st[R_LAST_CHANGE * LANES + l] = last_change
    st[R_NSW * LANES + l] = n_sw
    st[R_MIN_IV * LANES + l] = min_iv


@inlined
def sensor(st, l, t, x):
    """Tick stage 1 (docs/ecu.md, the realistic kernel, 1): the wheel speed the ECU reads, the
    true one or the toothed wheel's estimate held or bounded (`sensor_read`); records the edge
    times behind it."""
    st[R_READ_LAST * LANES + l] = st[R_TLAST * LANES + l]
    st[R_READ_PREV * LANES + l] = st[R_TPREV * LANES + l]
    if x[X_TOOTHED] == 0.0:
        return st[R_W * LANES + l]
    return E.sensor_read(
        st[R_WEST * LANES + l], st[R_TLAST * LANES + l], t, int(x[X_TEETH]), x[X_BOUND] != 0.0
    )


@inlined
def reference_speed(st, l, w_read, x, ts, tire, tc, acc_noise):
    """Tick stage 2 (docs/ecu.md, the realistic kernel, 2; Reference speed): the true speed,
    `vref_slew`, or `vref_accel` fed `accelerometer(a_true, bias, noise[tick])`."""
    tick = int(st[R_TICK * LANES + l])
    vw = w_read * st[R_RW * LANES + l]
    a_wheel = (vw - st[R_VW_PREV * LANES + l]) / ts if tick > 0 else 0.0
    st[R_VW_PREV * LANES + l] = vw
    st[R_VW * LANES + l] = vw
    vref_mode = int(x[X_VREF])
    vref = st[R_VREF * LANES + l]
    if vref_mode == 0:
        vref = st[R_V * LANES + l]
    elif vref_mode == 1:
        vref = E.vref_slew(vref, vw, x[X_AMAX], ts)
    elif tick > 0:
        fz, inv_m = st[R_FZ * LANES + l], st[R_INV_M * LANES + l]
        a_true = -_friction(st, l, tire, tc) * fz * inv_m
        noise = acc_noise[E.cyclic_index(tick, acc_noise.shape[0])]
        a_meas = E.accelerometer(a_true, x[X_BIAS], noise)
        vref, held = E.vref_accel(
            vref,
            vw,
            a_wheel,
            a_meas,
            ts,
            x[X_AGREE],
            x[X_AGREE_A],
            st[R_Q * LANES + l] <= x[X_PFREE],
            int(st[R_HELD * LANES + l]),
            x[X_ANCHOR],
        )
        st[R_HELD * LANES + l] = held
    st[R_VREF * LANES + l] = vref
    return vref


@inlined
def ecu_slip(st, l, vref, w_read):
    """Tick stage 3 (docs/ecu.md, the realistic kernel, 3): the slip the ECU computes,
    (vref - w_est R) / vref clipped to [0, 1]."""
    s = wheel_slip(vref, w_read, st[R_RW * LANES + l])
    st[R_ECU_SLIP * LANES + l] = s
    return s


@inlined
def cutout(st, l, vref, t, x):
    """Tick stage 4 (docs/ecu.md, Low-speed cut-out): the latch (its time is a metric), and the
    largest |v - vref| while the ABS works."""
    was_cut = st[R_CUT * LANES + l] != 0.0
    cut = E.cutout_latch(was_cut, vref, x[X_CUTOUT])
    st[R_CUT * LANES + l] = 1.0 if cut else 0.0
    if cut and not was_cut:
        st[R_CUT_T * LANES + l] = t
    if not cut:
        st[R_GAP * LANES + l] = max(st[R_GAP * LANES + l], abs(st[R_V * LANES + l] - vref))
    return cut


@njit(**INLINE)
def schedule(laws_key, kind, base, params, vref, v0, x):
    """Tick stage 5 (docs/ecu.md, Speed-scheduled gains): the law's parameters with its
    scheduled ones (kp and kd, or their table scales: `EcuForm.scheduled`) times
    max(vref / v0, floor), or as tuned."""
    f = E.speed_schedule(vref, v0, x[X_FLOOR]) if x[X_SCHED] != 0.0 else 1.0
    law_ecu_schedule(laws_key, kind, base, params, f)


@njit(**INLINE)
def law(laws_key, kind, state, inputs, params, table, grid, st, l, slip, w_read, vref, t, amp):
    """Tick stage 6 (docs/ecu.md, the realistic kernel, 4): the command of the law `kind`, its
    ECU form from the registry (`controllers.laws.dispatch.law_ecu_step`: the discrete form of
    design.md 4; none and bang-bang as in the ideal kernel), fed the signals it names
    (`forms.ECU_SIGNALS`: the ECU slip, the wheel speed read, the pressure at its bounds, the
    target slip, the amplitude, the reference speed, the valve model's pressure now and at the
    last tick, the wheel speed read at the last tick, the time) of lane l at t, whose pressure
    and wheel speed it then keeps for the next tick. The one call site of the law dispatch."""
    q, q_max = st[R_Q * LANES + l], st[R_QMAX * LANES + l]
    at_max = 1.0 if q >= q_max else 0.0
    at_min = 1.0 if q <= 0.0 else 0.0
    w_prev, q_prev = st[R_W_PREV * LANES + l], st[R_Q_PREV * LANES + l]
    target = st[R_TARGET * LANES + l]
    sig = (slip, w_read, at_max, at_min, target, amp, vref, q, q_prev, w_prev, t)
    st[R_W_PREV * LANES + l] = w_read
    st[R_Q_PREV * LANES + l] = q
    return law_ecu_step(laws_key, kind, state, inputs, sig, params, table, grid)


@inlined
def delay_line(line, tick, delay, u):
    """Tick stage 7 (docs/ecu.md, the realistic kernel, 5): the command of tick j - delay
    (zero for the first ticks); u enters the line."""
    if delay == 0:
        return u
    j = E.cyclic_index(tick, delay)
    cmd = line[j]
    line[j] = u
    return cmd


@inlined
def valves(st, l, rate, cmd, cut, t, ts, x):
    """Tick stage 8 (docs/ecu.md, Three-state modulator; the realistic kernel, 6): the held
    command of the continuous actuator, or the next valve pulse from t + dead time
    (`duty_pulse` of the PID laws' pressure rate K u, `switching_pulse` otherwise, build for the
    whole period once cut out), after accounting the retiring pulse's state changes."""
    st[R_CMD * LANES + l] = cmd
    if x[X_VALVES] == 0.0:
        st[R_U0 * LANES + l] = cmd
        return
    if cut:
        mode, on = E.VALVE_BUILD, ts
    elif rate:  # the PID laws: a pressure rate
        mode, on, resid = E.duty_pulse(
            st[R_GAIN * LANES + l] * cmd,
            st[R_RESID * LANES + l],
            st[R_Q * LANES + l],
            ts,
            x[X_KB],
            x[X_KD],
            st[R_QMAX * LANES + l],
            0.0,
            x[X_MINON],
        )
        st[R_RESID * LANES + l] = resid
    else:
        mode, on = E.switching_pulse(cmd, x[X_AMP], ts, x[X_MINON])
    if st[R_TICK * LANES + l] > 0.0:
        _account_pulse(st, l, ts, np.inf)
    st[R_PM0 * LANES + l] = st[R_PM1 * LANES + l]
    st[R_PS0 * LANES + l] = st[R_PS1 * LANES + l]
    st[R_PO0 * LANES + l] = st[R_PO1 * LANES + l]
    st[R_PM1 * LANES + l] = mode
    st[R_PS1 * LANES + l] = t + x[X_DEAD]
    st[R_PO1 * LANES + l] = on


@njit(**INLINE)
def _tick(st, l, aux, base, x, ts, t, tire, tc, table, grid, acc_noise, laws_key):
    """One ECU tick of lane l at t (docs/ecu.md, the realistic kernel): the tick stages in
    order. aux: the lane's scratch row (law state, scheduled parameters, inputs, delay line);
    base: its candidate's law parameters."""
    kind = int(x[X_LAW])
    amp = x[X_AMP]
    n_p = base.shape[0]
    state = aux[: D.N_STATE]
    params = aux[D.N_STATE : D.N_STATE + n_p]
    inputs = aux[D.N_STATE + n_p : D.N_STATE + n_p + ECU_INPUTS]
    line = aux[D.N_STATE + n_p + ECU_INPUTS :]
    w_read = sensor(st, l, t, x)
    vref = reference_speed(st, l, w_read, x, ts, tire, tc, acc_noise)
    slip = ecu_slip(st, l, vref, w_read)
    cut = cutout(st, l, vref, t, x)
    u = amp
    if not cut:
        schedule(laws_key, kind, base, params, vref, st[R_V0 * LANES + l], x)
        u = law(
            laws_key, kind, state, inputs, params, table, grid, st, l, slip, w_read, vref, t, amp
        )
    tick = int(st[R_TICK * LANES + l])
    cmd = delay_line(line, tick, int(x[X_DELAY]), u)
    valves(st, l, law_ecu_rate(laws_key, kind), amp if cut else cmd, cut, t, ts, x)
    st[R_TICK * LANES + l] = tick + 1.0


@_inline
def switch_within(st, l, t, dt):
    """Three-state valves (docs/ecu.md, Three-state modulator): whether a pulse boundary of lane
    l falls inside the step from t, t < b < t + dt (1.0 or 0.0). Branch-free: the metrics'
    vector loop flags the next step of every lane (`step_metrics`), a tick its own
    (`valve_switches`)."""
    t_end = t + dt
    b0 = st[R_PS0 * LANES + l] + st[R_PO0 * LANES + l]
    b1 = st[R_PS1 * LANES + l]
    b2 = b1 + st[R_PO1 * LANES + l]
    inside = ((t < b0) & (b0 < t_end)) | ((t < b1) & (b1 < t_end)) | ((t < b2) & (b2 < t_end))
    return select(inside, 1.0, 0.0)


@inlined
def switch_pressures(st, l, t, hs, dt, x):
    """The exact pressures at t + dt/2 and t + dt through the valve switch inside lane l's step
    (`modulator_advance`), which the step reads instead of its own one-state solution."""
    q, kb, kd, q_max = st[R_Q * LANES + l], x[X_KB], x[X_KD], st[R_QMAX * LANES + l]
    pm0, ps0, po0 = st[R_PM0 * LANES + l], st[R_PS0 * LANES + l], st[R_PO0 * LANES + l]
    pm1, ps1, po1 = st[R_PM1 * LANES + l], st[R_PS1 * LANES + l], st[R_PO1 * LANES + l]
    for row, h in ((R_QA, hs), (R_QB, dt)):
        st[row * LANES + l] = E.modulator_advance(
            q, t, h, pm0, ps0, po0, pm1, ps1, po1, kb, kd, q_max, 0.0
        )


@inlined
def valve_switches(st, l, t, hs, dt, x):
    """After a tick's new pulse: whether a valve switches inside lane l's step
    (`switch_within`) and, if so, the exact pressures through it (`switch_pressures`)."""
    st[R_QSWITCH * LANES + l] = switch_within(st, l, t, dt)
    if st[R_QSWITCH * LANES + l] != 0.0:
        switch_pressures(st, l, t, hs, dt, x)


@_inline
def _stage_pressures(st, l, t, hs, dt, kb, kd, q_max):
    """The three-state valves' pressures at t + dt/2 and t + dt (`modulator_advance`): one
    valve state over the step, `orifice_advance` from q; a step with a switch reads those of
    `valve_switches`. Branch-free."""
    q = st[R_Q * LANES + l]
    pm0, ps0, po0 = st[R_PM0 * LANES + l], st[R_PS0 * LANES + l], st[R_PO0 * LANES + l]
    pm1, ps1, po1 = st[R_PM1 * LANES + l], st[R_PS1 * LANES + l], st[R_PO1 * LANES + l]
    mode = E.valve_mode_at(t, pm0, ps0, po0, pm1, ps1, po1)
    qa = E.orifice_advance(q, mode, (t + hs) - t, kb, kd, q_max, 0.0)
    qb = E.orifice_advance(q, mode, (t + dt) - t, kb, kd, q_max, 0.0)
    switch = st[R_QSWITCH * LANES + l] != 0.0
    return select(switch, st[R_QA * LANES + l], qa), select(switch, st[R_QB * LANES + l], qb)


@_inline
def _step_start(st, l, dt, hs, kb, kd):
    """Lane l at the start of its step: the state x = (v, w, q, r), the plant p of
    `_rates_at`, the held command, the pressures of the three-state valves at t + dt/2 and
    t + dt (`_stage_pressures`) and the wheel angle."""
    r_w, q_max = st[R_RW * LANES + l], st[R_QMAX * LANES + l]
    pr = (
        r_w,
        st[R_FZ * LANES + l],
        st[R_INV_M * LANES + l],
        st[R_INV_I * LANES + l],
        st[R_KQ * LANES + l],
        st[R_GAIN * LANES + l],
        st[R_INV_TAU * LANES + l],
        q_max,
    )
    t = st[R_STEP * LANES + l] * dt
    qa, qb = _stage_pressures(st, l, t, hs, dt, kb, kd, q_max)
    x0 = (st[R_V * LANES + l], st[R_W * LANES + l], st[R_Q * LANES + l], st[R_R * LANES + l])
    return x0, pr, st[R_U0 * LANES + l], qa, qb, st[R_THETA * LANES + l]


@_inline
def _rk4_stages(rates_at, rates, tire, x0, s1, u0, p, tc, three_state, dt, hs, h6, qa, qb):
    """One classic RK4 step of x0 = (v, w, q, r, ...) by the right side `rates_at` (first stage,
    at the slip s1 the last step left: no division on the path) and `rates` (design.md 3.1;
    three-state valves: the stages read the exact pressures qa, qb): the step's end and the
    wheel speeds of stages 2 to 4 (for the wheel angle)."""
    k1 = rates_at(tire, x0, s1, u0, p, tc)
    x2 = _stage(rk4_point(x0, hs, k1), three_state, qa)
    k2 = rates(tire, x2, u0, p, tc)
    x3 = _stage(rk4_point(x0, hs, k2), three_state, qa)
    k3 = rates(tire, x3, u0, p, tc)
    x4 = _stage(rk4_point(x0, dt, k3), three_state, qb)
    k4 = rates(tire, x4, u0, p, tc)
    return rk4_update(x0, h6, k1, k2, k3, k4), x2[1], x3[1], x4[1]


@_inline
def _step_end(st, l, x0, xn, theta, w234, three_state, qb, h6, q_max):
    """Lane l after its step from x0 = (v, w, q, r) to xn (the wheel speed floored at 0, the
    pressure clipped, or the valves' exact one) and its wheel angle (RK4 on the stage speeds
    w234); keeps the step's start for `step_metrics`."""
    v, w, _, r = x0
    vn, wn, qn, rn = xn
    st[R_V_START * LANES + l] = v
    st[R_THETA0 * LANES + l] = theta
    st[R_W0 * LANES + l] = w
    st[R_V * LANES + l] = vn
    st[R_W * LANES + l] = fmax(wn, 0.0)
    st[R_Q * LANES + l] = select(three_state, qb, clip(qn, 0.0, q_max))
    st[R_R * LANES + l] = select(three_state, r, rn)
    st[R_THETA * LANES + l] = rk4_update(theta, h6, w, w234[0], w234[1], w234[2])


@_inline
def plant_step(st, l, tire, three_state, dt, hs, h6, tc, kb, kd):
    """One RK4 step of lane l from t = k dt under its held command (`_rk4_stages`) and its
    wheel angle. Straight-line code, a body of the vector loop."""
    x0, pr, u0, qa, qb, theta = _step_start(st, l, dt, hs, kb, kd)
    s1 = st[R_S1 * LANES + l]
    xn, w2, w3, w4 = _rk4_stages(
        _rates_at, _rates, tire, x0, s1, u0, pr, tc, three_state, dt, hs, h6, qa, qb
    )
    _step_end(st, l, x0, xn, theta, (w2, w3, w4), three_state, qb, h6, pr[7])


@_inline
def lagged_plant_step(st, l, tire, three_state, dt, hs, h6, tc, kb, kd):
    """`plant_step` with the tire's lagged slip S' a fifth state (row R_LAG,
    `_lagged_rates_at`; its tire law tc[8], `tire` unused)."""
    x0, pr, u0, qa, qb, theta = _step_start(st, l, dt, hs, kb, kd)
    xl = x0 + (st[R_LAG * LANES + l],)  # noqa: RUF005 (numba)
    p_sigma = (pr, st[R_SIGMA * LANES + l])
    s1 = st[R_S1 * LANES + l]
    xn, w2, w3, w4 = _rk4_stages(
        _lagged_rates_at,
        _lagged_rates,
        tire,
        xl,
        s1,
        u0,
        p_sigma,
        tc,
        three_state,
        dt,
        hs,
        h6,
        qa,
        qb,
    )
    _step_end(st, l, x0, xn[:4], theta, (w2, w3, w4), three_state, qb, h6, pr[7])
    st[R_LAG * LANES + l] = xn[4]


@_inline
def step_metrics(st, l, dt, n_steps, t_timeout, live):
    """The metrics of lane l's step just taken (the ideal kernel's quadrature; the slip
    objectives and the lock before the cut-out only), its end flags and whether a valve
    switches inside its next step (`switch_within`; a tick redoes it after a new pulse).
    Straight-line code, a body of the vector loop; returns 1 if a live lane ended."""
    v, vn, wn, qn, rn = (
        st[R_V_START * LANES + l],
        st[R_V * LANES + l],
        st[R_W * LANES + l],
        st[R_Q * LANES + l],
        st[R_R * LANES + l],
    )
    r_w, v_stop, target = st[R_RW * LANES + l], st[R_VSTOP * LANES + l], st[R_TARGET * LANES + l]
    k = st[R_STEP * LANES + l]
    t = k * dt
    working = st[R_CUT * LANES + l] == 0.0  # not cut out
    active = select(working, 1.0, 0.0)
    slip = st[R_SLIP * LANES + l]
    s_raw, s_new, stop, h, s_end = step_end(v, vn, wn, r_w, v_stop, slip, dt)
    dist = st[R_DIST * LANES + l] + trapezoid(v, select(stop, v_stop, vn), h)
    d_iae, d_itae, d_ise = error_integrals(target - slip, target - s_end, t, h)
    st[R_IAE * LANES + l] += active * d_iae
    itae = st[R_ITAE * LANES + l] + active * d_itae
    st[R_ISE * LANES + l] += active * d_ise
    st[R_ECU_IAE * LANES + l] += active * h * abs(target - st[R_ECU_SLIP * LANES + l])
    st[R_SINT * LANES + l] += trapezoid(slip, s_end, h)
    st[R_CLIP * LANES + l] = fmax(st[R_CLIP * LANES + l], abs(s_raw - s_new))
    st[R_MINSLIP * LANES + l] = fmin(st[R_MINSLIP * LANES + l], s_raw)
    st[R_PEAK * LANES + l] = fmax(st[R_PEAK * LANES + l], s_new)
    st[R_QLO * LANES + l] = fmin(st[R_QLO * LANES + l], qn)
    st[R_QHI * LANES + l] = fmax(st[R_QHI * LANES + l], qn)
    v_lo, v_hi = LOW_SPEED_BAND_M_S
    low = working & (v_lo < vn) & (vn < v_hi)
    low_err = st[R_LOW_ERR * LANES + l]
    st[R_LOW_ERR * LANES + l] = select(low, fmax(low_err, abs(target - s_new)), low_err)
    locked = working & (vn > v_stop) & (wn * r_w < st[R_LOCK_RATIO * LANES + l] * vn)
    st[R_LOCKED * LANES + l] += select(locked, dt, 0.0)
    lock_t = st[R_LOCK_T * LANES + l]
    st[R_LOCK_T * LANES + l] = select(locked & (lock_t != lock_t), t + dt, lock_t)

    check = vn + wn + qn + rn + itae + st[R_CMD * LANES + l]
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
    st[R_STOP * LANES + l] = select(stop, 1.0, 0.0)
    st[R_H * LANES + l] = h
    st[R_SLIP * LANES + l] = s_new
    st[R_S1 * LANES + l] = s_new  # wheel_slip(vn, wn, r_w)
    st[R_ITAE * LANES + l] = itae
    st[R_DIST * LANES + l] = dist
    st[R_STEP * LANES + l] = k + 1.0
    st[R_QSWITCH * LANES + l] = switch_within(st, l, (k + 1.0) * dt, dt)
    return ended & (l < live)


_NO_NRT: dict[str, Any] = {"_nrt": False}
"""No reference counting (module docstring); numba's stubs omit the flag."""


@functools.cache
def _plant_steps_of(tire: int, lagged: bool = False) -> Any:
    """The vector loop of `plant_step` over lanes 0 .. width - 1 (a whole number of vectors)
    with the tire law `tire` (a constant inside: numba freezes a closure's variables), or of
    `lagged_plant_step` (`lagged`: the tire law the last of the tire tuple, at run time),
    compiled as a function of its own, once per entry point compilation (not cached: the entry
    point's cache holds it). step = (dt, dt / 2, dt / 6, tire data, kb, kd)."""
    step_of = lagged_plant_step if lagged else plant_step

    def plant_steps(st, width, three_state, step):
        dt, hs, h6, tc_of_caller, kb, kd = step
        own = local_table(tc_of_caller[:7]) + (local_poly(tc_of_caller[7]),)  # noqa: RUF005
        tc = own + tc_of_caller[8:]
        for b in range(width // VECTOR):
            for j in range(VECTOR):
                step_of(st, b * VECTOR + j, tire, three_state, dt, hs, h6, tc, kb, kd)

    plant_steps.__qualname__ = "lagged_plant_steps" if lagged else f"plant_steps_tire_law_{tire}"
    return njit(nogil=True, error_model="numpy", **_NO_NRT)(plant_steps)


@njit(cache=True, nogil=True, error_model="numpy", **_NO_NRT)
def _metric_steps(st, width, live, dt, n_steps, t_timeout):
    """The vector loop of `step_metrics` over lanes 0 .. width - 1 (the same for every tire
    law: compiled once); 1 if a live lane ended."""
    any_end = False
    for b in range(width // VECTOR):
        for j in range(VECTOR):
            any_end |= step_metrics(st, b * VECTOR + j, dt, n_steps, t_timeout, live)
    return any_end


_BILINEAR_STEPS, _BURCKHARDT_STEPS, _TABLE_STEPS, _MAGIC_FORMULA_STEPS = (
    _plant_steps_of(k) for k in (KIND_BILINEAR, KIND_BURCKHARDT, KIND_TABLE, KIND_MAGIC_FORMULA)
)
_LAGGED_STEPS = _plant_steps_of(-1, lagged=True)
"""Every tire law's, with the lagged slip: one loop, not one per tire law, for compile time."""


EDGE_FIELDS = ("lane", "k", "advance", "dtheta", "w0", "w1", "s", "lo", "hi", "done")
"""Rows of the scratch `edges` (an edge crossed in a step, one per column; `sensor_edges`)."""
E_LANE, E_K, E_ADVANCE, E_DTHETA, E_W0, E_W1, E_S, E_LO, E_HI, E_DONE = range(len(EDGE_FIELDS))
EDGE_COLUMNS = 2 * LANES
"""Columns of `edges` (a lane's step keeps at most its last two edges, `edges_passed`): row f
of column i at f * EDGE_COLUMNS + i, a flat array whose rows sit at constant distances, so
that the crossing search's loop over the columns vectorizes (as the lane loops over `st`)."""


@_inline
def _lane_edges(st, l, teeth, spacing, edges, n):
    """Append lane l's edges that matter in its last step (`edges_passed`) to `edges` from
    column n, each with the start of its crossing search; the new column count. Without one,
    the lane's sensor is settled here as `sensor_step` settles it."""
    theta0, theta1 = st[R_THETA0 * LANES + l], st[R_THETA * LANES + l]
    w0, w1 = st[R_W0 * LANES + l], st[R_W * LANES + l]
    k, k_end = E.edges_passed(int(st[R_KNEXT * LANES + l]), theta1, teeth, spacing)
    if k > k_end:
        _settle_sensor(st, l, k_end, teeth, spacing)
    while k <= k_end:
        target = E.edge_angle(k, teeth, spacing)
        s, lo, hi, done, advance, dtheta = E.crossing_start(target, theta0, theta1)
        item = (
            float(l),
            float(k),
            advance,
            dtheta,
            w0,
            w1,
            s,
            lo,
            hi,
            select(done, 1.0, 0.0),
        )
        for f in range(len(EDGE_FIELDS)):
            edges[f * EDGE_COLUMNS + n] = item[f]
        n += 1
        k += 1
    return n


@_inline
def _settle_sensor(st, l, k_end, teeth, spacing):
    """Lane l's sensor after its last edge k_end of the step: the next edge, the estimate."""
    st[R_KNEXT * LANES + l] = k_end + 1
    st[R_EDGE_NEXT * LANES + l] = E.edge_angle(k_end + 1, teeth, spacing)
    st[R_WEST * LANES + l] = E.period_estimate(
        st[R_TLAST * LANES + l], st[R_TPREV * LANES + l], st[R_WEST * LANES + l], teeth
    )


@_inline
def _search_crossings(edges, n, dt):
    """`crossing_fraction` of the n edges in `edges`, in lockstep (`crossing_iteration`,
    branch-free: a vector loop over the edges in whole vectors, the columns after the n-th
    zeros marked done), until every search is done."""
    width = -(-n // VECTOR) * VECTOR
    for i in range(n, width):
        for f in range(len(EDGE_FIELDS)):
            edges[f * EDGE_COLUMNS + i] = 0.0
        edges[E_DONE * EDGE_COLUMNS + i] = 1.0
    for _ in range(E.CROSSING_ITERATIONS):
        busy = False
        for i in range(width):
            s, lo, hi, done = E.crossing_iteration(
                edges[E_S * EDGE_COLUMNS + i],
                edges[E_LO * EDGE_COLUMNS + i],
                edges[E_HI * EDGE_COLUMNS + i],
                edges[E_DONE * EDGE_COLUMNS + i] != 0.0,
                edges[E_ADVANCE * EDGE_COLUMNS + i],
                edges[E_DTHETA * EDGE_COLUMNS + i],
                edges[E_W0 * EDGE_COLUMNS + i],
                edges[E_W1 * EDGE_COLUMNS + i],
                dt,
            )
            edges[E_S * EDGE_COLUMNS + i] = s
            edges[E_LO * EDGE_COLUMNS + i] = lo
            edges[E_HI * EDGE_COLUMNS + i] = hi
            edges[E_DONE * EDGE_COLUMNS + i] = select(done, 1.0, 0.0)
            busy |= not done
        if not busy:
            return


@_inline
def sensor_edges(st, live, dt, x, spacing, jitter, edges):
    """The toothed sensor over the last step of every live lane whose wheel passed its next
    edge (docs/ecu.md, Toothed-wheel sensor; `sensor_step`, which holds everything otherwise,
    in its pieces): the edges that matter, their crossings searched in lockstep across the
    lanes, then each lane's captures in edge order and its estimate."""
    teeth = int(x[X_TEETH])
    n = 0
    for l in range(live):
        passed = st[R_THETA * LANES + l] >= st[R_EDGE_NEXT * LANES + l]
        if st[R_ENDED * LANES + l] == 0.0 and passed:
            n = _lane_edges(st, l, teeth, spacing, edges, n)
    _search_crossings(edges, n, dt)
    for i in range(n):
        l = int(edges[E_LANE * EDGE_COLUMNS + i])
        k = int(edges[E_K * EDGE_COLUMNS + i])
        t0 = (st[R_STEP * LANES + l] - 1.0) * dt
        s = edges[E_S * EDGE_COLUMNS + i]
        st[R_TPREV * LANES + l] = st[R_TLAST * LANES + l]
        st[R_TLAST * LANES + l] = E.edge_capture(t0, s, dt, k, x[X_TIMER], jitter)
        if i == n - 1 or edges[E_LANE * EDGE_COLUMNS + i + 1] != l:  # the lane's last edge
            _settle_sensor(st, l, k, teeth, spacing)


@inlined
def _fill_lane(st, l, aux, p, x, spacing):
    """Start a candidate with plant row p in lane l: the initial state, zero metrics."""
    r = st[l::LANES]  # lane l's rows
    r[:] = 0.0
    aux[l, :] = 0.0
    r_w, v0 = p[P_RADIUS], p[P_V0]
    r[R_V] = v0
    r[R_W] = v0 / r_w
    r[R_S1] = wheel_slip(v0, r[R_W], r_w)
    r[R_WEST] = v0 / r_w
    for row in (R_TLAST, R_TPREV, R_READ_LAST, R_READ_PREV):
        r[row] = -1.0
    r[R_VREF] = v0
    r[R_VW_PREV] = v0
    r[R_VW] = v0
    r[R_W_PREV] = v0 / r_w
    if x[X_TOOTHED] != 0.0:
        teeth = int(x[X_TEETH])
        k_next = E.sensor_first_edge(0.0, teeth, spacing)
        r[R_KNEXT] = k_next
        r[R_EDGE_NEXT] = E.edge_angle(k_next, teeth, spacing)
    else:
        r[R_EDGE_NEXT] = np.inf
    for row in (R_PM0, R_PM1, R_VALVE):
        r[row] = E.VALVE_HOLD
    r[R_LAST_CHANGE] = np.nan
    r[R_MIN_IV] = np.inf
    r[R_LOCK_T] = np.nan
    r[R_CUT_T] = np.nan
    r[R_RW] = r_w
    r[R_FZ] = p[P_LOAD] * p[P_MASS] * p[P_G]
    r[R_INV_M] = 1.0 / p[P_MASS]
    r[R_INV_I] = 1.0 / p[P_INERTIA]
    r[R_KQ] = p[P_KQ]
    r[R_GAIN] = p[P_K]
    r[R_INV_TAU] = 1.0 / p[P_TAU]
    r[R_QMAX] = p[P_QMAX]
    r[R_V0] = v0
    r[R_VSTOP] = p[P_VSTOP]
    r[R_TARGET] = p[P_TARGET]
    r[R_LOCK_RATIO] = p[P_LOCK_RATIO]
    r[R_HOPELESS] = p[P_HOPELESS_M]
    r[R_LAG] = r[R_S1]
    r[R_SIGMA] = p[P_SIGMA]


@inlined
def _finish_lane(st, l, out_row, ts, x):
    """Write the metrics row of the run that ended in lane l (three-state valves: the last
    pulse's changes up to the end of the run first)."""
    r = st[l::LANES]  # lane l's rows
    if x[X_VALVES] != 0.0:
        _account_pulse(st, l, ts, r[R_TEND])
    write_metrics(
        out_row,
        (r[R_STATUS], r[R_TEND], r[R_DIST], r[R_LOCK_T]),
        (r[R_IAE], r[R_ITAE], r[R_ISE], r[R_SINT]),
        (r[R_PEAK], r[R_LOCKED], r[R_CLIP], r[R_MINSLIP]),
    )
    for j in range(N_ECU_METRICS):  # the ECU's, in METRICS order (EL.LANE keeps it)
        out_row[M_ECU_IAE + j] = r[R_ECU_IAE + j]


@inlined
def _write_trace(trace_row, st, dt, tire, tc, x):
    """The trace row of lane 0's last step."""
    r = st[0::LANES]  # lane 0's rows
    t = (r[R_STEP] - 1.0) * dt
    vn, wn, qn, s_new = r[R_V], r[R_W], r[R_Q], r[R_SLIP]
    write_trace_row(
        trace_row,
        t + r[R_H],
        max(vn, r[R_VSTOP]) if r[R_STOP] != 0.0 else vn,
        wn * r[R_RW],
        s_new,
        r[R_TARGET],
        qn,
        r[R_KQ] * qn,
        r[R_CMD],
        r[R_DIST],
        _friction(st, 0, tire, tc),
    )
    trace_row[T_VREF] = r[R_VREF]
    trace_row[T_WEST] = r[R_VW]
    trace_row[T_ECU_SLIP] = r[R_ECU_SLIP]
    trace_row[T_VALVE] = (
        E.valve_mode_at(t + dt, r[R_PM0], r[R_PS0], r[R_PO0], r[R_PM1], r[R_PS1], r[R_PO1])
        if x[X_VALVES] != 0.0
        else 0.0
    )
    trace_row[T_EDGE_PREV] = r[R_READ_PREV]
    trace_row[T_EDGE_LAST] = r[R_READ_LAST]


@inlined
def _first_trace_row(trace_row, v0, target):
    """The trace row at t = 0."""
    trace_row[:] = 0.0
    trace_row[T_V] = v0
    trace_row[T_WHEEL_V] = v0
    trace_row[T_TARGET] = target
    trace_row[T_VREF] = v0
    trace_row[T_WEST] = v0
    trace_row[T_EDGE_PREV] = -1.0
    trace_row[T_EDGE_LAST] = -1.0


def _simulate(
    laws_key,
    tire,
    lp,
    plant,
    x,
    coef,
    xc_tuple,
    xs_tuple,
    ys_tuple,
    poly,
    table,
    grid,
    spacing,
    jitter,
    acc_noise,
    trace,
    out,
    st,
    lane_of,
    aux,
    edges,
):
    """The lane loop (module docstring): candidate i runs law parameters lp[i] on plant row
    min(i, rows - 1), with the ECU vector x, on the tire of law `tire` with coefficients coef,
    table nodes (xc, xs, ys) and Magic Formula polynomial poly."""
    xc = stack_copy(xc_tuple)
    xs = stack_copy(xs_tuple)
    ys = stack_copy(ys_tuple)
    tc = (coef[0], coef[1], coef[2], coef[3], xc, xs, ys, poly)
    n = lp.shape[0]
    p0 = plant[0]
    dt = p0[P_DT]
    hs = 0.5 * dt
    h6 = dt / 6.0
    n_steps = math.ceil(p0[P_TMAX] / dt - 1e-9)
    t_timeout = n_steps * dt
    m = int(x[X_M])
    ts = m * dt
    three_state = x[X_VALVES] != 0.0
    toothed = x[X_TOOTHED] != 0.0
    step = (dt, hs, h6, tc, x[X_KB], x[X_KD])
    lagged = p0[P_SIGMA] > 0.0
    lagged_step = (dt, hs, h6, tc + (tire,), x[X_KB], x[X_KD])  # noqa: RUF005 (numba)
    n_plant = plant.shape[0]
    st[:] = 0.0
    lane_of[:] = -1
    live = min(n, LANES)
    for l in range(live):
        _fill_lane(st, l, aux, plant[min(l, n_plant - 1)], x, spacing)
        lane_of[l] = l
    queued = live
    n_trace = trace.shape[0]
    rows = 1
    if n_trace > 0:
        _first_trace_row(trace[0], p0[P_V0], p0[P_TARGET])
    while live > 0:
        for l in range(live):
            k = st[R_STEP * LANES + l]
            t = k * dt
            if k == st[R_TICK * LANES + l] * m:
                base = lp[lane_of[l]]
                _tick(st, l, aux[l], base, x, ts, t, tire, tc, table, grid, acc_noise, laws_key)
                if three_state:
                    valve_switches(st, l, t, hs, dt, x)
            elif three_state and st[R_QSWITCH * LANES + l] != 0.0:
                switch_pressures(st, l, t, hs, dt, x)
        width = -(-live // VECTOR) * VECTOR
        if lagged:
            _LAGGED_STEPS(st, width, three_state, lagged_step)
        elif tire == KIND_BILINEAR:  # one vector loop per tire law, each a function of its own
            _BILINEAR_STEPS(st, width, three_state, step)
        elif tire == KIND_BURCKHARDT:
            _BURCKHARDT_STEPS(st, width, three_state, step)
        elif tire == KIND_MAGIC_FORMULA:
            _MAGIC_FORMULA_STEPS(st, width, three_state, step)
        else:
            _TABLE_STEPS(st, width, three_state, step)
        ended = _metric_steps(st, width, live, dt, n_steps, t_timeout)
        if toothed:
            sensor_edges(st, live, dt, x, spacing, jitter, edges)
        if n_trace > 0 and rows < n_trace:  # one candidate, in lane 0
            _write_trace(trace[rows], st, dt, tire, tc, x)
            rows += 1
        if ended:
            for l in range(live - 1, -1, -1):  # high to low: lanes moved down are done
                if st[R_ENDED * LANES + l] == 0.0:
                    continue
                _finish_lane(st, l, out[lane_of[l]], ts, x)
                if queued < n:
                    _fill_lane(st, l, aux, plant[min(queued, n_plant - 1)], x, spacing)
                    lane_of[l] = queued
                    queued += 1
                else:
                    last = live - 1
                    live = close_lane(st, l, live, lane_of, N_ROWS, LANES)
                    for j in range(aux.shape[1]):
                        aux[l, j] = aux[last, j]
    if n_trace > 0:
        out[0, M_NTRACE] = rows


_simulate = njit(cache=True, nogil=True, error_model="numpy", **_NO_NRT)(_simulate)


def _entry_point(laws_key):
    """The cached entry point for the registered control laws named by `laws_key`
    (`controllers.laws.registry.fingerprint`, as an integer: a closure variable, on which numba
    keys the disk cache; the law dispatch is generated from the registry when it compiles)."""

    def simulate_abs_wheel_ecu(
        tire,
        lp,
        plant,
        x,
        coef,
        xc,
        xs,
        ys,
        poly,
        table,
        grid,
        spacing,
        jitter,
        acc_noise,
        trace,
        out,
        st,
        lane_of,
        aux,
        edges,
    ):
        _simulate(
            laws_key,
            tire,
            lp,
            plant,
            x,
            coef,
            xc,
            xs,
            ys,
            poly,
            table,
            grid,
            spacing,
            jitter,
            acc_noise,
            trace,
            out,
            st,
            lane_of,
            aux,
            edges,
        )

    simulate_abs_wheel_ecu.__doc__ = _simulate.__doc__
    return njit(cache=True, nogil=True, error_model="numpy", **_NO_NRT)(simulate_abs_wheel_ecu)


entry_point = laws.per_fingerprint(_entry_point)
"""The compiled loop for the laws registered now."""


def simulate_abs_wheel_ecu(
    law_params: np.ndarray,
    plant: np.ndarray,
    ecu: np.ndarray,
    tire_kind: int,
    tire_coef: np.ndarray,
    tire_xs: np.ndarray,
    tire_ys: np.ndarray,
    table: np.ndarray,
    grid: np.ndarray,
    noise: tuple[np.ndarray, np.ndarray, np.ndarray],
    trace: np.ndarray,
    out: np.ndarray,
) -> None:
    """Simulate every row of `law_params` (n, P: the discrete law's parameter vector, in
        its `DiscreteLaw.params` order; one column, unused, for none and bang-bang), with the law
    of the registry's kind in `ecu` (`controllers.laws.kind`).

        `plant`: PLANT rows (1 or n; dt_s and t_max_s of row 0 for all); `ecu`: the ECU vector
        (`abs_wheel_ecu_layout.pack_ecu`); `tire_*`: `TireCurve.kernel_data()`; (table, grid): the
        ECU lookup table of a fuzzy law (`discrete.ecu_table`) or `discrete.no_table()`; `noise`:
        (spacing_rad, jitter_s, accel_noise_m_s2) of `EcuNoise`. Writes one ECU_METRICS row per
        candidate into `out`; when `trace` has rows (n must be 1), the ECU_TRACE rows too.
    """
    law = laws.by_kind(int(ecu[X_LAW]))
    if law.ecu is None:
        raise ValueError(f"control law {law.name!r} has no form in the realistic ECU")
    coef4, xc, xs, ys, poly = tire_arguments(tire_kind, tire_coef, tire_xs, tire_ys)
    rows = np.ascontiguousarray(np.atleast_2d(plant), dtype=np.float64)
    lagged = rows[:, P_SIGMA] > 0.0
    if lagged.any() and not lagged.all():
        raise ValueError("relaxation_length_m must be 0 in every plant row or in none")
    lp = np.ascontiguousarray(law_params, dtype=np.float64)
    aux_width = D.N_STATE + lp.shape[1] + ECU_INPUTS + max(int(ecu[X_DELAY]), 1)
    entry_point()(
        tire_kind,
        lp,
        rows,
        ecu,
        coef4,
        xc,
        xs,
        ys,
        poly,
        table,
        grid,
        *noise,
        trace,
        out,
        np.empty(N_ROWS * LANES),
        np.empty(LANES, dtype=np.int64),
        np.empty((LANES, aux_width)),
        np.empty(len(EDGE_FIELDS) * EDGE_COLUMNS),
    )


__all__ = ["LANES", "LOW_SPEED_BAND_M_S", "simulate_abs_wheel_ecu"]
