"""Compiled closed loop of the single-wheel ABS with an ECU-realistic controller
(docs/ecu.md), over a population, one candidate after the other (no lanes).

Plant: the ideal kernel's (`sim.abs_wheel_model.wheel_rates`, `sim.abs_wheel_tires`), RK4 at
the fixed step dt (`sim.integrate`), plus the wheel angle (dtheta/dt = w, RK4 on the stage
speeds) for the toothed sensor. With three-state valves the pressure is not integrated: it is
the exact orifice solution (`controllers.ecu.modulator_advance`) at the stage times.

ECU tick every ecu_ts_s = m dt (before the step at t = k dt, k % m == 0), in this order:
sensor read (true wheel speed, or the toothed wheel's last edge period, held or bounded),
reference speed (true, slew-limited or accelerometer), ECU slip (vref - w_est R) / vref in
[0, 1], cut-out latch, speed schedule (kp, kd times max(vref / v0, floor)), the DISCRETE law of
`controllers.discrete` (the one `export` ships; none and bang-bang as in the ideal kernel), the
delay line (the command of tick j applied at tick j + delay), then the actuator: continuous (the
held command u into K/(s(Ts+1))) or a valve pulse (`duty_pulse` for the PID laws' pressure rate
K u, `switching_pulse` for the switching laws; the driver's demand after the cut-out).
The toothed sensor advances after each step (`sensor_step` on the step's Hermite interpolant).

Metrics: the ideal kernel's slots (same quadrature), the slip integrals and the lock time
counting only before the cut-out; distance and time to v_stop; plus the ECU's (`ECU_METRICS`).
Each candidate is simulated on its own: row i of a population is bitwise the run of candidate i
alone.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from chassistune._branchfree import clip
from chassistune.controllers import discrete as D
from chassistune.controllers import ecu as E
from chassistune.controllers.switching import bang_bang_command
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
    tire_mu,
    write_metrics,
    write_trace_row,
)
from chassistune.sim.abs_wheel_model import step_end, wheel_rates, wheel_slip
from chassistune.sim.abs_wheel_tires import KIND_TABLE, table_tuples
from chassistune.sim.integrate import (
    error_integrals,
    rk4_point,
    rk4_update,
    trapezoid,
)

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

LAW_NONE, LAW_PID, LAW_FUZZY_PID, LAW_IMMUNE, LAW_THRESHOLD, LAW_BANGBANG = (
    EL.LAW_KINDS.index(n) for n in EL.LAW_KINDS
)

# the ideal kernel's metric and trace slots come first, at the same columns (ECU layouts)
M_ECU_IAE = EL.METRICS["ecu_slip_iae"]
if len(KL.METRICS) != M_ECU_IAE:  # pragma: no cover
    raise RuntimeError("the ECU metrics must follow the ideal kernel's")
T_VREF, T_WEST, T_ECU_SLIP, T_VALVE, T_EDGE_PREV, T_EDGE_LAST = (
    EL.TRACE[n] for n in EL.TRACE.names[len(KL.TRACE) :]
)

LOW_SPEED_BAND_M_S = (1.0, 9.0)
"""Speed band of `low_speed_slip_error` (fixed gains fail below about 9 m/s)."""

_jit = njit(cache=True, nogil=True, error_model="numpy")


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _rates(law, x, u, p, tire):
    """Derivatives of x = (v, w, q, r) of the wheel under the held command u, with the plant
    p = (r_w, fz, inv_m, inv_i, kq, gain, inv_tau, q_max) and the tire (c0 .. c3, xc, xs, ys)."""
    v, w, q, r = x
    r_w, fz, inv_m, inv_i, kq, gain, inv_tau, q_max = p
    fx = tire_mu(law, wheel_slip(v, w, r_w), tire) * fz
    dv, dw, dq, dr, _, _ = wheel_rates(w, q, r, fx, u, r_w, inv_m, inv_i, kq, gain, inv_tau, q_max)
    return dv, dw, dq, dr


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _stage(y, three_state, q):
    """The stage point y = (v, w, q, r), with three-state valves at the exact pressure q."""
    return (y[0], y[1], q if three_state else y[2], y[3])


@_jit
def _scheduled(kind, base, params, f):
    """Write the law's parameters into `params` with kp and kd (or their table scales) times f."""
    params[:] = base
    if kind == LAW_PID:
        params[D.PID_KP] = base[D.PID_KP] * f
        params[D.PID_KD] = base[D.PID_KD] * f
    elif kind == LAW_FUZZY_PID:
        params[D.FP_KP0] = base[D.FP_KP0] * f
        params[D.FP_KUP] = base[D.FP_KUP] * f
        params[D.FP_KD0] = base[D.FP_KD0] * f
        params[D.FP_KUD] = base[D.FP_KUD] * f
    elif kind == LAW_IMMUNE:
        params[D.IM_K] = base[D.IM_K] * f
        params[D.IM_KD] = base[D.IM_KD] * f


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


