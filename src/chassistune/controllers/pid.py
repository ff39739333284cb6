"""Continuous PID on the slip error with a filtered derivative and conditional integration
(design.md 4; derlsp-ao-abs eq. 12).

    u = u0 + kp e + ki z + kd N (e - xf),   dz/dt = e (0 while the actuator saturates in the
    direction e pushes),   dxf/dt = N (e - xf).

The controller's explicit state is (z, xf): the kernel integrates the rates returned here with
the plant's. `u0` is an additive feed-forward (the sampled command of a switching law, 0 for a
pure PID). Start xf at e(0) for a derivative without kick.

Step function (numba, inline="always", branch-free: callable in a vectorized loop body):

    pid_step(e, z, xf, u0, kp, ki, kd, n_filter, sat_hi, sat_lo) -> (u, dz_dt, dxf_dt)

    e: float, error (target - measured); z, xf: float, integrator and filter states;
    kp, ki, kd: float, gains; n_filter: float, derivative filter coefficient N (rad/s);
    sat_hi, sat_lo: bool, the actuator is at its upper / lower limit (conditional integration).
"""

from __future__ import annotations

from numba import njit

from chassistune._branchfree import select


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def pid_step(e, z, xf, u0, kp, ki, kd, n_filter, sat_hi, sat_lo):
    """Command u and the state rates (dz/dt, dxf/dt) of the filtered PID (design.md 4)."""
    u = u0 + kp * e + ki * z + kd * n_filter * (e - xf)
    dz = select((sat_hi & (e > 0.0)) | (sat_lo & (e < 0.0)), 0.0, e)
    return u, dz, n_filter * (e - xf)
