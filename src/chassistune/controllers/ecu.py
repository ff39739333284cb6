"""Compiled ECU parts between plant and controller (parameters in `ecu_params.py`).

Scalar-in, scalar-out step functions with their state passed in and returned, so that the
single-wheel kernel and a four-wheel vehicle kernel can call them per lane or per wheel. They
allocate nothing and draw nothing (random inputs arrive as pre-drawn arrays).

- Toothed-wheel sensor: edge k sits at wheel angle k 2 pi / N + d[k mod len(d)]; the kernel
  integrates the wheel angle, and `sensor_step` finds the edge times inside an integration step
  on the cubic Hermite interpolant of the angle (values and rates at both ends: the dense output
  consistent with the step's own order), floors them to the capture timer and estimates the
  speed from the last edge period, w_est = (2 pi / N) / (t_k - t_k-1). No edge: hold.
- Reference speed: slew-limited vref_k = max(v_wheel, vref_k-1 - a_max ts) (select-high of
  the wheels on a vehicle), or an integrated accelerometer (bias, noise) re-anchored to the
  wheel speed when the wheel is stable and either agrees or has its brake released.
- Three-state modulator: build / hold / dump with orifice rates dp/dt = k_b sqrt(p_s - p) and
  -k_d sqrt(p - p_r), integrated exactly (sqrt(p_s - p) falls linearly in time), so the
  pressure never leaves [p_r, p_s]. The controller issues one pulse per period: a state held for
  `on` seconds from `start` (command time + dead time), then hold; `duty_pulse` turns a pressure
  rate into such a pulse, quantized so that every valve state lasts at least the minimum on-time,
  carrying what the rounding missed into the next period; `switching_pulse` maps the held
  command of a switching law (threshold ABS: build, hold, dump, slow build) to a pulse.
- Low-speed cut-out (latched) and the speed schedule of the gains (kp, kd ~ v / v0).
"""

from __future__ import annotations

import math

import numba

from chassistune._branchfree import clip, select

VALVE_DUMP = -1
VALVE_HOLD = 0
VALVE_BUILD = 1

CROSSING_ITERATIONS = 60
"""Most iterations of the edge-time search (a halving each at worst: float resolution)."""
_EPS = 2.0**-52
_INV_TWO_PI = 1.0 / (2.0 * math.pi)
"""Turns per radian: `edges_passed` guesses an edge index by a product."""

_jit = numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")


@_jit
def cyclic_index(k, n):
    """k mod n in [0, n) (Python's modulo), by a mask when n is a power of two: the same index
    without an integer division (the pre-drawn noise arrays have such lengths)."""
    if n & (n - 1) == 0:
        return k & (n - 1)
    return k % n


@_jit
def edge_angle(k, teeth, spacing):
    """Wheel angle (rad) of edge k: k 2 pi / teeth + spacing[k mod len(spacing)] (k may be a
    whole float, as a kernel's state rows hold it)."""
    return k * (2.0 * math.pi / teeth) + spacing[cyclic_index(int(k), spacing.shape[0])]


@_jit
def hermite_advance(s, dtheta, w0, w1, dt):
    """The angle the wheel turned by s in [0, 1] of a step of length dt: its cubic Hermite
    interpolant less theta0, from the step's increment dtheta = theta1 - theta0 and the end
    speeds w0, w1 (free of the rounding of a large theta0)."""
    s2 = s * s
    s3 = s2 * s
    return (-2.0 * s3 + 3.0 * s2) * dtheta + (s3 - 2.0 * s2 + s) * dt * w0 + (s3 - s2) * dt * w1


@_jit
def hermite_rate(s, dtheta, w0, w1, dt):
    """d/ds of `hermite_advance`."""
    s2 = s * s
    return (
        (6.0 * s - 6.0 * s2) * dtheta
        + (3.0 * s2 - 4.0 * s + 1.0) * dt * w0
        + (3.0 * s2 - 2.0 * s) * dt * w1
    )


@_jit
def crossing_start(target, theta0, theta1):
    """Start of `crossing_fraction`'s search: (s, lo, hi, done, a, dtheta), s the linear guess,
    a = target - theta0 and dtheta = theta1 - theta0 (exact differences where theta0 >= dtheta:
    Sterbenz's lemma) the search's target and increment relative to theta0."""
    a = target - theta0
    dtheta = theta1 - theta0
    s = min(max(a / dtheta, 0.0), 1.0)
    return s, 0.0, 1.0, False, a, dtheta


