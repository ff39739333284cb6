"""Mixed slip-deceleration control (docs/abs_laws.md 3; Savaresi, Tanelli and Cantoni, ASME
JDSMC 129(1) 2007; Savaresi and Tanelli, Active Braking Control Systems Design for Vehicles,
Springer 2010): the regulated variable mixes the slip and the wheel's deceleration in g,

    eta_k = -R (w_k - w_k-1) / ts / g,   eps_k = (1 - alpha) S_k + alpha eta_k,
    e_k = eps* - eps_k,   r_k = kp e_k + kd (e_k - e_k-1) / ts   (e_-1 = e_0)

and u = r / K, r limited to +-rate_limit (`wheel_estimates`). Its set point eps* is a gain: the
law needs no target slip, so the road's peak is never read. Sampled every ts_s in the ideal
kernels (its tick, on the true wheel speed, new at every sample) and the ECU (its discrete form,
which `export` ships), where a toothed wheel's speed reading changes only at a tooth edge, below
about 8 m/s less often than once a sample: there the deceleration is the change between the last
two readings over the n samples between their arrivals, held until the next reading,

    eta_k = -R (w_k - w_last) / (n ts) / g  when w_k != w_last (then w_last = w_k), else eta_k-1

(the ABS practice of deriving the wheel's acceleration at the speed updates and holding it in
between: EP 0 125 613, "Method and system for deriving wheel acceleration and deceleration in
automotive anti-skid brake control systems"); with a reading new at every sample, n = 1 and it
is the difference above. The plain difference of a held reading is zero between edges and a
spike of several g at an edge, which let the wheel lock at 3.7 m/s (docs/abs_laws.md 3).

Vehicle defaults of their own: its wheels (J = 0.6 kg m^2, R = 0.4 m) turn a pressure into
slip 16 times faster than paper-derlsp-ao's (R kq / I), and the wheel's kp 2e5, kd 2e3 stop the
vehicle 1.87 adhesion bounds long on dry concrete; kp 6e4, kd 60 stop it in 1.19 (mu-jump 1.10).
"""

from __future__ import annotations

import functools
from typing import Any

from chassistune.controllers.laws import forms as F
from chassistune.controllers.laws import wheel_estimates as W
from chassistune.controllers.laws.registry import ABS_WHEEL, CForm, DiscreteLaw, EcuForm, Law
from chassistune.controllers.laws.shared import VEHICLE_PARAMS, per_wheel, rescaled
from chassistune.controllers.specs import ControllerSpec, GainSpec

GAINS = (
    GainSpec("alpha", "-", 0.1, 0.0, 1.0, "weight of the wheel deceleration in eps"),
    GainSpec("target", "-", 0.25, 0.05, 0.6, "eps*: set point of eps"),
    GainSpec("kp", "unit/s", 2e5, 1e3, 1e7, "pressure rate per unit error of eps"),
    GainSpec("kd", "unit", 2e3, 0.0, 1e5, "pressure per unit error of eps"),
)
RATE_PARAMS = ("nominal_actuator_gain", "rate_limit")
"""The calibration the law reads (`wheel_estimates.calibration`)."""
WHEEL = ControllerSpec(
    ABS_WHEEL,
    "mixed-slip-deceleration",
    "mixed slip-deceleration control (Savaresi, Tanelli and Cantoni 2007): PD on pressure rate "
    "of eps = (1 - alpha) S + alpha eta (eta: wheel deceleration in g); no target slip",
    gains=GAINS,
    params=(W.SAMPLE_PERIOD, *(p for p in W.WHEEL_CALIBRATION if p.name in RATE_PARAMS)),
)
VEHICLE = per_wheel(
    WHEEL,
    gains=rescaled(GAINS, {"kp": 6e4, "kd": 60.0}, {"kp": (1e3, 1e7), "kd": (0.0, 1e5)}),
    params=(
        W.SAMPLE_PERIOD,
        *(p for p in W.VEHICLE_CALIBRATION if p.name in RATE_PARAMS),
        *VEHICLE_PARAMS,
    ),
)
G_ALPHA, G_TARGET, G_KP, G_KD = (F.gains(WHEEL)[g.name] for g in GAINS)

STATE = ("error_prev",)
"""The law's memory in the ideal kernels: e at the last sample."""

DISCRETE = DiscreteLaw(
    "mixed-slip-deceleration",
    ("slip", "wheel_speed_rad_s", "wheel_speed_prev_rad_s"),
    ("alpha", "target", "kp", "kd", *RATE_PARAMS, "ts_s", "wheel_radius_m"),
    ("started", "error_prev", "speed_last_rad_s", "samples_since_speed", "eta_held"),
    0,
    "PD on the pressure rate of the mix of slip and wheel deceleration",
)
"""The discrete law (`ecu_step`) by name."""
D_ALPHA, D_TARGET, D_KP, D_KD, D_K, D_RATE, D_TS, D_RADIUS = range(len(DISCRETE.params))
S_STARTED, S_E_PREV, S_W_LAST, S_SAMPLES, S_ETA = range(len(DISCRETE.state))
IN_SLIP, IN_W, IN_W_PREV = range(len(DISCRETE.inputs))

