"""Linear ADRC slip control (docs/abs_laws.md 2; Gao, "Scaling and bandwidth-parameterization
based controller tuning", ACC 2003): the slip as y'' = f + b0 r with the pressure rate r as input,
b0 = b0_scale R kq / (I v) (v floored at 1 m/s), a forward-Euler extended state observer of
bandwidth wo and a PD of bandwidth wc on its states:

    e = z1 - S_k
    z1 <- z1 + ts (z2 - 3 wo e),  z2 <- z2 + ts (z3 - 3 wo^2 e + b0 r_k-1),  z3 <- z3 - ts wo^3 e
    r_k = clamp((wc^2 (S* - z1) - 2 wc z2 - z3) / b0, -rate_limit, rate_limit),  u = r_k / K

z1 starts at the first slip reading, z2 = z3 = r_-1 = 0. Sampled every ts_s in the ideal kernels
(its tick, the observer in its memory) and the ECU (its discrete form, which `export` ships).
"""

from __future__ import annotations

import functools
from typing import Any

from chassistune.controllers.laws import forms as F
from chassistune.controllers.laws import wheel_estimates as W
from chassistune.controllers.laws.registry import ABS_WHEEL, CForm, DiscreteLaw, EcuForm, Law
from chassistune.controllers.laws.shared import VEHICLE_PARAMS, per_wheel
from chassistune.controllers.specs import ControllerSpec, GainSpec

GAINS = (
    GainSpec("omega_c_rad_s", "rad/s", 15.0, 2.0, 60.0, "wc: controller bandwidth"),
    GainSpec("omega_o_rad_s", "rad/s", 60.0, 10.0, 150.0, "wo: observer bandwidth (wo ts < 0.75)"),
    GainSpec("b0_scale", "-", 1.0, 0.3, 3.0, "scale of the input gain b0 = R kq / (I v)"),
)
CALIBRATION = ("nominal_inertia_kg_m2", "nominal_brake_gain", "nominal_actuator_gain", "rate_limit")
"""The calibration the law reads (`wheel_estimates.calibration`)."""
WHEEL = ControllerSpec(
    ABS_WHEEL,
    "adrc",
    "linear active disturbance rejection control of the slip (Gao 2003): extended state "
    "observer and PD from two bandwidths",
    gains=GAINS,
    params=(W.SAMPLE_PERIOD, *(p for p in W.WHEEL_CALIBRATION if p.name in CALIBRATION)),
)
VEHICLE = per_wheel(
    WHEEL,
    params=(
        W.SAMPLE_PERIOD,
        *(p for p in W.VEHICLE_CALIBRATION if p.name in CALIBRATION),
        *VEHICLE_PARAMS,
    ),
)
G_WC, G_WO, G_B0 = (F.gains(WHEEL)[g.name] for g in GAINS)

STATE = ("z1", "z2", "z3", "rate_prev")
"""The law's memory in the ideal kernels: the observer's states and the last rate applied."""

DISCRETE = DiscreteLaw(
    "adrc",
    ("slip", "reference_speed_m_s"),
    (*(g.name for g in GAINS), *CALIBRATION, "target_slip", "ts_s", "wheel_radius_m"),
    ("started", *STATE),
    0,
    "linear ADRC: forward-Euler extended state observer, PD on its states",
)
"""The discrete law (`ecu_step`) by name."""
D_WC, D_WO, D_B0, D_I, D_KQ, D_K, D_RATE, D_TARGET, D_TS, D_RADIUS = range(len(DISCRETE.params))
S_STARTED, S_Z1, S_Z2, S_Z3, S_RATE = range(len(DISCRETE.state))
IN_SLIP, IN_V = range(len(DISCRETE.inputs))

EQUATIONS = (
    "- `adrc` (docs/abs_laws.md 2): b0 = b0_scale R kq / (I max(v_k, 1)), e = z1 - S_k,",
    "z1 <- z1 + ts (z2 - 3 wo e), z2 <- z2 + ts (z3 - 3 wo^2 e + b0 r_k-1), z3 <- z3 - ts wo^3 e",
    "(z1 = S_0, z2 = z3 = r_-1 = 0 at the start),",
    "u_k = clamp((wc^2 (S* - z1) - 2 wc z2 - z3) / b0, -r_max, r_max) / K",
)

