"""Fuzzy self-tuning PID (deffao-vehicle-abs, design.md 4): the PID's gains scheduled from e and
de/dt by a 7x7 rule base with three outputs (`controllers.fuzzy_pid.fuzzy_pid_gains`), sampled
every ts_s; the ECU and the export read an interpolated table (`controllers.discrete`) in its
discrete form (`ecu_step`), the discrete PID's (`laws.pid`) with the gains scheduled.

Vehicle defaults: the gains span kp0 + [0, 1] ku_p (deffao outputs are magnitudes in [0, 1]),
centred on the vehicle PID (`laws.pid`): kp in [700, 1700], kd in [15, 25], ki 0.
"""

from __future__ import annotations

import functools
from typing import Any

from chassistune.controllers.laws import forms as F
from chassistune.controllers.laws import pid
from chassistune.controllers.laws.registry import ABS_WHEEL, CForm, DiscreteLaw, EcuForm, Law
from chassistune.controllers.laws.shared import (
    N_FILTER,
    RULEBASE_NOTE,
    SAMPLE_PERIOD,
    per_wheel,
    rescaled,
)
from chassistune.controllers.specs import ControllerSpec, GainSpec, ParamSpec

KE = GainSpec(
    "ke",
    "1/(slip)",
    15.0,
    0.1,
    100.0,
    "quantization factor of the slip error e into the rule base's input universe",
)
KEC = GainSpec(
    "kec",
    "s/(slip)",
    0.3,
    1e-3,
    10.0,
    "quantization factor of de/dt (filtered) into the rule base's input universe",
)

WHEEL = ControllerSpec(
    ABS_WHEEL,
    "fuzzy-pid",
    "fuzzy self-tuning PID (deffao-vehicle-abs): gains scheduled from e and de/dt by a 7x7 "
    "rule base, kp = kp0 + ku_p * out_kp (likewise ki, kd), sampled every ts_s",
    gains=(
        KE,
        KEC,
        GainSpec("ku_p", "1/(slip)", 4000.0, 0.0, 1e4, "output scale of the kp rule table"),
        GainSpec("ku_i", "1/(slip s)", 0.0, 0.0, 1e4, "output scale of the ki rule table"),
        GainSpec("ku_d", "s/(slip)", 100.0, 0.0, 1e3, "output scale of the kd rule table"),
        GainSpec("kp0", "1/(slip)", 3000.0, 0.0, 1e4, "base proportional gain"),
        GainSpec("ki0", "1/(slip s)", 0.0, 0.0, 1e4, "base integral gain"),
        GainSpec("kd0", "s/(slip)", 180.0, 0.0, 1e3, "base derivative gain"),
    ),
    params=(
        ParamSpec("rulebase", "-", "deffao", RULEBASE_NOTE),
        N_FILTER,
        SAMPLE_PERIOD,
    ),
)

VEHICLE_DEFAULTS = {
    "ku_p": 1000.0,
    "ku_i": 0.0,
    "ku_d": 10.0,
    "kp0": 700.0,
    "ki0": 0.0,
    "kd0": 15.0,
}
VEHICLE_BOUNDS = {
    "ku_p": (0.0, 5000.0),
    "ku_i": (0.0, 5000.0),
    "ku_d": (0.0, 100.0),
    "kp0": (0.0, 5000.0),
    "ki0": (0.0, 5000.0),
    "kd0": (0.0, 100.0),
}

GAINS = ("ke", "kec", "ku_p", "ku_i", "ku_d", "kp0", "ki0", "kd0")
G_KE, G_KEC, G_KUP, G_KUI, G_KUD, G_KP0, G_KI0, G_KD0 = (F.gains(WHEEL)[n] for n in GAINS)

DISCRETE = DiscreteLaw(
    "fuzzy-pid",
    pid.DISCRETE.inputs,
    (*GAINS, "n_filter", "target_slip", "ts_s"),
    pid.DISCRETE.state,
    3,
    "parallel PID with table-scheduled gains, forward-Euler integrator, backward-Euler "
    "derivative filter",
)
"""The discrete fuzzy PID (`ecu_step`) by name: the discrete PID's inputs and state (it runs
its filter and output), its gains first."""
D_KE, D_KEC, D_KUP, D_KUI, D_KUD, D_KP0, D_KI0, D_KD0, D_N, D_TARGET, D_TS = (
    DISCRETE.params.index(n) for n in (*GAINS, "n_filter", "target_slip", "ts_s")
)
IN_SLIP = DISCRETE.inputs.index("slip")


