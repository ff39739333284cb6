"""The slip PID (design.md 4, derlsp-ao-abs eq. 12): continuous in the ideal kernels
(`controllers.pid`), sampled in the ECU and the export (`ecu_forms`: the discrete PID of the
`EQUATIONS`, whose filter and output the fuzzy PID shares).

Vehicle defaults of their own: with J = 0.6 kg m^2 the rear wheels carry about 1230 N while
braking, and the single wheel's PID 5000/0/230 makes them lock-cycle (mu-jump 98.35 m, no better
than no ABS), so the vehicle PID defaults to kp 1200, ki 0, kd 20 (design.md 3.3).
"""

from __future__ import annotations

import functools
from typing import Any

from chassistune.controllers.laws.forms import FORM, gains
from chassistune.controllers.laws.registry import ABS_WHEEL, CForm, DiscreteLaw, EcuForm, Law
from chassistune.controllers.laws.shared import N_FILTER, per_wheel
from chassistune.controllers.specs import ControllerSpec, GainSpec

WHEEL = ControllerSpec(
    ABS_WHEEL,
    "pid",
    "PID on the slip error e = S_target - S (derlsp-ao-abs eq. 12), filtered derivative "
    "without kick, conditional-integration anti-windup",
    gains=(
        GainSpec(
            "kp",
            "1/(slip)",
            5000.0,
            0.0,
            1e4,
            "proportional gain (acts like an integral gain on pressure: the actuator integrates)",
        ),
        GainSpec("ki", "1/(slip s)", 0.0, 0.0, 1e4, "integral gain"),
        GainSpec(
            "kd",
            "s/(slip)",
            230.0,
            0.0,
            1e3,
            "derivative gain (acts like a proportional gain on pressure)",
        ),
    ),
    params=(N_FILTER,),
)

VEHICLE_GAINS = (
    GainSpec(
        "kp",
        "1/(slip)",
        1200.0,
        0.0,
        5000.0,
        "proportional gain (an integral gain on pressure: the actuator integrates)",
    ),
    GainSpec("ki", "1/(slip s)", 0.0, 0.0, 5000.0, "integral gain"),
    GainSpec(
        "kd", "s/(slip)", 20.0, 0.0, 100.0, "derivative gain (a proportional gain on pressure)"
    ),
)

EQUATIONS = (
    "- `pid` (design.md 4 in discrete time; Simulink's discrete PID, parallel form, forward-Euler",
    "integrator, backward-Euler derivative filter: stable at any ts, unlike a forward-Euler "
    "filter,",
    "which needs N ts < 2):",
    "xf_0 = e_0,  xf_k = (xf_k-1 + ts N e_k) / (1 + ts N)         (backward Euler, no kick)",
    "d_k = N (e_k - xf_k)                                           (filtered de/dt)",
    "u_k = kp e_k + ki z_k + kd d_k",
    "z_k+1 = z_k + ts e_k, unless (pressure_at_max and e_k > 0) or (pressure_at_min and e_k < 0)",
)
"""The discrete PID (`ecu_forms`), as controller.h prints it."""

C_HELPERS = """\
/* backward-Euler derivative filter: xf_k = (xf_k-1 + ts N e_k) / (1 + ts N), d = N (e - xf) */
static double ct_filtered_derivative(ct_state *s, double e, double n_filter, double ts)
{
    if (s->started == 0.0) {
        s->filter = e;
    } else {
        double a = ts * n_filter;
        s->filter = (s->filter + a * e) / (1.0 + a);
    }
    return n_filter * (e - s->filter);
}

/* u = kp e + ki z + kd d; forward-Euler integral with conditional integration (anti-windup) */
static double ct_pid_output(ct_state *s, const double *in, double e, double d, double kp,
                            double ki, double kd, double ts)
{
    double u = kp * e + ki * s->integral + kd * d;
    int at_max = in[CT_IN_PRESSURE_AT_MAX] != 0.0;
    int at_min = in[CT_IN_PRESSURE_AT_MIN] != 0.0;
    if (!((at_max && e > 0.0) || (at_min && e < 0.0))) {
        s->integral = s->integral + ts * e;
    }
    s->started = 1.0;
    return u;
}
"""
"""The filtered derivative and the PID output of the discrete PID in C (the PID laws share it)."""

G_KP, G_KI, G_KD = (gains(WHEEL)[n] for n in ("kp", "ki", "kd"))

