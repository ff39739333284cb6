"""Fuzzy immune PID (fuzzy-immune-abs, design.md 4): an incremental PID whose proportional gain
kp1 = k_immune (1 - eta f(e, de/dt)) a one-output rule base suppresses
(`controllers.immune_pid.immune_pid_step`), sampled every ts_s. Single wheel only."""

from __future__ import annotations

import functools
from typing import Any

from chassistune.controllers.laws import forms as F
from chassistune.controllers.laws.registry import ABS_WHEEL, CForm, DiscreteLaw, EcuForm, Law
from chassistune.controllers.laws.shared import RULEBASE_NOTE, SAMPLE_PERIOD
from chassistune.controllers.specs import ControllerSpec, GainSpec, ParamSpec

WHEEL = ControllerSpec(
    ABS_WHEEL,
    "fuzzy-immune-pid",
    "fuzzy immune PID (fuzzy-immune-abs): incremental PID with immune gain "
    "kp1 = k_immune (1 - eta f(e, de/dt)), sampled every ts_s",
    gains=(
        GainSpec(
            "k_immune",
            "1/(slip)",
            1000.0,
            0.0,
            1e4,
            "immune proportional gain K (not the actuator's gain)",
        ),
        GainSpec("eta", "-", 0.5, 0.0, 0.99, "immune suppression factor (kp1 > 0 needs < 1)"),
        GainSpec("ki", "1/(slip s)", 0.0, 0.0, 1e4, "integral gain of the incremental law"),
        GainSpec("kd", "s/(slip)", 50.0, 0.0, 1e3, "derivative gain of the incremental law"),
        GainSpec("ke", "1/(slip)", 5.0, 0.1, 100.0, "quantization factor of e into [-1, 1]"),
        GainSpec("kec", "s/(slip)", 0.1, 1e-3, 10.0, "quantization factor of de/dt into [-1, 1]"),
    ),
    params=(
        ParamSpec("rulebase", "-", "immune", RULEBASE_NOTE),
        SAMPLE_PERIOD,
    ),
)

C_STEP = """\
/* fuzzy-immune-abs eq. 10 as DESIGN 4 reads it: the increment of the incremental PID */
static double ct_incremental_du(double kp1, double ki, double kd, double ts, double e0,
                                double e1, double e2)
{
    return kp1 * (e0 - e1) + ki * ts * e0 + kd * (e0 - 2.0 * e1 + e2) / ts;
}

double ct_step(ct_state *s, const double *in)
{
    double ts = s->p.ts_s;
    double e = s->p.target_slip - in[CT_IN_SLIP];
    int first = s->started == 0.0;
    double ec = first ? 0.0 : (e - s->e_prev) / ts;
    double f = ct_lookup(ct_table_{0}, ct_table_cell(s->p.ke * e, s->p.kec * ec));
    double kp1 = s->p.k_immune * (1.0 - s->p.eta * f);
    double u;
    if (first) {
        u = s->u_prev + ct_incremental_du(kp1, s->p.ki, 0.0, ts, e, 0.0, 0.0);
        s->e_prev2 = e;
    } else {
        u = s->u_prev + ct_incremental_du(kp1, s->p.ki, s->p.kd, ts, e, s->e_prev, s->e_prev2);
        s->e_prev2 = s->e_prev;
    }
    s->e_prev = e;
    s->u_prev = u;
    s->started = 1.0;
    return u;
}
"""
"""`ecu_step`'s step in C, in the same operation order."""

STATE = ("e_prev", "e_prev2")
"""The law's memory: the slip errors of the last two samples."""
M_E1, M_E2 = range(len(STATE))
GAINS = ("k_immune", "eta", "ki", "kd", "ke", "kec")
G_K, G_ETA, G_KI, G_KD, G_KE, G_KEC = (F.gains(WHEEL)[n] for n in GAINS)

