"""Instants inside a step of the vehicle kernel: the state at the stop (the CG speed crossing
v_stop, linear over the step; positions and heading the integrals of their rates) and a wheel's
lock time (its margin w R - lock_ratio |V|, linear over the step, crossing 0)."""

from __future__ import annotations

from chassistune._branchfree import select
from chassistune.sim.abs_vehicle_lane import lane_get
from chassistune.sim.abs_vehicle_layout import R_LOCK_M0, R_LOCK_M1, R_LOCK_T
from chassistune.sim.inlined import inlined
from chassistune.sim.integrate import crossing_fraction


@inlined
def rate_at_stop(a, b, stop, back):
    """b, or at a stop the value linear from a (step start) to b (end) a fraction `back` of the
    step before its end: the crossing fraction of the speed, linear over the step."""
    return select(stop, b - back * (b - a), b)


@inlined
def integral_at_stop(a, b, rate_b, stop, back, dt):
    """b, or at a stop the integral of a rate linear over the step (a position under the
    speed's linear law): the parabola through a (step start) and b with the slope rate_b at
    the end, `back` of the step before it: b - back dt rate_b + back^2 (a - b + dt rate_b)."""
    return select(stop, b - back * dt * rate_b + back * back * (a - b + dt * rate_b), b)


@inlined
def wheel_at_stop(a, b, stop, back):
    return (
        rate_at_stop(a[0], b[0], stop, back),
        rate_at_stop(a[1], b[1], stop, back),
        rate_at_stop(a[2], b[2], stop, back),
        rate_at_stop(a[3], b[3], stop, back),
        rate_at_stop(a[4], b[4], stop, back),
    )


@inlined
def at_stop(x0, x, stop, back, dt, cp, sp):
    """The state x, or at a stop the state at the stop instant, `back` of the step before x
    (x0 the step's start): the speeds, wheel and controller states linear over the step as
    the stop's crossing assumes, X, Y and the heading their integrals (`integral_at_stop`,
    slopes the end's global velocity from the heading's (cos, sin) = (cp, sp) and the yaw
    rate)."""
    a, b = x0[0], x[0]
    vx, vy, r = b[0], b[1], b[2]
    body = (
        rate_at_stop(a[0], vx, stop, back),
        rate_at_stop(a[1], vy, stop, back),
        rate_at_stop(a[2], r, stop, back),
        integral_at_stop(a[3], b[3], vx * cp - vy * sp, stop, back, dt),
        integral_at_stop(a[4], b[4], vx * sp + vy * cp, stop, back, dt),
        integral_at_stop(a[5], b[5], r, stop, back, dt),
        rate_at_stop(a[6], b[6], stop, back),
    )
    return (
        body,
        wheel_at_stop(x0[1], x[1], stop, back),
        wheel_at_stop(x0[2], x[2], stop, back),
        wheel_at_stop(x0[3], x[3], stop, back),
        wheel_at_stop(x0[4], x[4], stop, back),
    )


@inlined
def lock_time(st, j, l, dt):
    """Wheel j's lock time (NaN: never): where its margin w R - lock_ratio |V|, linear over the
    step in which it first locked, crosses 0."""
    t = lane_get(st, R_LOCK_T + j, l)
    m0 = lane_get(st, R_LOCK_M0 + j, l)
    frac = crossing_fraction(m0, lane_get(st, R_LOCK_M1 + j, l), 0.0, True)
    return select(t == t, t + frac * dt, t)
