"""Model-predictive slip control (docs/abs_laws.md 5; Petersen, Johansen, Kalkkuhl and Ludemann,
"Wheel slip control in ABS brakes using gain scheduled constrained LQR", ECC 2001): each sample,
the pressure move z = q_k+1 - q_k that minimises the squared error of the projected slip and a
move penalty on the linearised wheel-slip dynamics dS/dt = (b q - c F) / v (`sliding_mode`'s slip
model, force and 1 - S frozen at the sample, the force F_k the ECU's estimate, v floored at
1 m/s), under the actuator's pressure-rate and pressure limits. Horizon N = `HORIZON` = 1:

    G = (ts + T_L) b / v,   y_free = S_k + (ts + T_L)(b q_k - c F_k) / v
    h = 2 (G^2 + rho / q_max^2),   f = 2 G (y_free - S*)
    z = clamp(-f / h, max(-r_max ts, -q0), min(r_max ts, q_max - q0)),  q0 = clamp(q_k, 0, q_max)
    r_k = z / ts,   u = r_k / K

The QP of `controllers.slip_mpc_qp` with one move: its box and its pressure rows intersect into
one interval, and the minimiser is clamped into it (`slip_mpc_qp.horizon1_move`, which
`solve_moves` reproduces to 1e-8). This one form runs in the ideal kernels (its tick), the ECU
and the C export (its discrete form); a longer horizon needs the interior-point solve of
`solve_moves` in the kernels (a scratch per lane) and in C, which this law does not have yet.
"""

from __future__ import annotations

import functools
from typing import Any

from chassistune.controllers.laws import forms as F
from chassistune.controllers.laws import wheel_estimates as W
from chassistune.controllers.laws.registry import ABS_WHEEL, CForm, DiscreteLaw, EcuForm, Law
from chassistune.controllers.laws.shared import VEHICLE_PARAMS, per_wheel
from chassistune.controllers.specs import ControllerSpec, GainSpec

HORIZON = 1
"""Samples predicted: the QP has one move (the closed form above)."""
GAINS = (
    GainSpec("lookahead_s", "s", 0.05, 0.005, 0.3, "T_L: the cost weighs the slip T_L ahead"),
    GainSpec("move_weight", "-", 1e-2, 1e-5, 10.0, "rho: weight of (z / q_max)^2"),
)
WHEEL = ControllerSpec(
    ABS_WHEEL,
    "mpc",
    "model-predictive slip control (Petersen et al. 2001): one pressure move per sample from a "
    "QP on the linearised slip dynamics under the pressure-rate and pressure limits",
    gains=GAINS,
    params=(W.SAMPLE_PERIOD, *W.WHEEL_CALIBRATION),
)
VEHICLE = per_wheel(WHEEL, params=(W.SAMPLE_PERIOD, *W.VEHICLE_CALIBRATION, *VEHICLE_PARAMS))
G_LOOKAHEAD, G_WEIGHT = (F.gains(WHEEL)[g.name] for g in GAINS)

DISCRETE = DiscreteLaw(
    "mpc",
    (
        "slip",
        "reference_speed_m_s",
        "wheel_speed_rad_s",
        "wheel_speed_prev_rad_s",
        "pressure",
        "pressure_prev",
    ),
    (*(g.name for g in GAINS), *W.CALIBRATION, "target_slip", "ts_s", "wheel_radius_m"),
    ("started",),
    0,
    "model-predictive slip control, horizon 1: one move from a QP under rate and pressure limits",
)
"""The discrete law (`ecu_step`) by name."""
_p = DISCRETE.params.index
D_LOOKAHEAD, D_WEIGHT = _p("lookahead_s"), _p("move_weight")
D_I, D_M, D_KQ, D_QMAX, D_K, D_RATE = (_p(n) for n in W.CALIBRATION)
D_TARGET, D_TS, D_RADIUS = _p("target_slip"), _p("ts_s"), _p("wheel_radius_m")
IN_SLIP, IN_V, IN_W, IN_W_PREV, IN_Q, IN_Q_PREV = range(len(DISCRETE.inputs))

EQUATIONS = (
    "- `mpc` (docs/abs_laws.md 5), horizon 1: F_k = (kq (q_k + q_k-1) / 2 + I (w_k - w_k-1) / ts)"
    " / R,",
    "b = R kq / I, c = R^2 / I + (1 - S_k) / M, v = max(v_k, 1), G = (ts + T_L) b / v,",
    "y = S_k + (ts + T_L) (b q_k - c F_k) / v, h = 2 (G^2 + rho / q_max^2), f = 2 G (y - S*),",
    "q0 = clamp(q_k, 0, q_max), dq = r_max ts,",
    "z = clamp(-f / h, max(-dq, -q0), min(dq, q_max - q0)), u_k = clamp(z / ts, -r_max, r_max) / K",
)