@functools.cache
def kernel_forms() -> tuple[Any, Any]:
    """(start, tick) for the kernels: at rest at the start; at each sample the PID's gains
    scheduled from e and the filtered de/dt (`controllers.fuzzy_pid.fuzzy_pid_gains`)."""
    from numba import njit

    from chassistune.controllers.fuzzy_pid import fuzzy_pid_gains

    @njit(**F.FORM)
    def tick(sig, held, mem, g, g0, c, table, ts, first):
        kp, ki, kd = fuzzy_pid_gains(
            table,
            sig[F.SIG_SLIP_ERROR],
            sig[F.SIG_ERROR_RATE],
            g[g0 + G_KE],
            g[g0 + G_KEC],
            g[g0 + G_KUP],
            g[g0 + G_KUI],
            g[g0 + G_KUD],
            g[g0 + G_KP0],
            g[g0 + G_KI0],
            g[g0 + G_KD0],
        )
        return (held[F.H_U0], kp, ki, kd), mem

    return None, tick


@functools.cache
def ecu_step() -> Any:
    """The law's step in the realistic ECU and the export, `u = step(state, inputs, params,
    table, grid)` on the vectors of `controllers.discrete`: the discrete PID's filter and output
    (`laws.pid.ecu_forms`) with kp, ki, kd scheduled every sample from the ECU table at
    (ke e, kec d) (`controllers.discrete_lookup`)."""
    from numba import njit

    from chassistune.controllers.discrete_lookup import table_cell, table_value

    filtered_derivative, pid_output, _ = pid.ecu_forms()

    @njit(**F.FORM)
    def step(state, inputs, params, table, grid):
        e = params[D_TARGET] - inputs[IN_SLIP]
        d = filtered_derivative(state, e, params[D_N], params[D_TS])
        cell = table_cell(table, grid, params[D_KE] * e, params[D_KEC] * d)
        kp = params[D_KP0] + params[D_KUP] * table_value(table, 0, cell)
        ki = params[D_KI0] + params[D_KUI] * table_value(table, 1, cell)
        kd = params[D_KD0] + params[D_KUD] * table_value(table, 2, cell)
        return pid_output(state, inputs, e, d, kp, ki, kd, params[D_TS])

    return step


LAW = Law(
    "fuzzy-pid",
    (WHEEL, per_wheel(WHEEL, gains=rescaled(WHEEL.gains, VEHICLE_DEFAULTS, VEHICLE_BOUNDS))),
    kernel_forms,
    discrete=DISCRETE,
    ecu=EcuForm(ecu_step, scheduled=("kp0", "ku_p", "kd0", "ku_d"), rate=True),
    c=CForm(
        (
            *pid.EQUATIONS,
            "- `fuzzy-pid` (Tian 2025): the same PID with kp, ki, kd scheduled every sample from "
            "the table at",
            "(ke e_k, kec d_k): kp = kp0 + ku_p T_kp(ke e_k, kec d_k), likewise ki, kd.",
        ),
        """\
double ct_step(ct_state *s, const double *in)
{
    double e = s->p.target_slip - in[CT_IN_SLIP];
    double d = ct_filtered_derivative(s, e, s->p.n_filter, s->p.ts_s);
    ct_cell c = ct_table_cell(s->p.ke * e, s->p.kec * d);
    double kp = s->p.kp0 + s->p.ku_p * ct_lookup(ct_table_{0}, c);
    double ki = s->p.ki0 + s->p.ku_i * ct_lookup(ct_table_{1}, c);
    double kd = s->p.kd0 + s->p.ku_d * ct_lookup(ct_table_{2}, c);
    return ct_pid_output(s, in, e, d, kp, ki, kd, s->p.ts_s);
}
""",
        helpers=(pid.C_HELPERS,),
    ),
    rulebase_outputs=3,
    source="deffao-vehicle-abs (Tian, Huang et al. 2025): the fuzzy self-tuning PID, its rule base",
)
