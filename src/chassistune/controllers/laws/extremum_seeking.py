"""Extremum-seeking slip control (docs/abs_laws.md 4; Ariyur and Krstic, Real-Time Optimization
by Extremum-Seeking Control, Wiley 2003, ch. 7; Krstic and Wang, Automatica 36(4) 2000): the
target slip theta is found online by a sinusoidal dither on the slip, a washout of the measured
friction estimate J = F / (M g) and its demodulation by the dither,

    s_k = sin(omega t_k),  J_k = F_k / (M g),  Jlp <- Jlp + ts omega_h (J_k - Jlp)
    theta <- clamp(theta + ts k' (J_k - Jlp) s_k, THETA_MIN, THETA_MAX),  k' = k once t_k >= hold
    e_k = theta + a s_k - S_k,  r_k = kp e_k + kd (e_k - e_k-1) / ts   (e_-1 = e_0)

with F_k the ECU's force estimate (`wheel_estimates`), theta = `start` and Jlp = J_0 at the
first sample, u = r / K, r limited to +-rate_limit. It reads no target slip and nothing of the
road. The sine is `sine_form`: an odd polynomial after reduction of the phase, the same operations
in C (which then needs no libm); within 3e-16 of math.sin over one period, 2e-13 at 1200 rad.
"""

from __future__ import annotations

import functools
import math
from typing import Any

from chassistune.controllers.laws import forms as F
from chassistune.controllers.laws import wheel_estimates as W
from chassistune.controllers.laws.registry import ABS_WHEEL, CForm, DiscreteLaw, EcuForm, Law
from chassistune.controllers.laws.shared import VEHICLE_PARAMS, per_wheel, rescaled
from chassistune.controllers.specs import ControllerSpec, GainSpec

GAINS = (
    GainSpec("start", "-", 0.15, 0.03, 0.4, "theta at the start: the first target slip"),
    GainSpec("dither", "-", 0.02, 0.005, 0.05, "a: the dither's amplitude in slip"),
    GainSpec("dither_rad_s", "rad/s", 10.0, 3.0, 20.0, "omega: the dither's frequency"),
    GainSpec("gain_1_s", "1/s", 2.5, 0.5, 10.0, "k: d theta/dt per unit demodulated J"),
    GainSpec("highpass_rad_s", "rad/s", 3.0, 0.5, 10.0, "omega_h: the washout's corner"),
    GainSpec("hold_s", "s", 0.5, 0.0, 1.0, "theta frozen while the brake first applies"),
    GainSpec("kp", "unit/s", 5e5, 1e4, 5e6, "inner slip loop: pressure rate per unit slip"),
    GainSpec("kd", "unit", 1e4, 0.0, 1e5, "inner slip loop: pressure per unit slip rate"),
)
THETA_MIN, THETA_MAX = 0.03, 0.5
"""The interval theta is searched in (fixed)."""
CALIBRATION = (
    "nominal_inertia_kg_m2",
    "nominal_mass_kg",
    "nominal_brake_gain",
    "nominal_actuator_gain",
    "rate_limit",
)
"""The calibration the law reads (`wheel_estimates.calibration`)."""
WHEEL = ControllerSpec(
    ABS_WHEEL,
    "extremum-seeking",
    "extremum-seeking slip control (Ariyur and Krstic 2003): a sinusoidal dither on the slip, "
    "demodulated washed-out friction estimate F / (M g) drives the target; no road knowledge",
    gains=GAINS,
    params=(W.SAMPLE_PERIOD, *(p for p in W.WHEEL_CALIBRATION if p.name in CALIBRATION)),
)
VEHICLE = per_wheel(
    WHEEL,
    gains=rescaled(GAINS, {"kp": 5e4, "kd": 100.0}, {"kp": (1e3, 5e6), "kd": (0.0, 1e5)}),
    params=(
        W.SAMPLE_PERIOD,
        *(p for p in W.VEHICLE_CALIBRATION if p.name in CALIBRATION),
        *VEHICLE_PARAMS,
    ),
)
G_START, G_A, G_OMEGA, G_K, G_WH, G_HOLD, G_KP, G_KD = (F.gains(WHEEL)[g.name] for g in GAINS)

STATE = ("theta", "objective_lowpass", "error_prev")
"""The law's memory in the ideal kernels: theta, Jlp and e at the last sample."""