DISCRETE = DiscreteLaw(
    "pid",
    ("slip", "pressure_at_max", "pressure_at_min"),
    ("kp", "ki", "kd", "n_filter", "target_slip", "ts_s"),
    ("started", "integral", "filter"),
    0,
    "parallel PID, forward-Euler integrator, backward-Euler derivative filter",
)
"""The discrete PID (`EQUATIONS`, `ecu_forms`) by name."""
D_KP, D_KI, D_KD, D_N, D_TARGET, D_TS = (
    DISCRETE.params.index(n) for n in ("kp", "ki", "kd", "n_filter", "target_slip", "ts_s")
)
S_STARTED, S_INTEGRAL, S_FILTER = (
    DISCRETE.state.index(n) for n in ("started", "integral", "filter")
)
IN_SLIP, IN_AT_MAX, IN_AT_MIN = (
    DISCRETE.inputs.index(n) for n in ("slip", "pressure_at_max", "pressure_at_min")
)


@functools.cache
def kernel_forms() -> tuple[Any, Any]:
    """(start, tick) for the kernels: the gains of the continuous PID (`controllers.pid.pid_step`),
    fixed for the run; no tick."""
    from numba import njit

    @njit(**FORM)
    def start(g, g0, c):
        return 0.0, g[g0 + G_KP], g[g0 + G_KI], g[g0 + G_KD]

    return start, None


@functools.cache
def ecu_forms() -> tuple[Any, Any, Any]:
    """(filtered_derivative, pid_output, step): the discrete PID (`EQUATIONS`) on the vectors of
    `controllers.discrete`, `u = step(state, inputs, params, table, grid)` (the law's step in
    the realistic ECU and the export), and its two halves, which the fuzzy PID shares."""
    from numba import njit

    @njit(**FORM)
    def filtered_derivative(state, e, n_filter, ts):
        """Backward-Euler derivative filter: xf_k = (xf_k-1 + ts N e_k) / (1 + ts N),
        d = N (e - xf)."""
        if state[S_STARTED] == 0.0:
            state[S_FILTER] = e
        else:
            a = ts * n_filter
            state[S_FILTER] = (state[S_FILTER] + a * e) / (1.0 + a)
        return n_filter * (e - state[S_FILTER])

    @njit(**FORM)
    def pid_output(state, inputs, e, d, kp, ki, kd, ts):
        """u = kp e + ki z + kd d, then the forward-Euler integral with conditional
        integration."""
        u = kp * e + ki * state[S_INTEGRAL] + kd * d
        at_max = inputs[IN_AT_MAX] != 0.0
        at_min = inputs[IN_AT_MIN] != 0.0
        if not ((at_max and e > 0.0) or (at_min and e < 0.0)):
            state[S_INTEGRAL] = state[S_INTEGRAL] + ts * e
        state[S_STARTED] = 1.0
        return u

    @njit(**FORM)
    def step(state, inputs, params, table, grid):
        """The discrete PID (`EQUATIONS`)."""
        e = params[D_TARGET] - inputs[IN_SLIP]
        d = filtered_derivative(state, e, params[D_N], params[D_TS])
        return pid_output(
            state, inputs, e, d, params[D_KP], params[D_KI], params[D_KD], params[D_TS]
        )

    return filtered_derivative, pid_output, step


def ecu_step() -> Any:
    """The law's step in the realistic ECU: its discrete form (`ecu_forms`)."""
    return ecu_forms()[2]


LAW = Law(
    "pid",
    (WHEEL, per_wheel(WHEEL, gains=VEHICLE_GAINS)),
    kernel_forms,
    discrete=DISCRETE,
    ecu=EcuForm(ecu_step, scheduled=("kp", "kd"), rate=True),
    c=CForm(
        EQUATIONS,
        """\
double ct_step(ct_state *s, const double *in)
{
    double e = s->p.target_slip - in[CT_IN_SLIP];
    double d = ct_filtered_derivative(s, e, s->p.n_filter, s->p.ts_s);
    return ct_pid_output(s, in, e, d, s->p.kp, s->p.ki, s->p.kd, s->p.ts_s);
}
""",
        helpers=(C_HELPERS,),
    ),
    source="the papers' slip PID: derlsp-ao-abs eq. 12 (Tian et al.), design.md 4",
)
