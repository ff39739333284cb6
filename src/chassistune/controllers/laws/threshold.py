"""Rule-based threshold ABS (design.md 4, docs/abs.md): wheel deceleration/acceleration and slip
thresholds drive a phase machine (`controllers.switching.threshold_step`), sampled every ts_s in
the kernels and the ECU (`ecu_step`: its discrete form, which `export` ships)."""

from __future__ import annotations

import functools
from typing import Any

from chassistune.controllers.laws import forms as F
from chassistune.controllers.laws.registry import ABS_WHEEL, CForm, DiscreteLaw, EcuForm, Law
from chassistune.controllers.laws.shared import AMPLITUDE, REAR, SAMPLE_PERIOD, per_wheel
from chassistune.controllers.specs import ControllerSpec, ParamSpec

STATE = ("phase", "wheel_accel_m_s2")
"""The law's memory: its phase and the wheel acceleration over the last sample period."""
M_PHASE, M_ACCEL = range(len(STATE))

DISCRETE = DiscreteLaw(
    "threshold",
    ("slip", "wheel_speed_rad_s"),
    (
        "amplitude",
        "decel_threshold_m_s2",
        "accel_threshold_m_s2",
        "slip_margin",
        "slow_fraction",
        "target_slip",
        "ts_s",
        "wheel_radius_m",
    ),
    ("started", "phase", "wheel_speed_prev", "wheel_accel"),
    0,
    "sampled phase machine (build, hold, dump, recover, slow build)",
)
"""The discrete phase machine (`ecu_step`) by name."""
_param = DISCRETE.params.index
D_AMP, D_DECEL, D_ACCEL = (
    _param("amplitude"),
    _param("decel_threshold_m_s2"),
    _param("accel_threshold_m_s2"),
)
D_MARGIN, D_SLOW, D_TARGET = _param("slip_margin"), _param("slow_fraction"), _param("target_slip")
D_TS, D_RADIUS = _param("ts_s"), _param("wheel_radius_m")
S_STARTED, S_PHASE, S_W_PREV, S_ACCEL = (
    DISCRETE.state.index(n) for n in ("started", "phase", "wheel_speed_prev", "wheel_accel")
)
IN_SLIP, IN_WHEEL_SPEED = (DISCRETE.inputs.index(n) for n in ("slip", "wheel_speed_rad_s"))

WHEEL = ControllerSpec(
    ABS_WHEEL,
    "threshold",
    "rule-based ABS: wheel deceleration/acceleration and slip thresholds drive pressure "
    "build, hold, dump, recover and slow-build phases (see docs/abs.md)",
    params=(
        AMPLITUDE,
        SAMPLE_PERIOD,
        ParamSpec(
            "decel_threshold_m_s2",
            "m/s^2",
            15.0,
            "-a: wheel circumferential deceleration that stops the build-up",
            positive=True,
        ),
        ParamSpec(
            "accel_threshold_m_s2",
            "m/s^2",
            10.0,
            "+a: wheel re-acceleration held before building again",
            positive=True,
        ),
        ParamSpec(
            "slip_margin", "-", 0.05, "dump when slip exceeds target + margin", positive=True
        ),
        ParamSpec(
            "slow_fraction",
            "-",
            0.25,
            "slow build rate as a fraction of amplitude",
            positive=True,
        ),
    ),
)

