"""Right-hand side of the single-wheel ABS plant (design.md 3.1; derlsp-ao-abs eqs. 1-4, 9-10),
scalar and branch-free for the compiled kernels (numba, inline="always").

    M dv/dt = -mu(S) Fz,   I dw/dt = R mu(S) Fz - kq q   (w >= 0: held at 0 while Tb >= R Fx),
    S = (v - w R)/v,   T dr/dt = K u - r,   dq/dt = r with q held in [0, q_max].

    wheel_slip(v, w, r_w) -> S clipped to [0, 1]
    wheel_rates(w, q, r, fx, u, r_w, inv_m, inv_i, kq, gain, inv_tau, q_max)
        -> (dv, dw, dq, dr, sat_hi, sat_lo)    (fx = mu(S) Fz; sat_*: q at a limit, for the
                                                 controller's conditional integration)
    step_end(v, vn, wn, r_w, v_stop, slip, dt)
        -> (s_raw, s_new, stop, h, s_end)  the slip at a step's end and the stop inside it
"""

from __future__ import annotations

from numba import njit

from chassistune._branchfree import clip, select
from chassistune.sim.integrate import crossing_fraction


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def wheel_slip(v, w, r_w):
    """Longitudinal slip (v - w R)/v clipped to [0, 1] (a guard only: physics keeps it there)."""
    return clip((v - w * r_w) / v, 0.0, 1.0)


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def wheel_rates(w, q, r, fx, u, r_w, inv_m, inv_i, kq, gain, inv_tau, q_max):
    """Derivatives of (v, w, q, r) under the tire force fx and the command u."""
    dv = -fx * inv_m
    dw = (r_w * fx - kq * q) * inv_i
    dw = select((w <= 0.0) & (dw < 0.0), 0.0, dw)
    dr = (gain * u - r) * inv_tau
    sat_hi = q >= q_max
    sat_lo = q <= 0.0
    dq = select((sat_hi & (r > 0.0)) | (sat_lo & (r < 0.0)), 0.0, r)
    return dv, dw, dq, dr, sat_hi, sat_lo


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def step_end(v, vn, wn, r_w, v_stop, slip, dt):
    """A step of length dt from vehicle speed v to (vn, wheel speed wn), whose slip was `slip`
    at its start: the slip at its end unclipped (s_raw) and clipped (s_new), whether the speed
    crossed v_stop, the length h of the step up to there, and the slip s_end at that point
    (linear in the step)."""
    s_raw = (vn - wn * r_w) / vn
    s_new = clip(s_raw, 0.0, 1.0)
    stop = vn <= v_stop
    frac = crossing_fraction(v, vn, v_stop, stop)
    return s_raw, s_new, stop, frac * dt, slip + frac * (s_new - slip)