DISCRETE = DiscreteLaw(
    "extremum-seeking",
    (
        "slip",
        "wheel_speed_rad_s",
        "wheel_speed_prev_rad_s",
        "pressure",
        "pressure_prev",
        "time_s",
    ),
    (*(g.name for g in GAINS), *CALIBRATION, "ts_s", "wheel_radius_m"),
    ("started", *STATE),
    0,
    "extremum seeking of the friction estimate by a sinusoidal dither, PD slip loop",
)
"""The discrete law (`ecu_step`) by name."""
_p = DISCRETE.params.index
D_START, D_A, D_OMEGA, D_K, D_WH, D_HOLD, D_KP, D_KD = (_p(g.name) for g in GAINS)
D_I, D_M, D_KQ, D_ACT, D_RATE = (_p(n) for n in CALIBRATION)
D_TS, D_RADIUS = _p("ts_s"), _p("wheel_radius_m")
S_STARTED, S_THETA, S_JLP, S_E_PREV = range(len(DISCRETE.state))
IN_SLIP, IN_W, IN_W_PREV, IN_Q, IN_Q_PREV, IN_T = range(len(DISCRETE.inputs))

SINE_TERMS = tuple((-1.0) ** n / math.factorial(2 * n + 1) for n in range(12))
"""sin x = x (c0 + x^2 (c1 + x^2 (...))): the odd Taylor series to x^23, whose remainder on
|x| <= pi/2 is below 1e-18."""
PHASE_MAX = 1e9
"""Largest phase omega t reduced (a larger or NaN phase reads 0: wild gains stay finite)."""

EQUATIONS = (
    "- `extremum-seeking` (docs/abs_laws.md 4): s_k = sin(omega t_k), J_k = F_k / (M 9.81),",
    "F_k = (kq (q_k + q_k-1) / 2 + I (w_k - w_k-1) / ts) / R,",
    "Jlp <- Jlp + ts omega_h (J_k - Jlp)  (Jlp = J_0, theta = start at the first sample),",
    f"theta <- clamp(theta + ts k' (J_k - Jlp) s_k, {THETA_MIN}, {THETA_MAX}),"
    " k' = k if t_k >= hold else 0,",
    "e_k = theta + a s_k - S_k (e_-1 = e_0),",
    "u_k = clamp(kp e_k + kd (e_k - e_k-1) / ts, -r_max, r_max) / K",
)

C_SINE = f"""\
/* sin x: the phase reduced to [-pi/2, pi/2], then the odd Taylor series to x^23 (Horner) */
static double ct_sine(double x)
{{
    static const double c[{len(SINE_TERMS)}] = {{ {", ".join(repr(c) for c in SINE_TERMS)} }};
    double x2, p;
    int i;
    if (!(x >= 0.0 && x < {PHASE_MAX!r})) x = 0.0;
    x = x - (double)(long long)(x / {2.0 * math.pi!r} + 0.5) * {2.0 * math.pi!r};
    if (x > {0.5 * math.pi!r}) x = {math.pi!r} - x;
    if (x < {-0.5 * math.pi!r}) x = {-math.pi!r} - x;
    x2 = x * x;
    p = c[{len(SINE_TERMS) - 1}];
    for (i = {len(SINE_TERMS) - 2}; i >= 0; --i) p = c[i] + x2 * p;
    return x * p;
}}
"""
"""`sine` in C."""

C_STEP = f"""\
double ct_step(ct_state *s, const double *in)
{{
    double ts = s->p.ts_s, t = in[CT_IN_TIME_S];
    double f = ct_force_estimate(s, in);
    double j = f / (s->p.nominal_mass_kg * {W.G_M_S2!r});
    double dither = ct_sine(s->p.dither_rad_s * t);
    double gain = t >= s->p.hold_s ? s->p.gain_1_s : 0.0;
    double theta, e, e_prev;
    if (s->started == 0.0) {{
        s->theta = s->p.start;
        s->objective_lowpass = j;
    }}
    s->objective_lowpass = s->objective_lowpass + ts * s->p.highpass_rad_s
                           * (j - s->objective_lowpass);
    theta = s->theta + ts * gain * (j - s->objective_lowpass) * dither;
    if (theta < {THETA_MIN!r}) theta = {THETA_MIN!r};
    if (theta > {THETA_MAX!r}) theta = {THETA_MAX!r};
    e = theta + s->p.dither * dither - in[CT_IN_SLIP];
    e_prev = s->started != 0.0 ? s->error_prev : e;
    s->theta = theta;
    s->error_prev = e;
    s->started = 1.0;
    return ct_rate_limit(s->p.kp * e + s->p.kd * (e - e_prev) / ts, s->p.rate_limit)
           / s->p.nominal_actuator_gain;
}}
"""
"""`ecu_step`'s step in C, in the same operation order."""