@_jit
def crossing_iteration(s, lo, hi, done, a, dtheta, w0, w1, dt):
    """One iteration of `crossing_fraction`'s search on the angle turned, a =
    `hermite_advance`(s) (the relative form keeps the residual's rounding at the scale of one
    step's turn, so that Newton settles to float resolution in s in 3-5 iterations at any
    angle), branch-free (a finished search, `done`, stays as it is): the bracket [lo, hi]
    narrowed at s; done there when the angle hits the target or the bracket is at float
    resolution; else the Newton iterate, or the bracket's middle when Newton would leave it,
    done when Newton moved by at most one ulp of 1."""
    f = hermite_advance(s, dtheta, w0, w1, dt) - a
    below = f < 0.0
    lo2 = select(below, s, lo)
    hi2 = select(below, hi, s)
    hit = (f == 0.0) | (hi2 - lo2 <= 4.0 * _EPS)
    d = hermite_rate(s, dtheta, w0, w1, dt)
    newton = select(d > 0.0, s - f / d, -1.0)
    inside = (lo2 < newton) & (newton < hi2)
    nxt = select(inside, newton, 0.5 * (lo2 + hi2))
    converged = inside & (abs(newton - s) <= _EPS)
    return (
        select(done | hit, s, nxt),
        select(done, lo, lo2),
        select(done, hi, hi2),
        done | hit | converged,
    )


@_jit
def crossing_fraction(target, theta0, theta1, w0, w1, dt):
    """Fraction s of the step where the interpolated angle reaches `target`: safeguarded
    Newton from the linear guess, inside a bracket [lo, hi] that every iterate narrows (a
    bisection step whenever Newton would leave it), to float resolution (at most
    CROSSING_ITERATIONS halvings; `crossing_iteration`).

    theta0 < target <= theta1; the first crossing of a monotone interpolant (w0, w1 >= 0 and
    the angle increment between their bounds keep it monotone)."""
    s, lo, hi, done, a, dtheta = crossing_start(target, theta0, theta1)
    for _ in range(CROSSING_ITERATIONS):
        s, lo, hi, done = crossing_iteration(s, lo, hi, done, a, dtheta, w0, w1, dt)
        if done:
            break
    return s


@_jit
def sensor_first_edge(theta0, teeth, spacing):
    """Index of the first edge strictly ahead of the wheel angle theta0."""
    k = math.floor(theta0 * teeth / (2.0 * math.pi))
    while edge_angle(k, teeth, spacing) > theta0:
        k -= 1
    while edge_angle(k, teeth, spacing) <= theta0:
        k += 1
    return k


@_jit
def sensor_step(
    theta0, theta1, w0, w1, t0, dt, k_next, t_last, t_prev, w_est, teeth, timer_s, spacing, jitter
):
    """Advance the toothed-wheel sensor over one integration step [t0, t0 + dt].

    State: k_next (next edge index), t_last and t_prev (captured times of the last two edges,
    -1 before the first ones), w_est (speed estimate, rad/s). Only the last two edges inside the
    step matter (a fine wheel passes many per step): their exact times are found on the angle's
    interpolant, jittered by jitter[k mod len], floored to the timer, and the estimate becomes
    the nominal pitch over their captured period. No edge in the step, or a non-positive
    captured period: the estimate holds. Returns (k_next, t_last, t_prev, w_est).
    """
    k_first = int(k_next)
    if edge_angle(k_first, teeth, spacing) > theta1:
        return k_first, t_last, t_prev, w_est
    k, k_end = edges_passed(k_first, theta1, teeth, spacing)
    while k <= k_end:
        s = crossing_fraction(edge_angle(k, teeth, spacing), theta0, theta1, w0, w1, dt)
        t_prev = t_last
        t_last = edge_capture(t0, s, dt, k, timer_s, jitter)
        k += 1
    return k_end + 1, t_last, t_prev, period_estimate(t_last, t_prev, w_est, teeth)


