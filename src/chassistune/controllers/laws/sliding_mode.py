"""Sliding-mode slip control with a boundary layer (docs/abs_laws.md 1; Unsal and Kachroo, IEEE
TCST 7(2) 1999; Kachroo and Tomizuka, IEEE TAC 41(7) 1996, the boundary layer): on the surface
sigma = S - S*, the pressure whose slip rate is -k sat(sigma / phi) by the slip model
dS/dt = (b q - c F) / v (equivalent control, b = R kq / I, c = R^2 / I + (1 - S) / M), tracked
by a first-order pressure loop of time constant tau_q:

    q_cmd = clamp((c F - v k sat(sigma / phi)) / b, 0, q_max),  r = (q_cmd - q) / tau_q

with F the force estimate and u = r / K (`wheel_estimates`); v is floored at 1 m/s. Sampled
every ts_s in the ideal kernels (its tick) and the ECU (its discrete form, which `export`
ships); the same arithmetic in both.
"""

from __future__ import annotations

import functools
from typing import Any

from chassistune.controllers.laws import forms as F
from chassistune.controllers.laws import wheel_estimates as W
from chassistune.controllers.laws.registry import ABS_WHEEL, CForm, DiscreteLaw, EcuForm, Law
from chassistune.controllers.laws.shared import VEHICLE_PARAMS, per_wheel
from chassistune.controllers.specs import ControllerSpec, GainSpec, ParamSpec

PRESSURE_TAU = ParamSpec(
    "pressure_tau_s", "s", 0.02, "time constant of the loop that tracks q_cmd", positive=True
)
GAINS = (
    GainSpec("reach_1_s", "1/s", 20.0, 1.0, 200.0, "k: the slip's rate outside the layer"),
    GainSpec("layer", "-", 0.05, 0.005, 0.3, "phi: the boundary layer's half width in slip"),
)
DESCRIPTION = (
    "sliding-mode slip control with a boundary layer (Unsal and Kachroo 1999): equivalent "
    "control on the slip model, switching term saturated in |S - S*| <= phi"
)
WHEEL = ControllerSpec(
    ABS_WHEEL,
    "sliding-mode",
    DESCRIPTION,
    gains=GAINS,
    params=(W.SAMPLE_PERIOD, PRESSURE_TAU, *W.WHEEL_CALIBRATION),
)
VEHICLE = per_wheel(
    WHEEL,
    params=(W.SAMPLE_PERIOD, PRESSURE_TAU, *W.VEHICLE_CALIBRATION, *VEHICLE_PARAMS),
)
G_REACH, G_LAYER = (F.gains(WHEEL)[n] for n in ("reach_1_s", "layer"))

DISCRETE = DiscreteLaw(
    "sliding-mode",
    (
        "slip",
        "reference_speed_m_s",
        "wheel_speed_rad_s",
        "wheel_speed_prev_rad_s",
        "pressure",
        "pressure_prev",
    ),
    (
        "reach_1_s",
        "layer",
        "pressure_tau_s",
        *W.CALIBRATION,
        "target_slip",
        "ts_s",
        "wheel_radius_m",
    ),
    ("started",),
    0,
    "sliding mode with a boundary layer on the slip model, first-order pressure loop",
)
"""The discrete law (`ecu_step`) by name."""
_p = DISCRETE.params.index
D_REACH, D_LAYER, D_TAU = _p("reach_1_s"), _p("layer"), _p("pressure_tau_s")
D_I, D_M, D_KQ, D_QMAX, D_K, D_RATE = (_p(n) for n in W.CALIBRATION)
D_TARGET, D_TS, D_RADIUS = _p("target_slip"), _p("ts_s"), _p("wheel_radius_m")
IN_SLIP, IN_V, IN_W, IN_W_PREV, IN_Q, IN_Q_PREV = range(len(DISCRETE.inputs))

EQUATIONS = (
    "- `sliding-mode` (docs/abs_laws.md 1):",
    "F_k = (kq (q_k + q_k-1) / 2 + I (w_k - w_k-1) / ts) / R,  b = R kq / I,",
    "c = R^2 / I + (1 - S_k) / M,  v = max(v_k, 1),  sat = clamp((S_k - S*) / phi, -1, 1),",
    "q_cmd = clamp((c F_k - v k sat) / b, 0, q_max),",
    "u_k = clamp((q_cmd - q_k) / tau_q, -r_max, r_max) / K",
)