EQUATIONS = (
    "- `mixed-slip-deceleration` (docs/abs_laws.md 3): n = samples since the speed reading",
    "last changed (w_last), eta_k = -R (w_k - w_last) / (n ts) / 9.81 if w_k != w_last else",
    "eta_k-1 (w_-1 the last tick's reading), e_k = eps* - ((1 - alpha) S_k + alpha eta_k),",
    "e_-1 = e_0,",
    "u_k = clamp(kp e_k + kd (e_k - e_k-1) / ts, -r_max, r_max) / K",
)

C_STEP = """\
double ct_step(ct_state *s, const double *in)
{
    double w = in[CT_IN_WHEEL_SPEED_RAD_S];
    int started = s->started != 0.0;
    double w_last = started ? s->speed_last_rad_s : in[CT_IN_WHEEL_SPEED_PREV_RAD_S];
    double n = started ? s->samples_since_speed + 1.0 : 1.0;
    double eta = started ? s->eta_held : 0.0;
    if (w != w_last) {
        double a = (w - w_last) / (n * s->p.ts_s);
        eta = -s->p.wheel_radius_m * a / 9.81;
        w_last = w;
        n = 0.0;
    }
    double e = s->p.target - ((1.0 - s->p.alpha) * in[CT_IN_SLIP] + s->p.alpha * eta);
    double e_prev = started ? s->error_prev : e;
    s->started = 1.0;
    s->error_prev = e;
    s->speed_last_rad_s = w_last;
    s->samples_since_speed = n;
    s->eta_held = eta;
    return ct_rate_limit(s->p.kp * e + s->p.kd * (e - e_prev) / s->p.ts_s, s->p.rate_limit)
           / s->p.nominal_actuator_gain;
}
"""
"""`ecu_step`'s step in C, in the same operation order."""


@functools.cache
def compiled() -> tuple[Any, Any]:
    """(tick, step): the law at each sample of the ideal kernels (`Law.forms`: the command held
    as u0, the PID's gains left at zero; e_k-1 in its memory) and its discrete step on the
    vectors of `controllers.discrete` (the realistic ECU and the export)."""
    from numba import njit

    _, rate_limit = W.forms()

    @njit(**F.FORM)
    def deceleration(w, w_prev, dt, radius):
        """eta = -R (w - w_prev) / dt / g (module docstring)."""
        a = (w - w_prev) / dt
        return -radius * a / W.G_M_S2

    @njit(**F.FORM)
    def error(slip, eta, alpha, target):
        """e = eps* - eps (module docstring)."""
        return target - ((1.0 - alpha) * slip + alpha * eta)

    @njit(**F.FORM)
    def tick(sig, held, mem, g, g0, c, table, ts, first):
        eta = deceleration(
            sig[F.SIG_WHEEL_SPEED], sig[F.SIG_WHEEL_SPEED_PREV], ts, sig[F.SIG_RADIUS]
        )
        e = error(sig[F.SIG_SLIP], eta, g[g0 + G_ALPHA], g[g0 + G_TARGET])
        e_prev = e if first else mem[0]
        r = g[g0 + G_KP] * e + g[g0 + G_KD] * (e - e_prev) / ts
        u0 = rate_limit(r, c[F.P_RATE_LIMIT]) / c[F.P_ACTUATOR_GAIN]
        return (u0, held[F.H_KP], held[F.H_KI], held[F.H_KD]), (e,)

    @njit(**F.FORM)
    def step(state, inputs, params, table, grid):
        ts = params[D_TS]
        w = inputs[IN_W]
        started = state[S_STARTED] != 0.0
        w_last = state[S_W_LAST] if started else inputs[IN_W_PREV]
        n = state[S_SAMPLES] + 1.0 if started else 1.0
        eta = state[S_ETA] if started else 0.0
        if w != w_last:
            eta = deceleration(w, w_last, n * ts, params[D_RADIUS])
            w_last = w
            n = 0.0
        e = error(inputs[IN_SLIP], eta, params[D_ALPHA], params[D_TARGET])
        e_prev = state[S_E_PREV] if started else e
        state[S_STARTED] = 1.0
        state[S_E_PREV] = e
        state[S_W_LAST] = w_last
        state[S_SAMPLES] = n
        state[S_ETA] = eta
        r = params[D_KP] * e + params[D_KD] * (e - e_prev) / ts
        return rate_limit(r, params[D_RATE]) / params[D_K]

    return tick, step


LAW = Law(
    "mixed-slip-deceleration",
    (WHEEL, VEHICLE),
    lambda: (None, compiled()[0]),  # (start: at rest, tick)
    STATE,
    discrete=DISCRETE,
    ecu=EcuForm(lambda: compiled()[1], rate=True),
    c=CForm(EQUATIONS, C_STEP, helpers=(W.C_HELPERS,)),
    needs_target=False,
    source=(
        "Savaresi, Tanelli and Cantoni, ASME JDSMC 129(1) 2007; Savaresi and Tanelli, Active "
        "Braking Control Systems Design for Vehicles, Springer 2010 (docs/abs_laws.md 3)"
    ),
)