DISCRETE = DiscreteLaw(
    "fuzzy-immune-pid",
    ("slip",),
    (*GAINS, "target_slip", "ts_s"),
    ("started", "u_prev", "e_prev", "e_prev2"),
    1,
    "incremental (velocity) PID with table-scheduled proportional gain",
)
"""The discrete fuzzy immune PID (`ecu_step`) by name, its gains first."""
D_K, D_ETA, D_KI, D_KD, D_KE, D_KEC, D_TARGET, D_TS = (
    DISCRETE.params.index(n) for n in (*GAINS, "target_slip", "ts_s")
)
S_STARTED, S_U, S_E1, S_E2 = (
    DISCRETE.state.index(n) for n in ("started", "u_prev", "e_prev", "e_prev2")
)
IN_SLIP = DISCRETE.inputs.index("slip")


@functools.cache
def kernel_forms() -> tuple[Any, Any]:
    """(start, tick) for the kernels: at rest at the start; at each sample the incremental law's
    next command (`immune_pid_step`), the errors before the first sample taken as e(0) = the
    target (the wheel rolls freely: no kick)."""
    from numba import njit

    from chassistune.controllers.immune_pid import immune_pid_step

    @njit(**F.FORM)
    def tick(sig, held, mem, g, g0, c, table, ts, first):
        e = sig[F.SIG_SLIP_ERROR]
        e1 = sig[F.SIG_TARGET] if first else mem[M_E1]
        e2 = sig[F.SIG_TARGET] if first else mem[M_E2]
        u0 = immune_pid_step(
            table,
            e,
            e1,
            e2,
            held[F.H_U0],
            ts,
            first,
            g[g0 + G_K],
            g[g0 + G_ETA],
            g[g0 + G_KI],
            g[g0 + G_KD],
            g[g0 + G_KE],
            g[g0 + G_KEC],
        )
        return (u0, held[F.H_KP], held[F.H_KI], held[F.H_KD]), (e, e1)

    return None, tick


@functools.cache
def ecu_step() -> Any:
    """The law's step in the realistic ECU and the export, `u = step(state, inputs, params,
    table, grid)` on the vectors of `controllers.discrete`: the incremental law of the C form's
    equations, its gain kp1 read from the ECU table (`controllers.discrete_lookup`)."""
    from numba import njit

    from chassistune.controllers.discrete_lookup import table_cell, table_value
    from chassistune.controllers.immune_pid import incremental_pid_du

    @njit(**F.FORM)
    def step(state, inputs, params, table, grid):
        ts = params[D_TS]
        e = params[D_TARGET] - inputs[IN_SLIP]
        first = state[S_STARTED] == 0.0
        ec = 0.0 if first else (e - state[S_E1]) / ts
        f = table_value(table, 0, table_cell(table, grid, params[D_KE] * e, params[D_KEC] * ec))
        kp1 = params[D_K] * (1.0 - params[D_ETA] * f)
        if first:
            u = state[S_U] + incremental_pid_du(kp1, params[D_KI], 0.0, ts, e, 0.0, 0.0)
            state[S_E2] = e
        else:
            u = state[S_U] + incremental_pid_du(
                kp1, params[D_KI], params[D_KD], ts, e, state[S_E1], state[S_E2]
            )
            state[S_E2] = state[S_E1]
        state[S_E1] = e
        state[S_U] = u
        state[S_STARTED] = 1.0
        return u

    return step


LAW = Law(
    "fuzzy-immune-pid",
    (WHEEL,),
    kernel_forms,
    STATE,
    discrete=DISCRETE,
    ecu=EcuForm(ecu_step, scheduled=("k_immune", "kd"), rate=True),
    c=CForm(
        (
            "- `fuzzy-immune-pid` (Ding 2023 eqs. 6-10, the kernel's arithmetic): "
            "ec_k = (e_k - e_k-1) / ts",
            "(0 at k = 0), kp1 = k_immune (1 - eta T_f(ke e_k, kec ec_k)),",
            "u_k = u_k-1 + kp1 (e_k - e_k-1) + ki ts e_k + kd (e_k - 2 e_k-1 + e_k-2) / ts,",
            "starting from rest (u = 0, e = 0 before k = 0, no derivative term at k = 0); "
            "after k = 0,",
            "e_k-1 = e_k-2 = e_0 (the kernel's start, where the slip is 0 at the first sample).",
        ),
        C_STEP,
    ),
    rulebase_outputs=1,
    source="fuzzy-immune-abs (Ding 2023): the fuzzy immune PID",
)
