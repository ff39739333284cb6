"""The single-wheel PID closed loop in JAX: the bench's peer of `sim.abs_wheel_kernel` (never a
runtime dependency; `pip install chassistune[bench]`).

The same numerics as the kernel's PID path (docs/abs.md, Numerics): plant derlsp-ao-abs eqs. 1-4,
9-10 (`sim.abs_wheel_model`), the filtered PID with conditional integration (`controllers.pid`),
Kutta's RK3 k1 = f(x), k2 = f(x + h/2 k1), k3 = f(x - h k1 + 2 h k2), x + h/6 (k1 + 4 k2 + k3),
w >= 0 and 0 <= q <= q_max after each step, distance and slip ITAE by exact quadrature of the
step-end values (`sim.integrate.error_integrals`), the stop at v_stop located linearly inside the
last step. Written the way a JAX user would: one candidate's run as a `lax.while_loop` to its
end, `vmap` over candidates (a masked loop that runs until the last candidate ends), `jit`,
float64. Bilinear and Burckhardt tires.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np
from jax import lax

from chassistune.plants.tires import KIND_BILINEAR, KIND_BURCKHARDT
from chassistune.scenarios.abs_wheel import AbsWheelScenario

jax.config.update("jax_enable_x64", True)

Array = Any
"""A jax array (jax's own annotations are not needed by the callers)."""


def _mu_fn(scenario: AbsWheelScenario) -> Callable[[Array], Array]:
    """mu(S) of the scenario's tire (`sim.abs_wheel_tires.tire_law_mu`)."""
    kind, coef, _, _ = scenario.tire.kernel_data()
    c = [float(x) for x in coef] + [0.0] * (4 - len(coef))
    if kind == KIND_BILINEAR:
        return lambda s: jnp.where(s <= c[0], c[1] * s, c[2] - c[3] * s)
    if kind == KIND_BURCKHARDT:
        return lambda s: c[0] * (1.0 - jnp.exp(-c[1] * s)) - c[2] * s
    raise ValueError(f"the JAX peer has bilinear and Burckhardt tires only, not {scenario.road}")


def _error_integrals(a: Array, b: Array, t: Array, h: Array) -> tuple[Array, Array]:
    """IAE and ITAE over [t, t + h] of e linear from a to b, split at a sign change."""
    aa, bb = jnp.abs(a), jnp.abs(b)
    iae_same = 0.5 * h * (aa + bb)
    itae_same = t * iae_same + h * h * (aa / 6.0 + bb / 3.0)
    h1 = h * aa / (aa + bb)
    h2 = h - h1
    iae_cross = 0.5 * (aa * h1 + bb * h2)
    itae_cross = aa * h1 * (0.5 * t + h1 / 6.0) + bb * h2 * (0.5 * (t + h1) + h2 / 3.0)
    same = a * b >= 0.0
    return jnp.where(same, iae_same, iae_cross), jnp.where(same, itae_same, itae_cross)


def build_simulate(scenario: AbsWheelScenario) -> jax.stages.Wrapped:
    """A jitted function of gains (n, 3) -> (n, 3): stop distance (m), slip ITAE (s^2) and
    whether the run stopped at v_stop (1.0) or ended otherwise (0.0: hopeless, timeout,
    diverged), for the PID of `scenario`."""
    pp = scenario.plant_params
    mu = _mu_fn(scenario)
    target = scenario.target_slip
    nf = float(scenario.controller_params["n_filter"])
    r_w, q_max, v_stop, dt = pp.wheel_radius_m, pp.q_max, pp.v_stop_m_s, pp.dt_s
    fz = pp.load_fraction * pp.mass_kg * pp.g_m_s2
    inv_m, inv_i, inv_tau = 1.0 / pp.mass_kg, 1.0 / pp.wheel_inertia_kg_m2, 1.0 / pp.actuator_tau_s
    hopeless_m = scenario.scoring.hopeless_factor * scenario.bound_distance_m
    n_steps = int(np.ceil(pp.t_max_s / dt - 1e-9))

    def slip_of(v: Array, w: Array) -> Array:
        return jnp.clip((v - w * r_w) / v, 0.0, 1.0)

    def rates(x: Array, s: Array, gains: Array) -> Array:
        """(dv, dw, dq, dr, dz, dxf) at the state x = (v, w, q, r, z, xf) whose slip is s."""
        _, w, q, r, z, xf = x
        kp, ki, kd = gains
        e = target - s
        fx = mu(s) * fz
        sat_hi, sat_lo = q >= q_max, q <= 0.0
        u = kp * e + ki * z + kd * nf * (e - xf)
        dw = (r_w * fx - pp.brake_gain * q) * inv_i
        return jnp.stack(
            [
                -fx * inv_m,
                jnp.where((w <= 0.0) & (dw < 0.0), 0.0, dw),
                jnp.where((sat_hi & (r > 0.0)) | (sat_lo & (r < 0.0)), 0.0, r),
                (pp.actuator_gain * u - r) * inv_tau,
                jnp.where((sat_hi & (e > 0.0)) | (sat_lo & (e < 0.0)), 0.0, e),
                nf * (e - xf),
            ]
        )

    def step(carry: tuple[Array, ...], gains: Array) -> tuple[Array, ...]:
        x, slip, dist, itae, k, _ = carry
        k1 = rates(x, slip, gains)
        x2 = x + 0.5 * dt * k1
        k2 = rates(x2, slip_of(x2[0], x2[1]), gains)
        x3 = x - dt * k1 + 2.0 * dt * k2
        k3 = rates(x3, slip_of(x3[0], x3[1]), gains)
        xn = x + dt / 6.0 * (k1 + 4.0 * k2 + k3)
        xn = xn.at[1].set(jnp.maximum(xn[1], 0.0)).at[2].set(jnp.clip(xn[2], 0.0, q_max))
        v, vn = x[0], xn[0]
        s_new = slip_of(vn, xn[1])
        stop = vn <= v_stop
        h = jnp.where(stop, (v - v_stop) / (v - vn), 1.0) * dt
        s_end = slip + h / dt * (s_new - slip)
        dist = dist + 0.5 * h * (v + jnp.where(stop, v_stop, vn))
        itae = itae + _error_integrals(target - slip, target - s_end, k * dt, h)[1]
        finite = jnp.all(jnp.isfinite(xn))
        ended = stop | ~finite | (dist > hopeless_m) | (k + 1 >= n_steps)
        return xn, s_new, dist, itae, k + 1, jnp.where(ended, jnp.where(stop, 2, 1), 0)

    def one(gains: Array) -> Array:
        w0 = pp.v0_m_s / r_w
        x0 = jnp.array([pp.v0_m_s, w0, 0.0, 0.0, 0.0, target])
        zero = jnp.zeros(())
        carry = (x0, slip_of(pp.v0_m_s, w0), zero, zero, 0, 0)
        end = lax.while_loop(lambda c: c[5] == 0, lambda c: step(c, gains), carry)
        return jnp.stack([end[2], end[3], jnp.where(end[5] == 2, 1.0, 0.0)])

    return jax.jit(jax.vmap(one))


def simulate(scenario: AbsWheelScenario, gains: np.ndarray) -> np.ndarray:
    """`build_simulate` of the scenario on gains, as a numpy array (compiles on each call)."""
    return np.asarray(build_simulate(scenario)(jnp.asarray(gains, dtype=jnp.float64)))
