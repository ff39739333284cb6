"""Compiled closed-loop simulation of the single-wheel ABS (DESIGN 3.1) over a population.

One kernel serves every controller of the plant (an integer selects the control law; a loop-invariant
branch the compiler hoists) and both paths: a batch of n gain rows, or one row with a trace.
The time loop is outside and the loop over candidates inside, so the compiler can vectorize
across candidates; finished candidates are masked.

Plant (seed 000 eqs. 1-4, 9-10), with Fz = lf M g the wheel load (lf = 1 except sldemo's quirk):
    M dv/dt = -mu(S) Fz,   I dw/dt = R mu(S) Fz - kq q  (w >= 0: held at 0 while Tb >= R Fx),
    S = (v - w R)/v,   T dr/dt = K u - r,   dq/dt = r with q held in [0, q_max].
Control u: a continuous PID with filtered derivative and conditional integration (DESIGN 4),
    u = u0 + kp e + ki z + kd N (e - xf),  dz/dt = e (unless the pressure saturates in the
    direction e pushes),  dxf/dt = N (e - xf),  e = S_target - S,
plus a sampled part u0 (zero-order hold over each step) for the switching laws (no ABS, bang-bang,
threshold). Integration: classic RK4 at a fixed step; the stop at v_stop is located by linear
interpolation inside the last step.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from chassistune.plants.tires import tire_mu

# plant parameter vector
P_MASS, P_INERTIA, P_RADIUS, P_V0, P_G, P_K, P_TAU, P_KQ, P_QMAX = 0, 1, 2, 3, 4, 5, 6, 7, 8
P_VSTOP, P_TMAX, P_DT, P_LOAD, P_TARGET, P_HOPELESS_M, P_LOCK_RATIO = 9, 10, 11, 12, 13, 14, 15
N_PLANT = 16

# controller kinds and parameter vector
C_NONE, C_PID, C_BANGBANG, C_THRESHOLD = 0, 1, 2, 3
Q_NFILTER, Q_AMPLITUDE, Q_DECEL, Q_ACCEL, Q_SLIP_HIGH, Q_SLOW = 0, 1, 2, 3, 4, 5
N_CTRL = 6

# metrics columns
(M_STATUS, M_TIME, M_DIST, M_LOCK_T, M_IAE, M_ITAE, M_ISE, M_MEAN_SLIP, M_PEAK_SLIP,
 M_LOCKED_S, M_CLIP, M_NTRACE, M_MIN_SLIP) = range(13)
N_METRICS = 13
STATUS_STOPPED, STATUS_HOPELESS, STATUS_TIMEOUT, STATUS_DIVERGED = 0, 1, 2, 3

# trace columns
(T_TIME, T_V, T_WHEEL_V, T_SLIP, T_Q, T_TB, T_U, T_X, T_MU, T_TARGET) = range(10)
N_TRACE = 10

# threshold ABS phases
PH_BUILD, PH_HOLD, PH_DUMP, PH_RECOVER, PH_SLOW = 0, 1, 2, 3, 4


@numba.njit(cache=True, nogil=True, inline="always")
def _rhs(v, w, q, r, z, xf, t, u0, kp, ki, kd, p, kind, coef, xs, ys, nf):
    """Time derivatives of (v, w, q, r, x, z, xf, iae, itae, ise, int S) and the command u."""
    s = (v - w * p[P_RADIUS]) / v
    s = min(max(s, 0.0), 1.0)  # guard only: physics keeps S in [0, 1]
    e = p[P_TARGET] - s
    fz = p[P_LOAD] * p[P_MASS] * p[P_G]
    fx = tire_mu(kind, coef, xs, ys, s) * fz
    dv = -fx / p[P_MASS]
    dw = (p[P_RADIUS] * fx - p[P_KQ] * q) / p[P_INERTIA]
    if w <= 0.0 and dw < 0.0:
        dw = 0.0
    u = u0 + kp * e + ki * z + kd * nf * (e - xf)
    dr = (p[P_K] * u - r) / p[P_TAU]
    dq = r
    if (q >= p[P_QMAX] and r > 0.0) or (q <= 0.0 and r < 0.0):
        dq = 0.0
    dz = e
    if (q >= p[P_QMAX] and e > 0.0) or (q <= 0.0 and e < 0.0):
        dz = 0.0
    dxf = nf * (e - xf)
    ae = abs(e)
    return dv, dw, dq, dr, v, dz, dxf, ae, t * ae, e * e, s, u


@numba.njit(cache=True, nogil=True, inline="always")
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


@numba.njit(cache=True, nogil=True)
def simulate_abs_wheel(gains, p, tire_kind, tire_coef, tire_xs, tire_ys, ctrl_kind, c, trace, out):
    """Simulate every row of `gains` (n, 3: kp, ki, kd; zeros for laws without gains).

    Writes the metrics row of each candidate into `out` (n, N_METRICS); when `trace` has rows
    (n must be 1), also the time series (columns T_*), one row per step.
    """
    n = gains.shape[0]
    dt = p[P_DT]
    r_w = p[P_RADIUS]
    v_stop = p[P_VSTOP]
    target = p[P_TARGET]
    nf = c[Q_NFILTER]
    n_steps = int(math.ceil(p[P_TMAX] / dt - 1e-9))
    v = np.full(n, p[P_V0])
    w = np.full(n, p[P_V0] / r_w)
    q = np.zeros(n)
    r = np.zeros(n)
    x = np.zeros(n)
    z = np.zeros(n)
    xf = np.full(n, target)  # derivative filter starts at e(0): no derivative kick
    iae = np.zeros(n)
    itae = np.zeros(n)
    ise = np.zeros(n)
    sint = np.zeros(n)
    aw = np.zeros(n)  # wheel circumferential acceleration at the step start
    phase = np.zeros(n, dtype=np.int64)
    active = np.ones(n, dtype=np.bool_)
    for i in range(n):
        out[i, :] = 0.0
        out[i, M_STATUS] = STATUS_TIMEOUT
        out[i, M_LOCK_T] = np.nan
        out[i, M_MIN_SLIP] = 0.0
    n_trace = trace.shape[0]
    if n_trace > 0:
        trace[0, T_TIME] = 0.0
        trace[0, T_V] = v[0]
        trace[0, T_WHEEL_V] = w[0] * r_w
        trace[0, T_SLIP] = 0.0
        trace[0, T_Q] = 0.0
        trace[0, T_TB] = 0.0
        trace[0, T_U] = 0.0
        trace[0, T_X] = 0.0
        trace[0, T_MU] = 0.0
        trace[0, T_TARGET] = target
        out[0, M_NTRACE] = 1
    n_active = n
    for k in range(n_steps):
        if n_active == 0:
            break
        t = k * dt
        for i in range(n):
            if not active[i]:
                continue
            kp = gains[i, 0]
            ki = gains[i, 1]
            kd = gains[i, 2]
            vi, wi, qi, ri, zi, xfi = v[i], w[i], q[i], r[i], z[i], xf[i]
            s0 = min(max((vi - wi * r_w) / vi, 0.0), 1.0)
            u0, ph = _sampled_command(ctrl_kind, c, phase[i], s0, target, aw[i])
            phase[i] = ph
            a1, b1, c1, d1, e1, f1, g1, h1, i1, j1, l1, u1 = _rhs(
                vi, wi, qi, ri, zi, xfi, t, u0, kp, ki, kd, p,
                tire_kind, tire_coef, tire_xs, tire_ys, nf)
            hs = 0.5 * dt
            a2, b2, c2, d2, e2, f2, g2, h2, i2, j2, l2, _ = _rhs(
                vi + hs * a1, wi + hs * b1, qi + hs * c1, ri + hs * d1, zi + hs * f1,
                xfi + hs * g1, t + hs, u0, kp, ki, kd, p,
                tire_kind, tire_coef, tire_xs, tire_ys, nf)
            a3, b3, c3, d3, e3, f3, g3, h3, i3, j3, l3, _ = _rhs(
                vi + hs * a2, wi + hs * b2, qi + hs * c2, ri + hs * d2, zi + hs * f2,
                xfi + hs * g2, t + hs, u0, kp, ki, kd, p,
                tire_kind, tire_coef, tire_xs, tire_ys, nf)
            a4, b4, c4, d4, e4, f4, g4, h4, i4, j4, l4, _ = _rhs(
                vi + dt * a3, wi + dt * b3, qi + dt * c3, ri + dt * d3, zi + dt * f3,
                xfi + dt * g3, t + dt, u0, kp, ki, kd, p,
                tire_kind, tire_coef, tire_xs, tire_ys, nf)
            h6 = dt / 6.0
            vn = vi + h6 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
            wn = max(wi + h6 * (b1 + 2.0 * b2 + 2.0 * b3 + b4), 0.0)
            qn = min(max(qi + h6 * (c1 + 2.0 * c2 + 2.0 * c3 + c4), 0.0), p[P_QMAX])
            rn = ri + h6 * (d1 + 2.0 * d2 + 2.0 * d3 + d4)
            dx = h6 * (e1 + 2.0 * e2 + 2.0 * e3 + e4)
            zn = zi + h6 * (f1 + 2.0 * f2 + 2.0 * f3 + f4)
            xfn = xfi + h6 * (g1 + 2.0 * g2 + 2.0 * g3 + g4)
            d_iae = h6 * (h1 + 2.0 * h2 + 2.0 * h3 + h4)
            d_itae = h6 * (i1 + 2.0 * i2 + 2.0 * i3 + i4)
            d_ise = h6 * (j1 + 2.0 * j2 + 2.0 * j3 + j4)
            d_sint = h6 * (l1 + 2.0 * l2 + 2.0 * l3 + l4)
            aw[i] = (wn - wi) * r_w / dt
            if not (math.isfinite(vn) and math.isfinite(wn) and math.isfinite(rn)
                    and math.isfinite(zn) and math.isfinite(xfn) and math.isfinite(d_itae)):
                out[i, M_STATUS] = STATUS_DIVERGED
                out[i, M_TIME] = t
                active[i] = False
                n_active -= 1
                continue
            if vn <= v_stop:
                frac = (vi - v_stop) / (vi - vn)
            else:
                frac = 1.0
            x[i] += frac * dx
            iae[i] += frac * d_iae
            itae[i] += frac * d_itae
            ise[i] += frac * d_ise
            sint[i] += frac * d_sint
            s_raw = (vn - wn * r_w) / vn
            s_new = min(max(s_raw, 0.0), 1.0)
            clip = abs(s_raw - s_new)
            if clip > out[i, M_CLIP]:
                out[i, M_CLIP] = clip
            if s_raw < out[i, M_MIN_SLIP]:
                out[i, M_MIN_SLIP] = s_raw
            if s_new > out[i, M_PEAK_SLIP]:
                out[i, M_PEAK_SLIP] = s_new
            if vn > v_stop and wn * r_w < p[P_LOCK_RATIO] * vn:
                if math.isnan(out[i, M_LOCK_T]):
                    out[i, M_LOCK_T] = t + dt
                out[i, M_LOCKED_S] += dt
            v[i], w[i], q[i], r[i], z[i], xf[i] = vn, wn, qn, rn, zn, xfn
            if n_trace > 0 and k + 1 < n_trace:
                row = k + 1
                trace[row, T_TIME] = t + frac * dt
                trace[row, T_V] = vn
                trace[row, T_WHEEL_V] = wn * r_w
                trace[row, T_SLIP] = s_new
                trace[row, T_Q] = qn
                trace[row, T_TB] = p[P_KQ] * qn
                trace[row, T_U] = u1
                trace[row, T_X] = x[i]
                trace[row, T_MU] = tire_mu(tire_kind, tire_coef, tire_xs, tire_ys, s_new)
                trace[row, T_TARGET] = target
                out[i, M_NTRACE] = row + 1
            if vn <= v_stop:
                t_stop = t + frac * dt
                out[i, M_STATUS] = STATUS_STOPPED
                out[i, M_TIME] = t_stop
                active[i] = False
                n_active -= 1
            elif x[i] > p[P_HOPELESS_M]:
                out[i, M_STATUS] = STATUS_HOPELESS
                out[i, M_TIME] = t + dt
                active[i] = False
                n_active -= 1
    for i in range(n):
        if active[i]:
            out[i, M_TIME] = n_steps * dt
        out[i, M_DIST] = x[i]
        out[i, M_IAE] = iae[i]
        out[i, M_ITAE] = itae[i]
        out[i, M_ISE] = ise[i]
        tt = out[i, M_TIME]
        out[i, M_MEAN_SLIP] = sint[i] / tt if tt > 0.0 else 0.0