@_jit
def _run(tire, lp, p, x, tc, table, grid, spacing, jitter, acc_noise, trace, out):
    """One stop of one candidate (law parameters `lp`, plant row `p`, ECU vector `x`) on the
    tire of law `tire` with coefficients and nodes tc = (c0, c1, c2, c3, xc, xs, ys)."""
    kind = int(x[X_LAW])
    m = int(x[X_M])
    delay = int(x[X_DELAY])
    toothed = x[X_TOOTHED] != 0.0
    teeth = int(x[X_TEETH])
    bound = x[X_BOUND] != 0.0
    vref_mode = int(x[X_VREF])
    three_state = x[X_VALVES] != 0.0
    kb, kdv, dead, min_on = x[X_KB], x[X_KD], x[X_DEAD], x[X_MINON]
    amp = x[X_AMP]
    r_w, v0, gain = p[P_RADIUS], p[P_V0], p[P_K]
    fz = p[P_LOAD] * p[P_MASS] * p[P_G]
    inv_m, inv_i, inv_tau = 1.0 / p[P_MASS], 1.0 / p[P_INERTIA], 1.0 / p[P_TAU]
    kq, q_max, v_stop, target = p[P_KQ], p[P_QMAX], p[P_VSTOP], p[P_TARGET]
    dt = p[P_DT]
    hs = 0.5 * dt
    h6 = dt / 6.0
    ts = m * dt
    n_steps = math.ceil(p[P_TMAX] / dt - 1e-9)
    t_timeout = n_steps * dt
    v_lo, v_hi = LOW_SPEED_BAND_M_S
    pr = (r_w, fz, inv_m, inv_i, kq, gain, inv_tau, q_max)

    state = np.zeros(D.N_STATE)
    params = lp.copy()
    inputs = np.zeros(3)
    line = np.zeros(max(delay, 1))
    v, w, theta, q, r = v0, v0 / r_w, 0.0, 0.0, 0.0
    k_next = E.sensor_first_edge(0.0, teeth, spacing) if toothed else 0
    t_last, t_prev, w_est = -1.0, -1.0, v0 / r_w
    read_last, read_prev = -1.0, -1.0  # the edge times behind the estimate read at the tick
    vref, vw_prev, vw, slip_ecu, held = v0, v0, v0, 0.0, 0
    cut = False
    u0, cmd, resid = 0.0, 0.0, 0.0
    pm0, ps0, po0 = E.VALVE_HOLD, 0.0, 0.0  # previous pulse: mode, start, on-time
    pm1, ps1, po1 = E.VALVE_HOLD, 0.0, 0.0  # current pulse
    valve, last_change, n_sw, min_iv = E.VALVE_HOLD, np.nan, 0.0, np.inf
    slip = 0.0
    dist = iae = itae = ise = sint = ecu_iae = 0.0
    clip_max, min_slip, peak, locked_s = 0.0, 0.0, 0.0, 0.0
    lock_t, cut_t, gap, q_lo, q_hi, low_err = np.nan, np.nan, 0.0, 0.0, 0.0, 0.0
    status, t_end = STATUS_TIMEOUT, t_timeout
    n_trace = trace.shape[0]
    rows = 1
    if n_trace > 0:
        trace[0, :] = 0.0
        trace[0, T_V] = v0
        trace[0, T_WHEEL_V] = v0
        trace[0, T_TARGET] = target
        trace[0, T_VREF] = v0
        trace[0, T_WEST] = v0
        trace[0, T_EDGE_PREV] = -1.0
        trace[0, T_EDGE_LAST] = -1.0
    tick = 0
    for k in range(n_steps):
        t = k * dt
        if k % m == 0:
            wr = E.sensor_read(w_est, t_last, t, teeth, bound) if toothed else w
            read_last, read_prev = t_last, t_prev
            vw = wr * r_w
            a_wheel = (vw - vw_prev) / ts if tick > 0 else 0.0
            vw_prev = vw
            if vref_mode == 0:
                vref = v
            elif vref_mode == 1:
                vref = E.vref_slew(vref, vw, x[X_AMAX], ts)
            elif tick > 0:
                a_true = -tire_mu(tire, wheel_slip(v, w, r_w), tc) * fz * inv_m
                a_meas = E.accelerometer(a_true, x[X_BIAS], acc_noise[tick % acc_noise.shape[0]])
                vref, held = E.vref_accel(
                    vref,
                    vw,
                    a_wheel,
                    a_meas,
                    ts,
                    x[X_AGREE],
                    x[X_AGREE_A],
                    q <= x[X_PFREE],
                    held,
                    x[X_ANCHOR],
                )
            slip_ecu = wheel_slip(vref, wr, r_w)
            was_cut = cut
            cut = E.cutout_latch(cut, vref, x[X_CUTOUT])
            if cut and not was_cut:
                cut_t = t
            if not cut:
                gap = max(gap, abs(v - vref))
                f = E.speed_schedule(vref, v0, x[X_FLOOR]) if x[X_SCHED] != 0.0 else 1.0
                _scheduled(kind, lp, params, f)
                inputs[0] = slip_ecu
                if kind == LAW_THRESHOLD:
                    inputs[1] = wr
                else:
                    inputs[1] = 1.0 if q >= q_max else 0.0
                    inputs[2] = 1.0 if q <= 0.0 else 0.0
                if kind == LAW_NONE:
                    u = amp
                elif kind == LAW_BANGBANG:
                    u = bang_bang_command(target - slip_ecu, amp)
                else:
                    u = D.discrete_step(kind, state, inputs, params, table, grid)
            else:
                u = amp
            cmd = u
            if delay > 0:
                cmd = line[tick % delay]
                line[tick % delay] = u
            if cut:
                cmd = amp
            if not three_state:
                u0 = cmd
            else:
                if cut:
                    mode, on = E.VALVE_BUILD, ts
                elif LAW_PID <= kind <= LAW_IMMUNE:  # the PID laws: a pressure rate
                    mode, on, resid = E.duty_pulse(
                        gain * cmd, resid, q, ts, kb, kdv, q_max, 0.0, min_on
                    )
                else:
                    mode, on = E.switching_pulse(cmd, amp, ts, min_on)
                # the retiring pulse's state changes, then the new pulse's
                if tick > 0:
                    valve, last_change, n_sw, min_iv = _retire_pulse(
                        pm1, ps1, po1, ts, np.inf, valve, last_change, n_sw, min_iv
                    )
                pm0, ps0, po0 = pm1, ps1, po1
                pm1, ps1, po1 = mode, t + dead, on
            tick += 1

        # one RK4 step (u0 held; three-state: the exact pressure at the stage times)
        if three_state:
            qa = E.modulator_advance(q, t, hs, pm0, ps0, po0, pm1, ps1, po1, kb, kdv, q_max, 0.0)
            qb = E.modulator_advance(q, t, dt, pm0, ps0, po0, pm1, ps1, po1, kb, kdv, q_max, 0.0)
        else:
            qa = qb = q
        x0 = (v, w, q, r)
        k1 = _rates(tire, x0, u0, pr, tc)
        x2 = _stage(rk4_point(x0, hs, k1), three_state, qa)
        k2 = _rates(tire, x2, u0, pr, tc)
        x3 = _stage(rk4_point(x0, hs, k2), three_state, qa)
        k3 = _rates(tire, x3, u0, pr, tc)
        x4 = _stage(rk4_point(x0, dt, k3), three_state, qb)
        k4 = _rates(tire, x4, u0, pr, tc)
        vn, wn, qn, rn = rk4_update(x0, h6, k1, k2, k3, k4)
        wn = max(wn, 0.0)
        if three_state:
            qn = qb
            rn = r
        else:
            qn = clip(qn, 0.0, q_max)
        if toothed:
            theta_n = rk4_update(theta, h6, w, x2[1], x3[1], x4[1])
            k_next, t_last, t_prev, w_est = E.sensor_step(
                theta,
                theta_n,
                w,
                wn,
                t,
                dt,
                k_next,
                t_last,
                t_prev,
                w_est,
                teeth,
                x[X_TIMER],
                spacing,
                jitter,
            )
            theta = theta_n

        # metrics (the ideal kernel's quadrature); slip objectives and lock end at the cut-out
        active = 0.0 if cut else 1.0
        s_raw, s_new, stop, h, s_end = step_end(v, vn, wn, r_w, v_stop, slip, dt)
        dist += trapezoid(v, v_stop if stop else vn, h)
        d_iae, d_itae, d_ise = error_integrals(target - slip, target - s_end, t, h)
        iae += active * d_iae
        itae += active * d_itae
        ise += active * d_ise
        ecu_iae += active * h * abs(target - slip_ecu)
        sint += trapezoid(slip, s_end, h)
        clip_max = max(clip_max, abs(s_raw - s_new))
        min_slip = min(min_slip, s_raw)
        peak = max(peak, s_new)
        q_lo = min(q_lo, qn)
        q_hi = max(q_hi, qn)
        if not cut and v_lo < vn < v_hi:
            low_err = max(low_err, abs(target - s_new))
        locked = (not cut) and vn > v_stop and wn * r_w < p[P_LOCK_RATIO] * vn
        if locked:
            locked_s += dt
            if lock_t != lock_t:
                lock_t = t + dt
        check = vn + wn + qn + rn + itae + cmd
        if n_trace > 0 and rows < n_trace:
            write_trace_row(
                trace[rows],
                t + h,
                max(vn, v_stop) if stop else vn,
                wn * r_w,
                s_new,
                target,
                qn,
                kq * qn,
                cmd,
                dist,
                tire_mu(tire, s_new, tc),
            )
            trace[rows, T_VREF] = vref
            trace[rows, T_WEST] = vw
            trace[rows, T_ECU_SLIP] = slip_ecu
            trace[rows, T_VALVE] = (
                E.valve_mode_at(t + dt, pm0, ps0, po0, pm1, ps1, po1) if three_state else 0.0
            )
            trace[rows, T_EDGE_PREV] = read_prev
            trace[rows, T_EDGE_LAST] = read_last
            rows += 1
        v, w, q, r, slip = vn, wn, qn, rn, s_new
        if check - check != 0.0:
            status, t_end = STATUS_DIVERGED, t
            break
        if stop:
            status, t_end = STATUS_STOPPED, t + h
            break
        if dist > p[P_HOPELESS_M]:
            status, t_end = STATUS_HOPELESS, t + dt
            break
    if three_state:  # the last pulse's changes up to the end of the run
        valve, last_change, n_sw, min_iv = _retire_pulse(
            pm1, ps1, po1, ts, t_end, valve, last_change, n_sw, min_iv
        )
    write_metrics(
        out,
        (status, t_end, dist, lock_t),
        (iae, itae, ise, sint),
        (peak, locked_s, clip_max, min_slip),
    )
    out[M_NTRACE] = rows if n_trace > 0 else 0.0
    ecu = (ecu_iae, cut_t, n_sw, min_iv, gap, q_lo, q_hi, low_err)  # the ECU's, in METRICS order
    for j in range(len(ecu)):
        out[M_ECU_IAE + j] = ecu[j]