@_jit
def edges_passed(k_first, theta1, teeth, spacing):
    """(k, k_end): the edges of a step from the next edge k_first up to the angle theta1 that
    matter, the last two (edge k_first is passed: edge_angle(k_first) <= theta1). The edges are
    in order (`ecu_params.SPACING_CLIP`): the last one passed is found by walking from the
    pitch's guess floor(theta1 N / 2 pi), never below k_first, a step or two on any wheel (a
    product, no division)."""
    k_end = max(k_first, math.floor(theta1 * teeth * _INV_TWO_PI))
    while edge_angle(k_end + 1, teeth, spacing) <= theta1:
        k_end += 1
    while k_end > k_first and edge_angle(k_end, teeth, spacing) > theta1:
        k_end -= 1
    return max(k_first, k_end - 1), k_end


@_jit
def edge_capture(t0, s, dt, k, timer_s, jitter):
    """Captured time of edge k, crossed at the fraction s of the step from t0: jittered by
    jitter[k mod len], floored to the timer."""
    t_edge = t0 + s * dt + jitter[cyclic_index(k, jitter.shape[0])]
    return math.floor(t_edge / timer_s) * timer_s


@_jit
def period_estimate(t_last, t_prev, w_est, teeth):
    """The nominal pitch over the last captured period, or w_est held (no period yet, or a
    non-positive one)."""
    period = t_last - t_prev
    if t_prev >= 0.0 and period > 0.0:
        return (2.0 * math.pi / teeth) / period
    return w_est


@_jit
def sensor_read(w_est, t_last, t_now, teeth, bound):
    """The estimate the controller reads at t_now: held, or (bound) capped by the speed at
    which the next edge would already have arrived, pitch / (t_now - t_last)."""
    if bound and t_last >= 0.0 and t_now > t_last:
        return min(w_est, (2.0 * math.pi / teeth) / (t_now - t_last))
    return w_est


@_jit
def select_high4(a, b, c, d):
    """Largest of four wheel speeds (the vehicle is never slower than its fastest braked
    wheel)."""
    return max(max(a, b), max(c, d))


@_jit
def vref_slew(vref_prev, v_wheel, a_max, ts):
    """Slew-limited reference: vref_k = max(v_wheel, vref_k-1 - a_max ts)."""
    return max(v_wheel, vref_prev - a_max * ts)


@_jit
def accelerometer(a_true, bias, noise):
    """Measured longitudinal acceleration: the true one plus bias and this sample's noise."""
    return a_true + bias + noise


@_jit
def vref_accel(
    vref_prev, v_wheel, a_wheel, a_meas, ts, agree, agree_accel, released, held, hold_samples
):
    """Accelerometer reference: vref integrates a_meas over ts, never below the wheel speed.

    It re-anchors to the wheel once the wheel has been stable for `hold_samples` samples in a
    row (`held` counts them): its acceleration a_wheel (over the last sample) within agree_accel
    of a_meas, and either the speeds agree within `agree` or the wheel's brake is released
    (`released`: the ECU's pressure model near zero). Without the stability test, a wheel
    slowing down a little faster than the vehicle would drag the estimate down one sample at a
    time; without the release test, a bias that lifted the estimate above a free wheel by more
    than `agree` would never be corrected; without the run of samples, a wheel whose
    acceleration crosses the vehicle's for one sample at the end of a release (still 10-15 %
    slip on ice) would drag the estimate down at every release. Returns (vref, held).
    """
    v = max(vref_prev + a_meas * ts, v_wheel)
    if abs(a_wheel - a_meas) <= agree_accel and (released or v - v_wheel <= agree):
        held += 1
        if held >= hold_samples:
            return v_wheel, held
        return v, held
    return v, 0


@_jit
def orifice_advance(p, mode, h, kb, kd, p_supply, p_return):
    """Pressure after h seconds in a fixed valve state, exact for dp/dt = k_b sqrt(p_s - p)
    (build: p_s - r^2 with r = sqrt(p_s - p) - k_b h / 2, p_s once r <= 0), -k_d sqrt(p - p_r)
    (dump, alike), 0 (hold); clamped into [p_r, p_s] at the start. Branch-free (one square
    root, selects), so that a vector loop can run it."""
    p = clip(float(p), p_return, p_supply)
    build = mode == VALVE_BUILD
    r = math.sqrt(select(build, p_supply - p, p - p_return)) - 0.5 * select(build, kb, kd) * h
    rr = r * r
    dumped = select(r > 0.0, p_return + rr, p_return)
    held = select(mode == VALVE_DUMP, dumped, p)
    return select(build, select(r > 0.0, p_supply - rr, p_supply), held)


