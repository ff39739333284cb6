"""TEMPORARY (issue 11): the stage-by-stage ABS kernel as it was before the restructure (commit
2a8c6b9, with its fuzzy gain helpers), kept only as the baseline of the bench ratio
`abs_speedup_vs_previous_kernel`; remove with that figure.

Compiled closed-loop simulation of the single-wheel ABS (DESIGN 3.1) over a population.

One kernel serves every controller of the plant (an integer selects the control law) and both
paths: a batch of n gain rows, or one row with a trace (a single run is a batch of one).

Plant (Tian et al. eqs. 1-4, 9-10), with Fz = lf M g the wheel load (lf = 1 except sldemo's quirk):
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
from numba import njit

from chassistune.fuzzy.surface import surface_lookup, surface_value
from chassistune.plants.tires import tire_mu


@njit(cache=True, nogil=True)
def fuzzy_pid_gains(
    table,
    e: float,
    de: float,
    ke: float,
    kec: float,
    ku_p: float,
    ku_i: float,
    ku_d: float,
    kp0: float,
    ki0: float,
    kd0: float,
    out,
) -> None:  # pragma: no cover - compiled
    """Write the scheduled gains kp, ki, kd into out[0:3] (deffao-vehicle-abs Fig. 3; DESIGN 4).

    `table` must have three outputs in the order kp, ki, kd (deffao) or dkp, dki, dkd (classic).
    """
    surface_lookup(table, ke * e, kec * de, out)
    out[0] = kp0 + ku_p * out[0]
    out[1] = ki0 + ku_i * out[1]
    out[2] = kd0 + ku_d * out[2]


@njit(cache=True, nogil=True)
def immune_gain(
    table, e: float, ec: float, ke: float, kec: float, k_immune: float, eta: float
) -> float:  # pragma: no cover - compiled
    """Immune proportional gain kp1 = k_immune (1 - eta f(ke e, kec ec)) (Ding 2023 eq. 9)."""
    return k_immune * (1.0 - eta * surface_value(table, 0, ke * e, kec * ec))


@njit(cache=True, nogil=True)
def incremental_pid_du(
    kp1: float, ki: float, kd: float, ts: float, e0: float, e1: float, e2: float
) -> float:  # pragma: no cover - compiled
    """Control increment of the discrete PID (fuzzy-immune-abs eq. 10 as DESIGN 4 reads it).

    e0, e1, e2 are the errors at samples k, k-1, k-2; ts the controller's sample period.
    """
    return kp1 * (e0 - e1) + ki * ts * e0 + kd * (e0 - 2.0 * e1 + e2) / ts


# plant parameter vector
P_MASS, P_INERTIA, P_RADIUS, P_V0, P_G, P_K, P_TAU, P_KQ, P_QMAX = 0, 1, 2, 3, 4, 5, 6, 7, 8
P_VSTOP, P_TMAX, P_DT, P_LOAD, P_TARGET, P_HOPELESS_M, P_LOCK_RATIO = 9, 10, 11, 12, 13, 14, 15
P_NFILTER = 16
N_PLANT = 17

# controller kinds and parameter vector
C_NONE, C_PID, C_BANGBANG, C_THRESHOLD, C_FUZZY_PID, C_IMMUNE = 0, 1, 2, 3, 4, 5
Q_TS, Q_AMPLITUDE, Q_DECEL, Q_ACCEL, Q_SLIP_HIGH, Q_SLOW = 0, 1, 2, 3, 4, 5
N_CTRL = 6

# metrics columns
(M_STATUS, M_TIME, M_DIST, M_LOCK_T, M_IAE, M_ITAE, M_ISE, M_MEAN_SLIP, M_PEAK_SLIP,
 M_LOCKED_S, M_CLIP, M_NTRACE, M_MIN_SLIP) = range(13)
N_METRICS = 13
STATUS_STOPPED, STATUS_HOPELESS, STATUS_TIMEOUT, STATUS_DIVERGED = 0, 1, 2, 3

# state rows
S_V, S_W, S_Q, S_R, S_Z, S_XF = 0, 1, 2, 3, 4, 5
N_STATE = 6

# trace columns
(T_TIME, T_V, T_WHEEL_V, T_SLIP, T_Q, T_TB, T_U, T_X, T_MU, T_TARGET) = range(10)
N_TRACE = 10

# threshold ABS phases
PH_BUILD, PH_HOLD, PH_DUMP, PH_RECOVER, PH_SLOW = 0, 1, 2, 3, 4


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _rhs(v, w, q, r, z, xf, u0, kp, ki, kd, r_w, target, fz, inv_m, inv_i, kq, gain, inv_tau,
         q_max, nf, kind, coef, xs, ys):
    """Derivatives of (v, w, q, r, z, xf) and the command u at one state (fz = wheel load)."""
    s = (v - w * r_w) / v
    s = min(max(s, 0.0), 1.0)  # guard only: physics keeps S in [0, 1]
    e = target - s
    fx = tire_mu(kind, coef, xs, ys, s) * fz
    dv = -fx * inv_m
    dw = (r_w * fx - kq * q) * inv_i
    dw = 0.0 if (w <= 0.0 and dw < 0.0) else dw
    u = u0 + kp * e + ki * z + kd * nf * (e - xf)
    dr = (gain * u - r) * inv_tau
    q_hi = q >= q_max
    q_lo = q <= 0.0
    dq = 0.0 if ((q_hi and r > 0.0) or (q_lo and r < 0.0)) else r
    dz = 0.0 if ((q_hi and e > 0.0) or (q_lo and e < 0.0)) else e
    return dv, dw, dq, dr, dz, nf * (e - xf), u


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _stage(m, active, x, k_in, c, k_out, u_out, u0, kp, ki, kd, p, kind, coef, xs, ys):
    """One RK4 stage for the running candidates: k_out = f(x + c k_in)."""
    r_w = p[P_RADIUS]
    target = p[P_TARGET]
    fz = p[P_LOAD] * p[P_MASS] * p[P_G]
    inv_m = 1.0 / p[P_MASS]
    inv_i = 1.0 / p[P_INERTIA]
    kq = p[P_KQ]
    gain = p[P_K]
    inv_tau = 1.0 / p[P_TAU]
    q_max = p[P_QMAX]
    nf = p[P_NFILTER]
    for j in range(m):
        i = active[j]
        dv, dw, dq, dr, dz, dxf, u = _rhs(
            x[S_V, i] + c * k_in[S_V, i], x[S_W, i] + c * k_in[S_W, i],
            x[S_Q, i] + c * k_in[S_Q, i], x[S_R, i] + c * k_in[S_R, i],
            x[S_Z, i] + c * k_in[S_Z, i], x[S_XF, i] + c * k_in[S_XF, i],
            u0[i], kp[i], ki[i], kd[i], r_w, target, fz, inv_m, inv_i, kq, gain, inv_tau, q_max,
            nf, kind, coef, xs, ys)
        k_out[S_V, i] = dv
        k_out[S_W, i] = dw
        k_out[S_Q, i] = dq
        k_out[S_R, i] = dr
        k_out[S_Z, i] = dz
        k_out[S_XF, i] = dxf
        u_out[i] = u


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _abs_integrals(a, b, t, h):
    """Integrals over [t, t + h] of |e|, (t) |e| and e^2 for e linear from a to b."""
    aa = abs(a)
    bb = abs(b)
    if a * b >= 0.0:
        iae = 0.5 * h * (aa + bb)
        itae = t * iae + h * h * (aa / 6.0 + bb / 3.0)
    else:  # the error crosses zero at t + h1
        h1 = h * aa / (aa + bb)
        h2 = h - h1
        iae = 0.5 * (aa * h1 + bb * h2)
        itae = aa * (0.5 * t * h1 + h1 * h1 / 6.0) + bb * (0.5 * (t + h1) * h2 + h2 * h2 / 3.0)
    ise = h * (a * a + a * b + b * b) / 3.0
    return iae, itae, ise


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _sampled_command(ctrl_kind, c, phase, s, target, aw):
    """Zero-order-hold command u0 of the switching laws and the next threshold phase."""
    amp = c[Q_AMPLITUDE]
    if ctrl_kind == C_NONE:
        return amp, phase
    if ctrl_kind == C_BANGBANG:
        err = target - s
        if err > 0.0:
            return amp, phase
        if err < 0.0:
            return -amp, phase
        return 0.0, phase
    if ctrl_kind == C_THRESHOLD:
        a_minus = c[Q_DECEL]
        a_plus = c[Q_ACCEL]
        s_high = target + c[Q_SLIP_HIGH]
        ph = phase
        if ph == PH_BUILD and aw < -a_minus:
            ph = PH_HOLD
        elif ph == PH_HOLD:
            if s > s_high:
                ph = PH_DUMP
            elif aw > -a_minus:
                ph = PH_SLOW
        elif ph == PH_DUMP and aw > 0.0:
            ph = PH_RECOVER
        elif ph == PH_RECOVER and aw < a_plus and s < s_high:
            ph = PH_SLOW
        elif ph == PH_SLOW:
            if s > s_high:
                ph = PH_DUMP
            elif aw < -a_minus:
                ph = PH_HOLD
        if ph == PH_BUILD:
            return amp, ph
        if ph == PH_DUMP:
            return -amp, ph
        if ph == PH_SLOW:
            return amp * c[Q_SLOW], ph
        return 0.0, ph
    return 0.0, phase


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _immune_command(g, table, e, e1, e2, u_prev, ts, first):
    """Fuzzy immune PID (Ding 2023 eqs. 6-10, DESIGN 4), g = (k_immune, eta, ki, kd, ke, kec).

    The controller starts from rest (u = 0 and e = 0 before the first sample) without a
    derivative kick: the first sample adds kp1 e + ki ts e only."""
    ec = 0.0 if first else (e - e1) / ts
    kp1 = immune_gain(table, e, ec, g[4], g[5], g[0], g[1])
    if first:
        return u_prev + incremental_pid_du(kp1, g[2], 0.0, ts, e, 0.0, 0.0)
    return u_prev + incremental_pid_du(kp1, g[2], g[3], ts, e, e1, e2)


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
    scheduled = np.zeros(3)
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
                if ctrl_kind == C_FUZZY_PID:
                    e = target - slip[i]
                    ec = p[P_NFILTER] * (e - x[S_XF, i])  # filtered de/dt
                    g = gains[i]
                    fuzzy_pid_gains(table, e, ec, g[0], g[1], g[2], g[3], g[4], g[5], g[6], g[7],
                                    scheduled)
                    kp[i] = scheduled[0]
                    ki[i] = scheduled[1]
                    kd[i] = scheduled[2]
                elif ctrl_kind == C_IMMUNE:
                    u0[i] = _immune_command(gains[i], table, target - slip[i], e_prev[i],
                                            e_prev2[i], u0[i], ts, k == 0)
                    e_prev2[i] = e_prev[i]
                    e_prev[i] = target - slip[i]
                else:
                    if k > 0:
                        aw[i] = (x[S_W, i] - w_sampled[i]) * r_w / ts
                    w_sampled[i] = x[S_W, i]
                    u0[i], phase[i] = _sampled_command(ctrl_kind, c, phase[i], slip[i], target,
                                                       aw[i])
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
            wi = x[S_W, i]
            vn = vi + h6 * (k1[S_V, i] + 2.0 * k2[S_V, i] + 2.0 * k3[S_V, i] + k4[S_V, i])
            wn = max(wi + h6 * (k1[S_W, i] + 2.0 * k2[S_W, i] + 2.0 * k3[S_W, i] + k4[S_W, i]),
                     0.0)
            qn = x[S_Q, i] + h6 * (k1[S_Q, i] + 2.0 * k2[S_Q, i] + 2.0 * k3[S_Q, i] + k4[S_Q, i])
            qn = min(max(qn, 0.0), q_max)
            rn = x[S_R, i] + h6 * (k1[S_R, i] + 2.0 * k2[S_R, i] + 2.0 * k3[S_R, i] + k4[S_R, i])
            zn = x[S_Z, i] + h6 * (k1[S_Z, i] + 2.0 * k2[S_Z, i] + 2.0 * k3[S_Z, i] + k4[S_Z, i])
            xfn = x[S_XF, i] + h6 * (k1[S_XF, i] + 2.0 * k2[S_XF, i] + 2.0 * k3[S_XF, i]
                                     + k4[S_XF, i])
            s_raw = (vn - wn * r_w) / vn
            s_new = min(max(s_raw, 0.0), 1.0)
            stop = vn <= v_stop
            frac = (vi - v_stop) / (vi - vn) if stop else 1.0
            h = frac * dt
            v_end = v_stop if stop else vn
            s_end = slip[i] + frac * (s_new - slip[i])
            dist[i] += 0.5 * h * (vi + v_end)
            d_iae, d_itae, d_ise = _abs_integrals(target - slip[i], target - s_end, t, h)
            iae[i] += d_iae
            itae[i] += d_itae
            ise[i] += d_ise
            sint[i] += 0.5 * h * (slip[i] + s_end)
            clipmax[i] = max(clipmax[i], abs(s_raw - s_new))
            minslip[i] = min(minslip[i], s_raw)
            peakslip[i] = max(peakslip[i], s_new)
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