C_STEP = """\
double ct_step(ct_state *s, const double *in)
{
    double radius = s->p.wheel_radius_m, inertia = s->p.nominal_inertia_kg_m2;
    double slip = in[CT_IN_SLIP];
    double f = ct_force_estimate(s, in);
    double b = radius * s->p.nominal_brake_gain / inertia;
    double c = radius * radius / inertia + (1.0 - slip) / s->p.nominal_mass_kg;
    double sat = (slip - s->p.target_slip) / s->p.layer;
    double v = in[CT_IN_REFERENCE_SPEED_M_S];
    double q_cmd;
    s->started = 1.0;
    if (sat > 1.0) sat = 1.0;
    if (sat < -1.0) sat = -1.0;
    if (v < 1.0) v = 1.0;
    q_cmd = (c * f - v * s->p.reach_1_s * sat) / b;
    if (q_cmd > s->p.nominal_q_max) q_cmd = s->p.nominal_q_max;
    if (q_cmd < 0.0) q_cmd = 0.0;
    return ct_rate_limit((q_cmd - in[CT_IN_PRESSURE]) / s->p.pressure_tau_s, s->p.rate_limit)
           / s->p.nominal_actuator_gain;
}
"""
"""`ecu_step`'s step in C, in the same operation order."""


@functools.cache
def compiled() -> tuple[Any, Any]:
    """(tick, step): the law at each sample of the ideal kernels (`Law.forms`: the command held
    as u0, the PID's gains left at zero) and its discrete step on the vectors of
    `controllers.discrete` (the realistic ECU and the export), both through `rate`."""
    from numba import njit

    force_estimate, rate_limit = W.forms()
    tick_force = W.tick_force()

    @njit(**F.FORM)
    def rate(slip, target, v_ref, q, f, reach, layer, tau, q_max, radius, inertia, mass, kq):
        """The pressure-rate demand r (module docstring)."""
        b = radius * kq / inertia
        c = radius * radius / inertia + (1.0 - slip) / mass
        sat = (slip - target) / layer
        v = v_ref
        if sat > 1.0:
            sat = 1.0
        if sat < -1.0:
            sat = -1.0
        if v < 1.0:
            v = 1.0
        q_cmd = (c * f - v * reach * sat) / b
        if q_cmd > q_max:
            q_cmd = q_max
        if q_cmd < 0.0:
            q_cmd = 0.0
        return (q_cmd - q) / tau

    @njit(**F.FORM)
    def tick(sig, held, mem, g, g0, c, table, ts, first):
        radius, inertia, kq = sig[F.SIG_RADIUS], c[F.P_INERTIA], c[F.P_BRAKE_GAIN]
        q = sig[F.SIG_PRESSURE]
        f = tick_force(sig, c, ts)
        r = rate(
            sig[F.SIG_SLIP],
            sig[F.SIG_TARGET],
            sig[F.SIG_SPEED],
            q,
            f,
            g[g0 + G_REACH],
            g[g0 + G_LAYER],
            c[F.P_PRESSURE_TAU],
            c[F.P_QMAX],
            radius,
            inertia,
            c[F.P_MASS],
            kq,
        )
        u0 = rate_limit(r, c[F.P_RATE_LIMIT]) / c[F.P_ACTUATOR_GAIN]
        return (u0, held[F.H_KP], held[F.H_KI], held[F.H_KD]), mem

    @njit(**F.FORM)
    def step(state, inputs, params, table, grid):
        state[0] = 1.0  # started: the law keeps no other state
        radius, inertia, kq = params[D_RADIUS], params[D_I], params[D_KQ]
        q = inputs[IN_Q]
        f = force_estimate(
            q, inputs[IN_Q_PREV], inputs[IN_W], inputs[IN_W_PREV], params[D_TS], radius, inertia, kq
        )
        r = rate(
            inputs[IN_SLIP],
            params[D_TARGET],
            inputs[IN_V],
            q,
            f,
            params[D_REACH],
            params[D_LAYER],
            params[D_TAU],
            params[D_QMAX],
            radius,
            inertia,
            params[D_M],
            kq,
        )
        return rate_limit(r, params[D_RATE]) / params[D_K]

    return tick, step


LAW = Law(
    "sliding-mode",
    (WHEEL, VEHICLE),
    lambda: (None, compiled()[0]),  # (start: at rest, tick)
    discrete=DISCRETE,
    ecu=EcuForm(lambda: compiled()[1], rate=True),
    c=CForm(EQUATIONS, C_STEP, helpers=(W.C_HELPERS, W.C_FORCE)),
    source=(
        "Unsal and Kachroo, IEEE TCST 7(2) 1999 (sliding-mode slip control); boundary layer "
        "after Slotine and Li, Applied Nonlinear Control, Prentice Hall 1991, 7.2 "
        "(docs/abs_laws.md 1)"
    ),
)