@_jit
def valve_mode_at(t, prev_mode, prev_start, prev_on, mode, start, on):
    """Valve state at time t given the previous and the current pulse (state, start, length):
    the current pulse rules from its start, the previous one before; after a pulse: hold.
    Branch-free (a float)."""
    hold = float(VALVE_HOLD)
    current = select(t < start + on, float(mode), hold)
    previous = select((t >= prev_start) & (t < prev_start + prev_on), float(prev_mode), hold)
    return select(t >= start, current, previous)


@_jit
def modulator_advance(
    p, t0, h, prev_mode, prev_start, prev_on, mode, start, on, kb, kd, p_supply, p_return
):
    """Pressure at t0 + h from p at t0, exact through every valve switch inside the interval
    (the pulse boundaries prev_start + prev_on, start, start + on)."""
    t = t0
    t_end = t0 + h
    while t < t_end:
        nxt = t_end
        for b in (prev_start + prev_on, start, start + on):
            if t < b < nxt:
                nxt = b
        m = valve_mode_at(t, prev_mode, prev_start, prev_on, mode, start, on)
        p = orifice_advance(p, m, nxt - t, kb, kd, p_supply, p_return)
        t = nxt
    return p


@_jit
def quantize_on_time(on, ts, min_on):
    """On-time rounded to the nearest admissible value: 0, [min_on, ts - min_on] or ts, so that
    the pulse and the hold after it each last at least min_on (or do not happen)."""
    if on >= ts - 0.5 * min_on:
        return ts
    if on > ts - min_on:
        return ts - min_on
    if on < 0.5 * min_on:
        return 0.0
    return max(on, min_on)


@_jit
def duty_pulse(rate, residual, p, ts, kb, kd, p_supply, p_return, min_on):
    """Pulse (state, on-time, new residual) realizing the pressure change rate ts + residual
    within one period (a sigma-delta quantizer: what one pulse misses, the next one adds).

    The exact on-time of the orifice law goes through `quantize_on_time`. The residual is the
    requested minus the realized change; a request beyond one period's reach saturates at the
    whole period and clears the residual (no wind-up).
    """
    p = min(max(p, p_return), p_supply)
    dp = rate * ts + residual
    if dp > 0.0:
        mode = VALVE_BUILD
        target = min(p + dp, p_supply)
        on = 2.0 * (math.sqrt(p_supply - p) - math.sqrt(p_supply - target)) / kb
    elif dp < 0.0:
        mode = VALVE_DUMP
        target = max(p + dp, p_return)
        on = 2.0 * (math.sqrt(p - p_return) - math.sqrt(target - p_return)) / kd
    else:
        return VALVE_HOLD, 0.0, 0.0
    on_q = quantize_on_time(on, ts, min_on)
    if on_q == ts:
        return mode, ts, 0.0
    if on_q == 0.0:
        return VALVE_HOLD, 0.0, dp
    return mode, on_q, dp - (orifice_advance(p, mode, on_q, kb, kd, p_supply, p_return) - p)


@_jit
def switching_pulse(u0, amplitude, ts, min_on):
    """Pulse of a switching law that commands valve states directly (threshold ABS, bang-bang):
    the sign of its held command u0 picks build / hold / dump, and a fraction |u0| / amplitude
    of the full command (the threshold law's slow build) becomes a pulse of that fraction of
    the period."""
    if u0 == 0.0 or amplitude <= 0.0:
        return VALVE_HOLD, 0.0
    mode = VALVE_BUILD if u0 > 0.0 else VALVE_DUMP
    on = quantize_on_time(min(abs(u0) / amplitude, 1.0) * ts, ts, min_on)
    return (mode, on) if on > 0.0 else (VALVE_HOLD, 0.0)


@_jit
def cutout_latch(latched, v_ref, cutout_m_s):
    """ABS off for the rest of the stop once the reference speed falls below the cut-out
    (`latched` a bool, or 0.0 / 1.0 from a kernel's float state row)."""
    return bool(latched) or v_ref < cutout_m_s


@_jit
def speed_schedule(v_ref, v0, floor):
    """Gain factor of the speed schedule: kp, kd times max(v_ref / v0, floor)."""
    return max(v_ref / v0, floor)
