"""Sampled switching laws of the single-wheel ABS (design.md 4): no ABS, bang-bang, threshold.

Each law is evaluated at its own sample instants and its command held in between (zero-order
hold), so the law does not change when the integration step is refined. The held command enters
the plant as the feed-forward u0 of `pid_step` (with zero gains).

Step functions (numba, inline="always"; scalar in, scalar out):

    no_abs_command(amplitude) -> u0
        the driver's constant pressure command.
    bang_bang_command(e, amplitude) -> u0                                   (branch-free)
        amplitude * sign(e), e = S_target - S (sldemo_absbrake's controller); 0 at e == 0 or NaN.
    wheel_deceleration_sample(w, w_sampled, r_w, ts) -> a_w
        wheel circumferential acceleration over the last sample period (m/s^2).
    threshold_step(phase, s, target, a_w, amplitude, decel, accel, slip_margin, slow_fraction)
            -> (u0, phase)
        rule-based ABS phases (PH_BUILD, PH_HOLD, PH_DUMP, PH_RECOVER, PH_SLOW; an int) driven by
        the wheel deceleration a_w against -decel / +accel (m/s^2) and the slip against
        target + slip_margin; commands +amplitude (build), 0 (hold, recover), -amplitude (dump),
        slow_fraction * amplitude (slow build). A state machine: call it in a scalar pass.
"""

from __future__ import annotations

from numba import njit

from chassistune._branchfree import select

PH_BUILD, PH_HOLD, PH_DUMP, PH_RECOVER, PH_SLOW = 0, 1, 2, 3, 4


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def no_abs_command(amplitude):
    """No ABS: the driver's pressure command, constant."""
    return amplitude


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def bang_bang_command(e, amplitude):
    """amplitude * sign(e) (0 for e == 0 or NaN), branch-free."""
    return select(e > 0.0, amplitude, select(e < 0.0, -amplitude, 0.0))


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def wheel_deceleration_sample(w, w_sampled, r_w, ts):
    """Wheel circumferential acceleration (w - w_sampled) R / ts over one sample period."""
    return (w - w_sampled) * r_w / ts


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def threshold_step(phase, s, target, a_w, amplitude, decel, accel, slip_margin, slow_fraction):
    """Next phase of the threshold ABS and its command (docs/abs.md)."""
    s_high = target + slip_margin
    ph = phase
    if ph == PH_BUILD and a_w < -decel:
        ph = PH_HOLD
    elif ph == PH_HOLD:
        if s > s_high:
            ph = PH_DUMP
        elif a_w > -decel:
            ph = PH_SLOW
    elif ph == PH_DUMP and a_w > 0.0:
        ph = PH_RECOVER
    elif ph == PH_RECOVER and a_w < accel and s < s_high:
        ph = PH_SLOW
    elif ph == PH_SLOW:
        if s > s_high:
            ph = PH_DUMP
        elif a_w < -decel:
            ph = PH_HOLD
    if ph == PH_BUILD:
        return amplitude, ph
    if ph == PH_DUMP:
        return -amplitude, ph
    if ph == PH_SLOW:
        return amplitude * slow_fraction, ph
    return 0.0, ph