@functools.cache
def sine_form() -> Any:
    """sin x as `C_SINE` computes it, a numba function."""
    from numba import njit

    terms = SINE_TERMS[::-1]
    two_pi, pi, half_pi = 2.0 * math.pi, math.pi, 0.5 * math.pi

    @njit(**F.FORM)
    def sine(x):
        if not (x >= 0.0 and x < PHASE_MAX):
            x = 0.0
        x = x - float(int(x / two_pi + 0.5)) * two_pi
        if x > half_pi:
            x = pi - x
        if x < -half_pi:
            x = -pi - x
        x2 = x * x
        p = terms[0]
        for i in range(1, len(terms)):
            p = terms[i] + x2 * p
        return x * p

    return sine


@functools.cache
def compiled() -> tuple[Any, Any]:
    """(tick, step): the law at each sample of the ideal kernels (`Law.forms`: the command held
    as u0, the PID's gains left at zero; theta, Jlp, e_k-1 in its memory) and its discrete step on
    the vectors of `controllers.discrete` (the realistic ECU and the export), both through
    `update`."""
    from numba import njit

    force_estimate, rate_limit = W.forms()
    tick_force = W.tick_force()
    sine = sine_form()

    @njit(**F.FORM)
    def update(state, f, slip, t, ts, g, mass):
        """(theta, Jlp, e, r): one step (module docstring) from state (theta, Jlp, e_k-1,
        started) with the gains g in `GAINS` order."""
        theta, j_lp, e_prev, started = state
        start, a, omega, k, wh, hold, kp, kd = g
        j = f / (mass * W.G_M_S2)
        dither = sine(omega * t)
        gain = k if t >= hold else 0.0
        if not started:
            theta, j_lp = start, j
        j_lp = j_lp + ts * wh * (j - j_lp)
        theta = theta + ts * gain * (j - j_lp) * dither
        if theta < THETA_MIN:
            theta = THETA_MIN
        if theta > THETA_MAX:
            theta = THETA_MAX
        e = theta + a * dither - slip
        if not started:
            e_prev = e
        return theta, j_lp, e, kp * e + kd * (e - e_prev) / ts

    @njit(**F.FORM)
    def tick(sig, held, mem, g, g0, c, table, ts, first):
        f = tick_force(sig, c, ts)
        gains = (
            g[g0 + G_START],
            g[g0 + G_A],
            g[g0 + G_OMEGA],
            g[g0 + G_K],
            g[g0 + G_WH],
            g[g0 + G_HOLD],
            g[g0 + G_KP],
            g[g0 + G_KD],
        )
        x = update(
            (mem[0], mem[1], mem[2], not first),
            f,
            sig[F.SIG_SLIP],
            sig[F.SIG_TIME],
            ts,
            gains,
            c[F.P_MASS],
        )
        u0 = rate_limit(x[3], c[F.P_RATE_LIMIT]) / c[F.P_ACTUATOR_GAIN]
        return (u0, held[F.H_KP], held[F.H_KI], held[F.H_KD]), (x[0], x[1], x[2])

    @njit(**F.FORM)
    def step(state, inputs, params, table, grid):
        ts, radius = params[D_TS], params[D_RADIUS]
        f = force_estimate(
            inputs[IN_Q],
            inputs[IN_Q_PREV],
            inputs[IN_W],
            inputs[IN_W_PREV],
            ts,
            radius,
            params[D_I],
            params[D_KQ],
        )
        gains = (
            params[D_START],
            params[D_A],
            params[D_OMEGA],
            params[D_K],
            params[D_WH],
            params[D_HOLD],
            params[D_KP],
            params[D_KD],
        )
        x = update(
            (state[S_THETA], state[S_JLP], state[S_E_PREV], state[S_STARTED] != 0.0),
            f,
            inputs[IN_SLIP],
            inputs[IN_T],
            ts,
            gains,
            params[D_M],
        )
        state[S_THETA], state[S_JLP], state[S_E_PREV] = x[0], x[1], x[2]
        state[S_STARTED] = 1.0
        return rate_limit(x[3], params[D_RATE]) / params[D_ACT]

    return tick, step


LAW = Law(
    "extremum-seeking",
    (WHEEL, VEHICLE),
    lambda: (None, compiled()[0]),  # (start: at rest, tick)
    STATE,
    discrete=DISCRETE,
    ecu=EcuForm(lambda: compiled()[1], rate=True),
    c=CForm(EQUATIONS, C_STEP, helpers=(W.C_HELPERS, W.C_FORCE, C_SINE)),
    source=(
        "Ariyur and Krstic, Real-Time Optimization by Extremum-Seeking Control, Wiley 2003, "
        "ch. 7 (ABS); Krstic and Wang, Automatica 36(4) 2000 (dither, washout, demodulation); "
        "Dincmen, Guvenc and Acarman, IEEE TCST 22(1) 2014 (docs/abs_laws.md)"
    ),
    needs_target=False,
)