C_STEP = """\
double ct_step(ct_state *s, const double *in)
{
    double radius = s->p.wheel_radius_m, inertia = s->p.nominal_inertia_kg_m2;
    double ts = s->p.ts_s, q_max = s->p.nominal_q_max, slip = in[CT_IN_SLIP];
    double q = in[CT_IN_PRESSURE], v = in[CT_IN_REFERENCE_SPEED_M_S];
    double f = ct_force_estimate(s, in);
    double b = radius * s->p.nominal_brake_gain / inertia;
    double c = radius * radius / inertia + (1.0 - slip) / s->p.nominal_mass_kg;
    double reach, gain, free, h, lin, q0, dq, lo, hi, z;
    s->started = 1.0;
    if (v < 1.0) v = 1.0;
    reach = ts + s->p.lookahead_s;
    gain = reach * b / v;
    free = slip + reach * (b * q - c * f) / v;
    h = 2.0 * (gain * gain + s->p.move_weight / (q_max * q_max));
    lin = 2.0 * gain * (free - s->p.target_slip);
    q0 = q;
    if (q0 > q_max) q0 = q_max;
    if (q0 < 0.0) q0 = 0.0;
    dq = s->p.rate_limit * ts;
    lo = -q0 > -dq ? -q0 : -dq;
    hi = q_max - q0 < dq ? q_max - q0 : dq;
    z = -lin / h;
    if (z < lo) z = lo;
    if (z > hi) z = hi;
    return ct_rate_limit(z / ts, s->p.rate_limit) / s->p.nominal_actuator_gain;
}
"""
"""`ecu_step`'s step in C, in the same operation order."""


@functools.cache
def compiled() -> tuple[Any, Any, Any]:
    """(tick, step, move): the law at each sample of the ideal kernels (`Law.forms`: the command
    held as u0, the PID's gains left at zero), its discrete step on the vectors of
    `controllers.discrete` (the realistic ECU and the export), both through `move`, the QP's
    minimiser z (module docstring)."""
    from numba import njit

    force_estimate, rate_limit = W.forms()

    @njit(**F.FORM)
    def move(slip, target, v_ref, q, f, lookahead, weight, ts, q_max, rate, radius, inertia, m, kq):
        """The pressure move z of the horizon-1 QP (module docstring)."""
        b = radius * kq / inertia
        c = radius * radius / inertia + (1.0 - slip) / m
        v = v_ref
        if v < 1.0:
            v = 1.0
        reach = ts + lookahead
        gain = reach * b / v
        free = slip + reach * (b * q - c * f) / v
        h = 2.0 * (gain * gain + weight / (q_max * q_max))
        lin = 2.0 * gain * (free - target)
        q0 = q
        if q0 > q_max:
            q0 = q_max
        if q0 < 0.0:
            q0 = 0.0
        dq = rate * ts
        lo = -q0 if -q0 > -dq else -dq
        hi = q_max - q0 if q_max - q0 < dq else dq
        z = -lin / h
        if z < lo:
            z = lo
        if z > hi:
            z = hi
        return z

    @njit(**F.FORM)
    def tick(sig, held, mem, g, g0, c, table, ts, first):
        radius, inertia, kq = sig[F.SIG_RADIUS], c[F.P_INERTIA], c[F.P_BRAKE_GAIN]
        q = sig[F.SIG_PRESSURE]
        w, w_prev = sig[F.SIG_WHEEL_SPEED], sig[F.SIG_WHEEL_SPEED_PREV]
        f = force_estimate(q, sig[F.SIG_PRESSURE_PREV], w, w_prev, ts, radius, inertia, kq)
        z = move(
            sig[F.SIG_SLIP],
            sig[F.SIG_TARGET],
            sig[F.SIG_SPEED],
            q,
            f,
            g[g0 + G_LOOKAHEAD],
            g[g0 + G_WEIGHT],
            ts,
            c[F.P_QMAX],
            c[F.P_RATE_LIMIT],
            radius,
            inertia,
            c[F.P_MASS],
            kq,
        )
        u0 = rate_limit(z / ts, c[F.P_RATE_LIMIT]) / c[F.P_ACTUATOR_GAIN]
        return (u0, held[F.H_KP], held[F.H_KI], held[F.H_KD]), mem

    @njit(**F.FORM)
    def step(state, inputs, params, table, grid):
        state[0] = 1.0  # started: the law keeps no other state
        ts, radius, inertia, kq = params[D_TS], params[D_RADIUS], params[D_I], params[D_KQ]
        q = inputs[IN_Q]
        f = force_estimate(
            q, inputs[IN_Q_PREV], inputs[IN_W], inputs[IN_W_PREV], ts, radius, inertia, kq
        )
        z = move(
            inputs[IN_SLIP],
            params[D_TARGET],
            inputs[IN_V],
            q,
            f,
            params[D_LOOKAHEAD],
            params[D_WEIGHT],
            ts,
            params[D_QMAX],
            params[D_RATE],
            radius,
            inertia,
            params[D_M],
            kq,
        )
        return rate_limit(z / ts, params[D_RATE]) / params[D_K]

    return tick, step, move


LAW = Law(
    "mpc",
    (WHEEL, VEHICLE),
    lambda: (None, compiled()[0]),  # (start: at rest, tick)
    discrete=DISCRETE,
    ecu=EcuForm(lambda: compiled()[1], rate=True),
    c=CForm(EQUATIONS, C_STEP, helpers=(W.C_HELPERS, W.C_FORCE)),
    source=(
        "Petersen, Johansen, Kalkkuhl and Ludemann, ECC 2001 (constrained, gain-scheduled "
        "LQR/MPC of the linearised wheel slip); QP: controllers/slip_mpc_qp.py, horizon 1 in "
        "closed form (docs/abs_laws.md)"
    ),
)
