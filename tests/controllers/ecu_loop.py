"""Test oracle: a scalar single-wheel ABS loop composed of the ECU step functions.

An independent, deliberately plain implementation (one candidate, no lanes) of the
`paper-derlsp-ao` wheel (design.md 3.1, bilinear tire) under a sampled PID, used to check that the
ECU parts compose: in the ideal limit it must reproduce the package's kernel, and it gives the
realistic ECU kernel a reference to match. Order of one ECU tick (every m steps), as in
docs/ecu.md: sensor read, reference speed, ECU slip, cut-out, speed schedule, the discrete PID
(forward-Euler integrator, backward-Euler derivative filter), the delay line, then the valves
(continuous: the K/(s(Ts+1)) actuator; three-state: a duty-quantized pulse).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

import chassistune as ct
from chassistune.controllers import ecu as E
from chassistune.controllers.ecu_params import EcuParams, draw_noise, orifice_gains

# paper-derlsp-ao (design.md 3.1): M, I, R, g, K, T, kq, q_max, v0, v_stop, dt, t_max
PLANT = np.array([100.0, 12.0, 0.5, 9.81, 100.0, 0.01, 1.0, 1500.0, 30.0, 0.5, 1e-3, 120.0])
SENSOR_IDEAL, SENSOR_TOOTHED = 0, 1
VREF_TRUE, VREF_SLEW, VREF_ACCEL = 0, 1, 2
LOW_SPEED_M_S = (1.0, 9.0)
"""Speed band of the low-speed slip error (fixed gains fail below ~9 m/s)."""


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _mu(s, st, mh, mg):
    """Bilinear tire, seed 000 eq. 5."""
    return mh * s / st if s <= st else (mh - mg * st) / (1.0 - st) - (mh - mg) * s / (1.0 - st)


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _run(road, gains, plant, modes, ecu, spacing, jitter, accel_noise):
    """One stop. modes: (sensor, vref, three-state, m, delay, scheduled, stale bound);
    ecu: (teeth, timer, a_max, bias, agree, agree_accel, p_free, kb, kd, dead, min_on, cutout).

    Returns (distance, stop time, largest |v - vref| above 5 m/s, lowest and highest pressure,
    largest true slip error |S_target - S| at step ends in the LOW_SPEED_M_S band).
    """
    st, mh, mg = road[0], road[1], road[2]
    kp, ki, kd, nf = gains[0], gains[1], gains[2], gains[3]
    mass, inertia, r_w, g, gain, tau = plant[0], plant[1], plant[2], plant[3], plant[4], plant[5]
    kq, q_max, v0, v_stop, dt, t_max = plant[6], plant[7], plant[8], plant[9], plant[10], plant[11]
    sensor, vref_mode, valves, m, delay, sched, bound = modes
    teeth, timer, a_max, bias = int(ecu[0]), ecu[1], ecu[2], ecu[3]
    agree, agree_accel = ecu[4], ecu[5]
    p_free, kb, kdv, dead, min_on, cutout = ecu[6], ecu[7], ecu[8], ecu[9], ecu[10], ecu[11]
    ts = m * dt
    amp = q_max / (0.15 * gain)  # the driver's demand: q_max in 0.15 s
    v, w, theta, q, r = v0, v0 / r_w, 0.0, 0.0, 0.0
    k_next = E.sensor_first_edge(0.0, teeth, spacing)
    t_last, t_prev, w_est = -1.0, -1.0, v0 / r_w
    vref, vw_prev, cut = v0, v0, False
    z, xf, u0, resid = 0.0, st, 0.0, 0.0
    line = np.zeros(max(delay, 1))
    pulses = np.zeros(6)  # previous and current pulse: mode, start, on-time
    dist, gap, q_lo, q_hi, e_low = 0.0, 0.0, q, q, 0.0
    v_lo, v_hi = LOW_SPEED_M_S
    kv, kw, kqd, krd = np.zeros(4), np.zeros(4), np.zeros(4), np.zeros(4)
    ws = np.zeros(4)
    n_steps = math.ceil(t_max / dt)
    tick = 0
    for k in range(n_steps):
        t = k * dt
        if k % m == 0:
            wr = w if sensor == 0 else E.sensor_read(w_est, t_last, t, teeth, bound == 1)
            vw = wr * r_w
            a_wheel = (vw - vw_prev) / ts if k > 0 else 0.0
            vw_prev = vw
            if vref_mode == 0 or k == 0:
                vref = v if vref_mode == 0 else v0
            elif vref_mode == 1:
                vref = E.vref_slew(vref, vw, a_max, ts)
            else:
                s_true = min(max((v - w * r_w) / v, 0.0), 1.0)
                a_meas = E.accelerometer(
                    -_mu(s_true, st, mh, mg) * g, bias, accel_noise[tick % accel_noise.shape[0]]
                )
                vref, _ = E.vref_accel(
                    vref, vw, a_wheel, a_meas, ts, agree, agree_accel, q <= p_free, 0, 1
                )  # re-anchors on one sample
            if v > 5.0:
                gap = max(gap, abs(v - vref))
            e = st - (vref - vw) / vref
            cut = E.cutout_latch(cut, vref, cutout)
            f = E.speed_schedule(vref, v0, 0.05) if sched == 1 else 1.0
            xf = (xf + nf * ts * e) / (1.0 + nf * ts)  # backward Euler
            u = f * kp * e + ki * z + f * kd * nf * (e - xf)
            if not ((q >= q_max and e > 0.0) or (q <= 0.0 and e < 0.0)):
                z += ts * e  # forward Euler, conditional integration
            cmd = u
            if delay > 0:
                cmd = line[tick % delay]
                line[tick % delay] = u
            if cut:
                cmd = amp
            if valves == 0:
                u0 = cmd
            else:
                if cut:
                    mode, on = E.VALVE_BUILD, ts
                else:
                    mode, on, resid = E.duty_pulse(
                        gain * cmd, resid, q, ts, kb, kdv, q_max, 0.0, min_on
                    )
                pulses[0], pulses[1], pulses[2] = pulses[3], pulses[4], pulses[5]
                pulses[3], pulses[4], pulses[5] = mode, t + dead, on
            tick += 1
        for j in range(4):  # classic RK4 on v, w (and q, r for the continuous actuator)
            c = 0.0 if j == 0 else (0.5 if j < 3 else 1.0)
            vv = v + c * dt * (kv[j - 1] if j > 0 else 0.0)
            ww = w + c * dt * (kw[j - 1] if j > 0 else 0.0)
            ws[j] = ww
            if valves == 0:
                qq = q + c * dt * (kqd[j - 1] if j > 0 else 0.0)
                rr = r + c * dt * (krd[j - 1] if j > 0 else 0.0)
                krd[j] = (gain * u0 - rr) / tau
                kqd[j] = 0.0 if ((qq >= q_max and rr > 0.0) or (qq <= 0.0 and rr < 0.0)) else rr
            else:
                qq = E.modulator_advance(
                    q,
                    t,
                    c * dt,
                    int(pulses[0]),
                    pulses[1],
                    pulses[2],
                    int(pulses[3]),
                    pulses[4],
                    pulses[5],
                    kb,
                    kdv,
                    q_max,
                    0.0,
                )
            fx = _mu(min(max((vv - ww * r_w) / vv, 0.0), 1.0), st, mh, mg) * mass * g
            kv[j] = -fx / mass
            dw = (r_w * fx - kq * qq) / inertia
            kw[j] = 0.0 if (ww <= 0.0 and dw < 0.0) else dw
        vn = v + dt / 6.0 * (kv[0] + 2.0 * kv[1] + 2.0 * kv[2] + kv[3])
        wn = max(w + dt / 6.0 * (kw[0] + 2.0 * kw[1] + 2.0 * kw[2] + kw[3]), 0.0)
        theta_n = theta + dt / 6.0 * (ws[0] + 2.0 * ws[1] + 2.0 * ws[2] + ws[3])
        if valves == 0:
            qn = min(
                max(q + dt / 6.0 * (kqd[0] + 2.0 * kqd[1] + 2.0 * kqd[2] + kqd[3]), 0.0), q_max
            )
            r += dt / 6.0 * (krd[0] + 2.0 * krd[1] + 2.0 * krd[2] + krd[3])
        else:
            qn = E.modulator_advance(
                q,
                t,
                dt,
                int(pulses[0]),
                pulses[1],
                pulses[2],
                int(pulses[3]),
                pulses[4],
                pulses[5],
                kb,
                kdv,
                q_max,
                0.0,
            )
        if sensor == 1:
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
                timer,
                spacing,
                jitter,
            )
        if v_lo < vn < v_hi:
            e_low = max(e_low, abs(st - min(max((vn - wn * r_w) / vn, 0.0), 1.0)))
        q_lo = min(q_lo, qn)
        q_hi = max(q_hi, qn)
        if vn <= v_stop:
            frac = (v - v_stop) / (v - vn)
            return dist + 0.5 * frac * dt * (v + v_stop), t + frac * dt, gap, q_lo, q_hi, e_low
        dist += 0.5 * dt * (v + vn)
        v, w, theta, q = vn, wn, theta_n, qn
    return dist, -1.0, gap, q_lo, q_hi, e_low


def bilinear_road(road: str) -> tuple[float, float, float]:
    """(S_T, mu_h, mu_g) of a bilinear road, from the public parameter echo."""
    p = ct.simulate("abs-wheel", road=road, controller="none").scenario.params()
    return p["slip_opt"], p["mu_peak"], p["mu_lock"]


@dataclass(frozen=True)
class Stop:
    distance_m: float
    time_s: float
    """-1 when the run did not stop by t_max."""
    max_gap_m_s: float
    """Largest |true speed - reference| at the ticks above 5 m/s."""
    pressure_min: float
    pressure_max: float
    low_speed_slip_error: float
    """Largest |S_target - S| (true slip) between 1 and 9 m/s."""


def ecu_stop(
    road: str,
    params: EcuParams,
    *,
    sensor: int = SENSOR_IDEAL,
    vref: int = VREF_TRUE,
    three_state: bool = False,
    m: int = 1,
    delay: int = 0,
    scheduled: bool = False,
    cutout: bool = False,
    seed: int = 0,
    gains: tuple[float, float, float] = (5000.0, 0.0, 230.0),
) -> Stop:
    """One stop of the oracle loop on a bilinear road with the PID `gains` (kp, ki, kd)."""
    st, mh, mg = bilinear_road(road)
    kb, kdv = orifice_gains(params, PLANT[7], 0.0)
    noise = draw_noise(params, seed)
    dead = round(params.valve_dead_time_s / PLANT[10]) * PLANT[10]
    modes = (
        sensor,
        vref,
        int(three_state),
        m,
        delay,
        int(scheduled),
        int(params.sensor_stale == "bound"),
    )
    ecu = np.array(
        [
            params.sensor_teeth,
            params.sensor_timer_s,
            params.vref_decel_max_m_s2,
            params.accel_bias_m_s2,
            params.vref_agree_m_s,
            params.vref_agree_m_s2,
            params.vref_free_pressure * PLANT[7],
            kb,
            kdv,
            dead,
            params.valve_min_on_s,
            params.abs_cutout_m_s if cutout else 0.0,
        ]
    )
    out = _run(
        np.array([st, mh, mg]),
        np.array([*gains, 100.0]),
        PLANT,
        modes,
        ecu,
        noise.spacing_rad,
        noise.jitter_s,
        noise.accel_noise_m_s2,
    )
    return Stop(*(float(x) for x in out))