@_jit
def _simulate(
    tire, lp, plant, x, coef, xc, xs, ys, table, grid, spacing, jitter, acc_noise, trace, out
):
    """Every candidate in turn (row i of `lp`, plant row min(i, rows - 1))."""
    for i in range(lp.shape[0]):
        _run(
            tire,
            lp[i],
            plant[min(i, plant.shape[0] - 1)],
            x,
            (coef[0], coef[1], coef[2], coef[3], xc, xs, ys),
            table,
            grid,
            spacing,
            jitter,
            acc_noise,
            trace,
            out[i],
        )


_NO_TABLE = table_tuples(np.array([0.0, 1.0]), np.array([0.0, 0.0]))


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
    `controllers.discrete.LAWS` order; one column, unused, for none and bang-bang).

    `plant`: PLANT rows (1 or n); `ecu`: the ECU vector (`abs_wheel_ecu_layout.pack_ecu`);
    `tire_*`: `TireCurve.kernel_data()`; (table, grid): the ECU lookup table of a fuzzy law
    (`discrete.ecu_table`) or `discrete.no_table()`; `noise`: (spacing_rad, jitter_s,
    accel_noise_m_s2) of `EcuNoise`. Writes one ECU_METRICS row per candidate into `out`; when
    `trace` has rows (n must be 1), the ECU_TRACE rows too.
    """
    coef4 = np.zeros(4)
    coef4[: len(tire_coef)] = tire_coef
    xc, xs, ys = table_tuples(tire_xs, tire_ys) if tire_kind == KIND_TABLE else _NO_TABLE
    rows = np.ascontiguousarray(np.atleast_2d(plant), dtype=np.float64)
    _simulate(
        tire_kind,
        np.ascontiguousarray(law_params, dtype=np.float64),
        rows,
        ecu,
        coef4,
        xc,
        xs,
        ys,
        table,
        grid,
        *noise,
        trace,
        out,
    )


__all__ = ["LOW_SPEED_BAND_M_S", "simulate_abs_wheel_ecu"]