C_STEP = """\
double ct_step(ct_state *s, const double *in)
{
    double slip = in[CT_IN_SLIP], v = in[CT_IN_REFERENCE_SPEED_M_S];
    double wo = s->p.omega_o_rad_s, wc = s->p.omega_c_rad_s, ts = s->p.ts_s;
    double b0, e, z1, z2, z3, r;
    if (v < 1.0) v = 1.0;
    b0 = s->p.b0_scale * s->p.wheel_radius_m * s->p.nominal_brake_gain
         / (s->p.nominal_inertia_kg_m2 * v);
    if (s->started == 0.0) {
        s->z1 = slip;
        s->z2 = 0.0;
        s->z3 = 0.0;
        s->rate_prev = 0.0;
    }
    e = s->z1 - slip;
    z1 = s->z1 + ts * (s->z2 - 3.0 * wo * e);
    z2 = s->z2 + ts * (s->z3 - 3.0 * (wo * wo) * e + b0 * s->rate_prev);
    z3 = s->z3 + ts * (-(wo * wo * wo) * e);
    r = ct_rate_limit((wc * wc * (s->p.target_slip - z1) - 2.0 * wc * z2 - z3) / b0,
                      s->p.rate_limit);
    s->z1 = z1;
    s->z2 = z2;
    s->z3 = z3;
    s->rate_prev = r;
    s->started = 1.0;
    return r / s->p.nominal_actuator_gain;
}
"""
"""`ecu_step`'s step in C, in the same operation order."""


@functools.cache
def compiled() -> tuple[Any, Any]:
    """(tick, step): the law at each sample of the ideal kernels (the command held as u0, the
    PID's gains left at zero; the observer in its memory) and its discrete step on the vectors of
    `controllers.discrete` (the realistic ECU and the export), both through `update`."""
    from numba import njit

    _, rate_limit = W.forms()

    @njit(**F.FORM)
    def update(slip, v_ref, z, target, wc, wo, b0_scale, inertia, kq, limit, ts, radius):
        """(z1, z2, z3, r): the observer's update and the limited rate (module docstring)."""
        z1, z2, z3, r_prev = z
        v = v_ref
        if v < 1.0:
            v = 1.0
        b0 = b0_scale * radius * kq / (inertia * v)
        e = z1 - slip
        n1 = z1 + ts * (z2 - 3.0 * wo * e)
        n2 = z2 + ts * (z3 - 3.0 * (wo * wo) * e + b0 * r_prev)
        n3 = z3 + ts * (-(wo * wo * wo) * e)
        r = rate_limit((wc * wc * (target - n1) - 2.0 * wc * n2 - n3) / b0, limit)
        return n1, n2, n3, r

    @njit(**F.FORM)
    def tick(sig, held, mem, g, g0, c, table, ts, first):
        slip = sig[F.SIG_SLIP]
        z = (slip, 0.0, 0.0, 0.0) if first else (mem[0], mem[1], mem[2], mem[3])
        x = update(
            slip,
            sig[F.SIG_SPEED],
            z,
            sig[F.SIG_TARGET],
            g[g0 + G_WC],
            g[g0 + G_WO],
            g[g0 + G_B0],
            c[F.P_INERTIA],
            c[F.P_BRAKE_GAIN],
            c[F.P_RATE_LIMIT],
            ts,
            sig[F.SIG_RADIUS],
        )
        return (x[3] / c[F.P_ACTUATOR_GAIN], held[F.H_KP], held[F.H_KI], held[F.H_KD]), x

    @njit(**F.FORM)
    def step(state, inputs, params, table, grid):
        slip = inputs[IN_SLIP]
        if state[S_STARTED] == 0.0:
            state[S_Z1], state[S_Z2], state[S_Z3], state[S_RATE] = slip, 0.0, 0.0, 0.0
        x = update(
            slip,
            inputs[IN_V],
            (state[S_Z1], state[S_Z2], state[S_Z3], state[S_RATE]),
            params[D_TARGET],
            params[D_WC],
            params[D_WO],
            params[D_B0],
            params[D_I],
            params[D_KQ],
            params[D_RATE],
            params[D_TS],
            params[D_RADIUS],
        )
        state[S_Z1], state[S_Z2], state[S_Z3], state[S_RATE] = x
        state[S_STARTED] = 1.0
        return x[3] / params[D_K]

    return tick, step


LAW = Law(
    "adrc",
    (WHEEL, VEHICLE),
    lambda: (None, compiled()[0]),  # (start: at rest, tick)
    STATE,
    discrete=DISCRETE,
    ecu=EcuForm(lambda: compiled()[1], rate=True),
    c=CForm(EQUATIONS, C_STEP, helpers=(W.C_HELPERS,)),
    source=(
        "Gao, ACC 2003 (bandwidth-parameterised linear ADRC); extended state observer after "
        "Han, IEEE TIE 56(3) 2009 (docs/abs_laws.md 2)"
    ),
)
