"""Compiled closed-loop simulation of the single-wheel ABS (DESIGN 3.1) over a population.

One kernel serves every controller of the plant (an integer selects the control law) and both
paths: a batch of n gain rows, or one row with a trace (a single run is a batch of one).

Plant (seed 000 eqs. 1-4, 9-10), with Fz = lf M g the wheel load (lf = 1 except sldemo's quirk):
    M dv/dt = -mu(S) Fz,   I dw/dt = R mu(S) Fz - kq q  (w >= 0: held at 0 while Tb >= R Fx),
    S = (v - w R)/v,   T dr/dt = K u - r,   dq/dt = r with q held in [0, q_max].
Control u: a continuous PID with filtered derivative and conditional integration (DESIGN 4),
    u = u0 + kp e + ki z + kd N (e - xf),  dz/dt = e (unless the pressure saturates in the
    direction e pushes),  dxf/dt = N (e - xf),  e = S_target - S,
plus a sampled part u0 for the switching laws (no ABS, bang-bang, threshold): evaluated every
`ts_s` (a whole number of steps) and held in between, so that the controller does not change
when the integration step is refined.

Integration: classic RK4 at a fixed step on (v, w, q, r, z, xf); distance and the slip integrals
(IAE, ITAE, ISE, mean slip) by quadrature of the step-end values, exact for a slip error linear
over the step (a sign change inside a step costs no first-order error); the stop at v_stop is
located by linear interpolation inside the last step.

Speed: the RK4 stages run stage by stage over all running candidates (short independent loop
bodies the CPU overlaps; one candidate's stages form a long dependent chain), and finished
candidates leave the index list of running ones. Float division follows numpy's error model (no
Python zero-division checks in the loops).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from chassistune._branchfree import clip, fmax, fmin, select
from chassistune.controllers.fuzzy_pid import fuzzy_pid_gains
from chassistune.controllers.immune_pid import immune_pid_step
from chassistune.controllers.pid import pid_step
from chassistune.controllers.switching import (
    bang_bang_command,
    no_abs_command,
    threshold_step,
    wheel_deceleration_sample,
)
from chassistune.plants.tires import tire_mu
from chassistune.sim import abs_wheel_layout as L
from chassistune.sim.abs_wheel_model import wheel_rates, wheel_slip
from chassistune.sim.integrate import (
    crossing_fraction,
    error_integrals,
    rk4_point,
    rk4_update,
    trapezoid,
)

# slots of the declared layouts (numba freezes these module integers as constants)
P_MASS, P_INERTIA, P_RADIUS, P_V0 = (L.PLANT[n] for n in (
    "mass_kg", "wheel_inertia_kg_m2", "wheel_radius_m", "v0_m_s"))
P_G, P_K, P_TAU, P_KQ, P_QMAX = (L.PLANT[n] for n in (
    "g_m_s2", "actuator_gain", "actuator_tau_s", "brake_gain", "q_max"))
P_VSTOP, P_TMAX, P_DT, P_LOAD, P_TARGET = (L.PLANT[n] for n in (
    "v_stop_m_s", "t_max_s", "dt_s", "load_fraction", "target_slip"))
P_HOPELESS_M, P_LOCK_RATIO, P_NFILTER = (L.PLANT[n] for n in (
    "hopeless_distance_m", "lock_ratio", "n_filter"))

C_NONE, C_PID, C_BANGBANG, C_THRESHOLD, C_FUZZY_PID, C_IMMUNE = (
    L.CONTROLLER_KINDS.index(n) for n in (
        "none", "pid", "bang-bang", "threshold", "fuzzy-pid", "fuzzy-immune-pid"))
Q_TS, Q_AMPLITUDE, Q_DECEL, Q_ACCEL, Q_SLIP_HIGH, Q_SLOW = (L.CONTROLLER[n] for n in (
    "ts_s", "amplitude", "decel_threshold_m_s2", "accel_threshold_m_s2", "slip_margin",
    "slow_fraction"))

(M_STATUS, M_TIME, M_DIST, M_LOCK_T, M_IAE, M_ITAE, M_ISE, M_MEAN_SLIP, M_PEAK_SLIP, M_LOCKED_S,
 M_CLIP, M_NTRACE, M_MIN_SLIP) = (L.METRICS[n] for n in (
    "status", "stop_time_s", "stop_distance_m", "wheel_lock_time_s", "slip_iae", "slip_itae",
    "slip_ise", "mean_slip", "peak_slip", "locked_time_s", "slip_clip_max", "trace_rows",
    "min_slip_unclipped"))
N_METRICS = len(L.METRICS)
STATUS_STOPPED, STATUS_HOPELESS, STATUS_TIMEOUT, STATUS_DIVERGED = (
    L.STATUS_NAMES.index(n) for n in ("stopped", "hopeless", "timeout", "diverged"))

(T_TIME, T_V, T_WHEEL_V, T_SLIP, T_TARGET, T_Q, T_TB, T_U, T_X, T_MU) = (L.TRACE[n] for n in (
    "time_s", "vehicle_speed_m_s", "wheel_speed_m_s", "slip", "target_slip", "pressure",
    "brake_torque_n_m", "command", "distance_m", "mu"))
N_TRACE = len(L.TRACE)

# state rows
S_V, S_W, S_Q, S_R, S_Z, S_XF = 0, 1, 2, 3, 4, 5
N_STATE = 6


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _rhs(v, w, q, r, z, xf, u0, kp, ki, kd, p, kind, coef, xs, ys):
    """Derivatives of (v, w, q, r, z, xf) and the command u of the wheel under the PID."""
    r_w = p[P_RADIUS]
    s = wheel_slip(v, w, r_w)
    e = p[P_TARGET] - s
    fx = tire_mu(kind, coef, xs, ys, s) * (p[P_LOAD] * p[P_MASS] * p[P_G])
    u, dz, dxf = pid_step(e, z, xf, u0, kp, ki, kd, p[P_NFILTER], q >= p[P_QMAX], q <= 0.0)
    dv, dw, dq, dr, _, _ = wheel_rates(w, q, r, fx, u, r_w, 1.0 / p[P_MASS], 1.0 / p[P_INERTIA],
                                       p[P_KQ], p[P_K], 1.0 / p[P_TAU], p[P_QMAX])
    return dv, dw, dq, dr, dz, dxf, u


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _stage(m, active, x, k_in, c, k_out, u_out, u0, kp, ki, kd, p, kind, coef, xs, ys):
    """One RK4 stage for the running candidates: k_out = f(x + c k_in)."""
    for j in range(m):
        i = active[j]
        dv, dw, dq, dr, dz, dxf, u = _rhs(
            rk4_point(x[S_V, i], c, k_in[S_V, i]), rk4_point(x[S_W, i], c, k_in[S_W, i]),
            rk4_point(x[S_Q, i], c, k_in[S_Q, i]), rk4_point(x[S_R, i], c, k_in[S_R, i]),
            rk4_point(x[S_Z, i], c, k_in[S_Z, i]), rk4_point(x[S_XF, i], c, k_in[S_XF, i]),
            u0[i], kp[i], ki[i], kd[i], p, kind, coef, xs, ys)
        k_out[S_V, i] = dv
        k_out[S_W, i] = dw
        k_out[S_Q, i] = dq
        k_out[S_R, i] = dr
        k_out[S_Z, i] = dz
        k_out[S_XF, i] = dxf
        u_out[i] = u


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _update(x, i, k1, k2, k3, k4, h6, row):
    """RK4 update of state `row` of candidate i."""
    return rk4_update(x[row, i], h6, k1[row, i], k2[row, i], k3[row, i], k4[row, i])


@numba.njit(cache=True, nogil=True, error_model="numpy")
def simulate_abs_wheel(gains, p, tire_kind, tire_coef, tire_xs, tire_ys, ctrl_kind, c, table,
                       trace, out):
    """Simulate every row of `gains` (n, G: the controller's gains in registry order).

    `table` is a compiled fuzzy surface (`chassistune.fuzzy.surface`) for the fuzzy laws, any
    surface otherwise. Fuzzy PID gains: ke, kec, ku_p, ku_i, ku_d, kp0, ki0, kd0; fuzzy immune
    PID gains: k_immune, eta, ki, kd, ke, kec.

    Writes the metrics row of each candidate into `out` (n, N_METRICS); when `trace` has rows
    (n must be 1), also the time series (columns T_*), one row per step.
    """
    n = gains.shape[0]
    dt = p[P_DT]
    hs = 0.5 * dt
    h6 = dt / 6.0
    r_w = p[P_RADIUS]
    v_stop = p[P_VSTOP]
    q_max = p[P_QMAX]
    target = p[P_TARGET]
    n_steps = math.ceil(p[P_TMAX] / dt - 1e-9)
    kp = np.zeros(n)  # gains of the continuous PID part (scheduled by the fuzzy PID)
    ki = np.zeros(n)
    kd = np.zeros(n)
    if ctrl_kind == C_PID:
        kp[:] = gains[:, 0]
        ki[:] = gains[:, 1]
        kd[:] = gains[:, 2]
    e_prev = np.full(n, target)  # immune PID: e(k-1), e(k-2); starting at e(0): no kick
    e_prev2 = np.full(n, target)
    x = np.zeros((N_STATE, n))
    x[S_V, :] = p[P_V0]
    x[S_W, :] = p[P_V0] / r_w
    x[S_XF, :] = target  # derivative filter starts at e(0): no derivative kick
    k1 = np.zeros((N_STATE, n))
    k2 = np.zeros((N_STATE, n))
    k3 = np.zeros((N_STATE, n))
    k4 = np.zeros((N_STATE, n))
    u0 = np.zeros(n)
    u_first = np.zeros(n)
    u_tmp = np.zeros(n)
    slip = np.zeros(n)  # clipped slip at the last step end
    dist = np.zeros(n)
    iae = np.zeros(n)
    itae = np.zeros(n)
    ise = np.zeros(n)
    sint = np.zeros(n)
    aw = np.zeros(n)  # wheel circumferential acceleration over the last sample period
    w_sampled = np.full(n, p[P_V0] / r_w)  # wheel speed at the last sample
    steps_per_sample = max(1, round(c[Q_TS] / dt))
    phase = np.zeros(n, dtype=np.int64)
    status = np.full(n, float(STATUS_TIMEOUT))
    t_end = np.full(n, n_steps * dt)
    lock_t = np.full(n, np.nan)
    locked = np.zeros(n)
    clipmax = np.zeros(n)
    minslip = np.zeros(n)
    peakslip = np.zeros(n)
    active = np.arange(n)
    m = n
    n_trace = trace.shape[0]
    if n_trace > 0:
        trace[0, :] = 0.0
        trace[0, T_V] = p[P_V0]
        trace[0, T_WHEEL_V] = p[P_V0]
        trace[0, T_TARGET] = target
    rows = 1
    for k in range(n_steps):
        if m == 0:
            break
        t = k * dt
        if ctrl_kind != C_PID and k % steps_per_sample == 0:  # sampled laws: own period ts
            ts = steps_per_sample * dt
            for j in range(m):
                i = active[j]
                e = target - slip[i]
                g = gains[i]
                if ctrl_kind == C_FUZZY_PID:
                    ec = p[P_NFILTER] * (e - x[S_XF, i])  # filtered de/dt
                    kp[i], ki[i], kd[i] = fuzzy_pid_gains(table, e, ec, g[0], g[1], g[2], g[3],
                                                          g[4], g[5], g[6], g[7])
                elif ctrl_kind == C_IMMUNE:
                    u0[i] = immune_pid_step(table, e, e_prev[i], e_prev2[i], u0[i], ts, k == 0,
                                            g[0], g[1], g[2], g[3], g[4], g[5])
                    e_prev2[i] = e_prev[i]
                    e_prev[i] = e
                elif ctrl_kind == C_BANGBANG:
                    u0[i] = bang_bang_command(e, c[Q_AMPLITUDE])
                elif ctrl_kind == C_THRESHOLD:
                    if k > 0:
                        aw[i] = wheel_deceleration_sample(x[S_W, i], w_sampled[i], r_w, ts)
                    w_sampled[i] = x[S_W, i]
                    u0[i], phase[i] = threshold_step(phase[i], slip[i], target, aw[i],
                                                     c[Q_AMPLITUDE], c[Q_DECEL], c[Q_ACCEL],
                                                     c[Q_SLIP_HIGH], c[Q_SLOW])
                else:
                    u0[i] = no_abs_command(c[Q_AMPLITUDE])
        _stage(m, active, x, k4, 0.0, k1, u_first, u0, kp, ki, kd, p, tire_kind, tire_coef,
               tire_xs, tire_ys)
        _stage(m, active, x, k1, hs, k2, u_tmp, u0, kp, ki, kd, p, tire_kind, tire_coef,
               tire_xs, tire_ys)
        _stage(m, active, x, k2, hs, k3, u_tmp, u0, kp, ki, kd, p, tire_kind, tire_coef,
               tire_xs, tire_ys)
        _stage(m, active, x, k3, dt, k4, u_tmp, u0, kp, ki, kd, p, tire_kind, tire_coef,
               tire_xs, tire_ys)
        j = 0
        while j < m:
            i = active[j]
            vi = x[S_V, i]
            vn = _update(x, i, k1, k2, k3, k4, h6, S_V)
            wn = fmax(_update(x, i, k1, k2, k3, k4, h6, S_W), 0.0)
            qn = clip(_update(x, i, k1, k2, k3, k4, h6, S_Q), 0.0, q_max)
            rn = _update(x, i, k1, k2, k3, k4, h6, S_R)
            zn = _update(x, i, k1, k2, k3, k4, h6, S_Z)
            xfn = _update(x, i, k1, k2, k3, k4, h6, S_XF)
            s_raw = (vn - wn * r_w) / vn
            s_new = clip(s_raw, 0.0, 1.0)
            stop = vn <= v_stop
            frac = crossing_fraction(vi, vn, v_stop, stop)
            h = frac * dt
            v_end = select(stop, v_stop, vn)
            s_end = slip[i] + frac * (s_new - slip[i])
            dist[i] += trapezoid(vi, v_end, h)
            d_iae, d_itae, d_ise = error_integrals(target - slip[i], target - s_end, t, h)
            iae[i] += d_iae
            itae[i] += d_itae
            ise[i] += d_ise
            sint[i] += trapezoid(slip[i], s_end, h)
            clipmax[i] = fmax(clipmax[i], abs(s_raw - s_new))
            minslip[i] = fmin(minslip[i], s_raw)
            peakslip[i] = fmax(peakslip[i], s_new)
            if vn > v_stop and wn * r_w < p[P_LOCK_RATIO] * vn:
                locked[i] += dt
                if lock_t[i] != lock_t[i]:
                    lock_t[i] = t + dt
            x[S_V, i] = vn
            x[S_W, i] = wn
            x[S_Q, i] = qn
            x[S_R, i] = rn
            x[S_Z, i] = zn
            x[S_XF, i] = xfn
            slip[i] = s_new
            check = vn + wn + rn + zn + xfn + itae[i]
            ended = True
            if check - check != 0.0:
                status[i] = STATUS_DIVERGED
                t_end[i] = t
            elif stop:
                status[i] = STATUS_STOPPED
                t_end[i] = t + h
            elif dist[i] > p[P_HOPELESS_M]:
                status[i] = STATUS_HOPELESS
                t_end[i] = t + dt
            else:
                ended = False
            if ended:  # leave the running list (order does not matter: candidates are independent)
                m -= 1
                active[j] = active[m]
                active[m] = i
            else:
                j += 1
        if n_trace > 0 and rows < n_trace:
            trace[rows, T_TIME] = min(t + dt, t_end[0])
            trace[rows, T_V] = max(x[S_V, 0], v_stop) if status[0] == STATUS_STOPPED else x[S_V, 0]
            trace[rows, T_WHEEL_V] = x[S_W, 0] * r_w
            trace[rows, T_SLIP] = slip[0]
            trace[rows, T_Q] = x[S_Q, 0]
            trace[rows, T_TB] = p[P_KQ] * x[S_Q, 0]
            trace[rows, T_U] = u_first[0]
            trace[rows, T_X] = dist[0]
            trace[rows, T_MU] = tire_mu(tire_kind, tire_coef, tire_xs, tire_ys, slip[0])
            trace[rows, T_TARGET] = target
            rows += 1
    for i in range(n):
        out[i, :] = 0.0
        out[i, M_STATUS] = status[i]
        out[i, M_TIME] = t_end[i]
        out[i, M_DIST] = dist[i]
        out[i, M_LOCK_T] = lock_t[i]
        out[i, M_IAE] = iae[i]
        out[i, M_ITAE] = itae[i]
        out[i, M_ISE] = ise[i]
        out[i, M_MEAN_SLIP] = sint[i] / t_end[i] if t_end[i] > 0.0 else 0.0
        out[i, M_PEAK_SLIP] = peakslip[i]
        out[i, M_LOCKED_S] = locked[i]
        out[i, M_CLIP] = clipmax[i]
        out[i, M_MIN_SLIP] = minslip[i]
        out[i, M_NTRACE] = rows if n_trace > 0 else 0.0