C_STEP = """\
enum { CT_BUILD = 0, CT_HOLD = 1, CT_DUMP = 2, CT_RECOVER = 3, CT_SLOW = 4 };

static int ct_next_phase(int ph, double slip, double aw, double s_high, double a_minus,
                         double a_plus)
{
    if (ph == CT_BUILD && aw < -a_minus) return CT_HOLD;
    if (ph == CT_HOLD) {
        if (slip > s_high) return CT_DUMP;
        if (aw > -a_minus) return CT_SLOW;
    } else if (ph == CT_DUMP && aw > 0.0) {
        return CT_RECOVER;
    } else if (ph == CT_RECOVER && aw < a_plus && slip < s_high) {
        return CT_SLOW;
    } else if (ph == CT_SLOW) {
        if (slip > s_high) return CT_DUMP;
        if (aw < -a_minus) return CT_HOLD;
    }
    return ph;
}

double ct_step(ct_state *s, const double *in)
{
    double w = in[CT_IN_WHEEL_SPEED_RAD_S];
    int ph;
    if (s->started != 0.0) {
        s->wheel_accel = (w - s->wheel_speed_prev) * s->p.wheel_radius_m / s->p.ts_s;
    }
    s->wheel_speed_prev = w;
    s->started = 1.0;
    ph = ct_next_phase((int)s->phase, in[CT_IN_SLIP], s->wheel_accel,
                       s->p.target_slip + s->p.slip_margin, s->p.decel_threshold_m_s2,
                       s->p.accel_threshold_m_s2);
    s->phase = (double)ph;
    if (ph == CT_BUILD) return s->p.amplitude;
    if (ph == CT_DUMP) return -s->p.amplitude;
    if (ph == CT_SLOW) return s->p.amplitude * s->p.slow_fraction;
    return 0.0;
}
"""
"""`ecu_step`'s step in C, in the same operation order."""


@functools.cache
def kernel_forms() -> tuple[Any, Any]:
    """(start, tick) for the kernels: at rest at the start; at each sample the wheel
    acceleration over the last one (none at the first), then the phase machine's command
    (`controllers.switching.threshold_step`)."""
    from numba import njit

    from chassistune.controllers.switching import threshold_step, wheel_deceleration_sample

    @njit(**F.FORM)
    def tick(sig, held, mem, g, g0, c, table, ts, first):
        aw = mem[M_ACCEL]
        if not first:
            aw = wheel_deceleration_sample(
                sig[F.SIG_WHEEL_SPEED], sig[F.SIG_WHEEL_SPEED_PREV], sig[F.SIG_RADIUS], ts
            )
        u0, phase = threshold_step(
            int(mem[M_PHASE]),
            sig[F.SIG_SLIP],
            sig[F.SIG_TARGET],
            aw,
            c[F.P_AMPLITUDE],
            c[F.P_DECEL],
            c[F.P_ACCEL],
            c[F.P_SLIP_MARGIN],
            c[F.P_SLOW],
        )
        return (u0, held[F.H_KP], held[F.H_KI], held[F.H_KD]), (float(phase), aw)

    return None, tick


@functools.cache
def ecu_step() -> Any:
    """The law's step in the realistic ECU and the export, `u = step(state, inputs, params,
    table, grid)` on the vectors of `controllers.discrete`: the phase machine
    (`controllers.switching.threshold_step`) fed the wheel acceleration over the last sample."""
    from numba import njit

    from chassistune.controllers.switching import threshold_step, wheel_deceleration_sample

    @njit(**F.FORM)
    def step(state, inputs, params, table, grid):
        w = inputs[IN_WHEEL_SPEED]
        ts = params[D_TS]
        if state[S_STARTED] != 0.0:
            state[S_ACCEL] = wheel_deceleration_sample(w, state[S_W_PREV], params[D_RADIUS], ts)
        state[S_W_PREV] = w
        state[S_STARTED] = 1.0
        u, ph = threshold_step(
            int(state[S_PHASE]),
            inputs[IN_SLIP],
            params[D_TARGET],
            state[S_ACCEL],
            params[D_AMP],
            params[D_DECEL],
            params[D_ACCEL],
            params[D_MARGIN],
            params[D_SLOW],
        )
        state[S_PHASE] = ph
        return u

    return step


LAW = Law(
    "threshold",
    (WHEEL, per_wheel(WHEEL, params=(*WHEEL.params, REAR))),
    kernel_forms,
    STATE,
    discrete=DISCRETE,
    ecu=EcuForm(ecu_step),
    c=CForm(
        (
            "- `threshold` (design.md 4's rule-based ABS, the kernel's phases): "
            "aw_k = (w_k - w_k-1) R / ts",
            "(0 at k = 0), then the phase machine build -> hold -> dump -> recover -> slow build,"
            " with",
            "u = +amplitude (build), 0 (hold, recover), -amplitude (dump), slow_fraction "
            "amplitude (slow).",
        ),
        C_STEP,
        switching=True,
    ),
    source="ours, after the classic Bosch cycle of deceleration and slip thresholds (docs/abs.md)",
)
