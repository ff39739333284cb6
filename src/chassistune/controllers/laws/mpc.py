"""Model-predictive slip control (docs/abs_laws.md 5; Petersen, Johansen, Kalkkuhl and Ludemann,
"Wheel slip control in ABS brakes using gain scheduled constrained LQR", ECC 2001): each sample,
the pressure moves z_j = q_j+1 - q_j, j = 0 .. N-1, that minimise the squared error of the
projected slip and a move penalty on the linearised wheel-slip dynamics dS/dt = (b q - c F) / v
(`sliding_mode`'s slip model, force and 1 - S frozen at the sample, the force F_k the ECU's
estimate, v floored at 1 m/s), under the actuator's pressure-rate and pressure limits; the first
move is applied (receding horizon). The horizon N is the fixed parameter `horizon` (1 .. 5,
default 1), read at run time. The N-step prediction, with d = (b q_k - c F_k) / v:

    S_j = S_k + j ts d + (ts b / v) sum_l<j (j - l) z_l                      (j = 1 .. N)
    y_j = S_j + T_L (d + (b / v) sum_l<j z_l) = y_free_j + sum_l<j G_jl z_l  (T_L ahead)
    y_free_j = S_k + j ts d + T_L d,   G_jl = beta (j - l) + gamma,
    beta = ts b / v,   gamma = T_L b / v
    minimise sum_j (y_j - S*)^2 + rho sum_l (z_l / q_max)^2:
    H = 2 (G'G + rho / q_max^2 I),  f = 2 G'(y_free - S*)
    subject to |z_l| <= r_max ts,  0 <= q0 + z_0 + ... + z_l <= q_max,  q0 = clamp(q_k, 0, q_max)
    r_k = z_0 / ts,   u = r_k / K

N = 1 in closed form (the box and the pressure rows intersect into one interval, the minimiser
clamped into it, `slip_mpc_qp.horizon1_move`):

    G = (ts + T_L) b / v,   y_free = S_k + (ts + T_L)(b q_k - c F_k) / v
    h = 2 (G^2 + rho / q_max^2),   f = 2 G (y_free - S*)
    z = clamp(-f / h, max(-r_max ts, -q0), min(r_max ts, q_max - q0))

N > 1 by `slip_mpc_qp.solve_moves` at its fixed iteration count (IPM_ITERATIONS predictor-
corrector steps, POLISH_STEPS polish steps), its scratch on the stack of fixed size
MAX_HORIZON (the kernels run without numba's runtime). The horizon is the same in every lane of
a run, so the lanes take the same branch. The same forms run in the ideal kernels (the tick),
the ECU and the C export (the discrete step, `C_STEP` with `slip_mpc_qp.C_SOLVER`).
"""

from __future__ import annotations

import functools
from typing import Any

from chassistune.controllers.laws import forms as F
from chassistune.controllers.laws import wheel_estimates as W
from chassistune.controllers.laws.registry import ABS_WHEEL, CForm, DiscreteLaw, EcuForm, Law
from chassistune.controllers.laws.shared import VEHICLE_PARAMS, per_wheel
from chassistune.controllers.slip_mpc_qp_c import C_SOLVER, MAX_HORIZON
from chassistune.controllers.specs import ControllerSpec, GainSpec, ParamSpec

HORIZON = ParamSpec(
    "horizon",
    "samples",
    1.0,
    f"samples predicted N (1: the closed form; 2 .. {MAX_HORIZON}: the interior-point QP)",
    integers=(1, MAX_HORIZON),
)
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
    params=(W.SAMPLE_PERIOD, HORIZON, *W.WHEEL_CALIBRATION),
)
VEHICLE = per_wheel(
    WHEEL, params=(W.SAMPLE_PERIOD, HORIZON, *W.VEHICLE_CALIBRATION, *VEHICLE_PARAMS)
)
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
    (
        *(g.name for g in GAINS),
        *W.CALIBRATION,
        "target_slip",
        "ts_s",
        "wheel_radius_m",
        "horizon",
    ),
    ("started",),
    0,
    "model-predictive slip control: the first of N moves of a QP under rate and pressure limits",
)
"""The discrete law (`ecu_step`) by name."""
_p = DISCRETE.params.index
D_LOOKAHEAD, D_WEIGHT = _p("lookahead_s"), _p("move_weight")
D_I, D_M, D_KQ, D_QMAX, D_K, D_RATE = (_p(n) for n in W.CALIBRATION)
D_TARGET, D_TS, D_RADIUS = _p("target_slip"), _p("ts_s"), _p("wheel_radius_m")
D_HORIZON = _p("horizon")
IN_SLIP, IN_V, IN_W, IN_W_PREV, IN_Q, IN_Q_PREV = range(len(DISCRETE.inputs))

EQUATIONS = (
    "- `mpc` (docs/abs_laws.md 5): F_k = (kq (q_k + q_k-1) / 2 + I (w_k - w_k-1) / ts) / R,",
    "b = R kq / I, c = R^2 / I + (1 - S_k) / M, v = max(v_k, 1), q0 = clamp(q_k, 0, q_max),",
    "dq = r_max ts; horizon N = 1: G = (ts + T_L) b / v,",
    "y = S_k + (ts + T_L) (b q_k - c F_k) / v, h = 2 (G^2 + rho / q_max^2), f = 2 G (y - S*),",
    "z = clamp(-f / h, max(-dq, -q0), min(dq, q_max - q0));",
    "N > 1: d = (b q_k - c F_k) / v, beta = ts b / v, gamma = T_L b / v,",
    "y_j = S_k + j ts d + T_L d, G_jl = beta (j - l) + gamma (l < j),",
    "H = 2 (G'G + rho / q_max^2 I), f = 2 G'(y - S*), z = the first of the moves that minimise",
    "z'H z / 2 + f'z with |z_l| <= dq, 0 <= q0 + z_0 + .. + z_l <= q_max (interior point, fixed",
    "iterations, ct_qp_solve_moves); u_k = clamp(z / ts, -r_max, r_max) / K",
)

C_STEP = """\
/* the first move of the horizon-n QP (n > 1) */
static double ct_mpc_horizon_move(int n, double slip, double target, double q0, double drift,
                                  double beta, double gamma, double lookahead, double ts,
                                  double weight, double q_max, double dq)
{
    double h[CT_QP_N][CT_QP_N], f[CT_QP_N], lo[CT_QP_N], hi[CT_QP_N], z[CT_QP_N];
    double penalty = weight / (q_max * q_max), err, g;
    int a, col, i;
    for (a = 0; a < n; a++) {
        lo[a] = -dq;
        hi[a] = dq;
        f[a] = 0.0;
        for (col = 0; col < n; col++) h[a][col] = a == col ? penalty : 0.0;
    }
    for (i = 0; i < n; i++) {
        err = slip + (i + 1) * ts * drift + lookahead * drift - target;
        for (a = 0; a <= i; a++) {
            g = beta * (i + 1 - a) + gamma;
            f[a] += g * err;
            for (col = 0; col <= i; col++) h[a][col] += g * (beta * (i + 1 - col) + gamma);
        }
    }
    for (a = 0; a < n; a++) {
        f[a] *= 2.0;
        for (col = 0; col < n; col++) h[a][col] *= 2.0;
    }
    ct_qp_solve_moves(n, h, f, lo, hi, q0, q_max, z);
    return z[0];
}

double ct_step(ct_state *s, const double *in)
{
    double radius = s->p.wheel_radius_m, inertia = s->p.nominal_inertia_kg_m2;
    double ts = s->p.ts_s, q_max = s->p.nominal_q_max, slip = in[CT_IN_SLIP];
    double q = in[CT_IN_PRESSURE], v = in[CT_IN_REFERENCE_SPEED_M_S];
    double f = ct_force_estimate(s, in);
    double b = radius * s->p.nominal_brake_gain / inertia;
    double c = radius * radius / inertia + (1.0 - slip) / s->p.nominal_mass_kg;
    double reach, gain, free, h, lin, q0, dq, lo, hi, z;
    int horizon = (int)s->p.horizon;
    s->started = 1.0;
    if (v < 1.0) v = 1.0;
    q0 = q;
    if (q0 > q_max) q0 = q_max;
    if (q0 < 0.0) q0 = 0.0;
    dq = s->p.rate_limit * ts;
    if (horizon > 1) {
        z = ct_mpc_horizon_move(horizon, slip, s->p.target_slip, q0, (b * q - c * f) / v,
                                ts * b / v, s->p.lookahead_s * b / v, s->p.lookahead_s, ts,
                                s->p.move_weight, q_max, dq);
        return ct_rate_limit(z / ts, s->p.rate_limit) / s->p.nominal_actuator_gain;
    }
    reach = ts + s->p.lookahead_s;
    gain = reach * b / v;
    free = slip + reach * (b * q - c * f) / v;
    h = 2.0 * (gain * gain + s->p.move_weight / (q_max * q_max));
    lin = 2.0 * gain * (free - s->p.target_slip);
    lo = -q0 > -dq ? -q0 : -dq;
    hi = q_max - q0 < dq ? q_max - q0 : dq;
    z = -lin / h;
    if (z < lo) z = lo;
    if (z > hi) z = hi;
    return ct_rate_limit(z / ts, s->p.rate_limit) / s->p.nominal_actuator_gain;
}
"""
"""`ecu_step`'s step in C, in the same operation order (`slip_mpc_qp_c.C_SOLVER` before it)."""


@functools.cache
def compiled() -> tuple[Any, Any, Any]:
    """(tick, step, move): the law at each sample of the ideal kernels (`Law.forms`: the command
    held as u0, the PID's gains left at zero), its discrete step on the vectors of
    `controllers.discrete` (the realistic ECU and the export), both through `move`, the first
    move z_0 of the QP (module docstring)."""
    from numba import njit

    from chassistune.controllers import slip_mpc_qp as qp

    force_estimate, rate_limit = W.forms()
    tick_force = W.tick_force()

    @njit(cache=True, nogil=True, error_model="numpy")
    def horizon_move(n, slip, target, q0, drift, beta, gamma, lookahead, ts, weight, q_max, dq):
        """z_0 of the horizon-n QP, n > 1 (module docstring), by `slip_mpc_qp.solve_moves` on
        a scratch on this function's stack."""
        h, f, lo, hi, z, mat, vec = qp.stack_scratch(n)
        penalty = weight / (q_max * q_max)
        for a in range(n):
            lo[a] = -dq
            hi[a] = dq
            f[a] = 0.0
            for col in range(n):
                h[a, col] = penalty if a == col else 0.0
        for i in range(n):
            err = slip + (i + 1) * ts * drift + lookahead * drift - target
            for a in range(i + 1):
                g = beta * (i + 1 - a) + gamma
                f[a] += g * err
                for col in range(i + 1):
                    h[a, col] += g * (beta * (i + 1 - col) + gamma)
        for a in range(n):
            f[a] *= 2.0
            for col in range(n):
                h[a, col] *= 2.0
        qp.solve_moves(h, f, lo, hi, q0, q_max, qp.IPM_ITERATIONS, qp.POLISH_STEPS, z, mat, vec)
        return z[0]

    @njit(**F.FORM)
    def move(
        slip, target, v_ref, q, f, lookahead, weight, ts, q_max, rate, radius, inertia, m, kq, n
    ):
        """The first pressure move z_0 of the horizon-n QP (module docstring): the closed form
        for n = 1, else `horizon_move`."""
        b = radius * kq / inertia
        c = radius * radius / inertia + (1.0 - slip) / m
        v = v_ref
        if v < 1.0:
            v = 1.0
        q0 = q
        if q0 > q_max:
            q0 = q_max
        if q0 < 0.0:
            q0 = 0.0
        dq = rate * ts
        if n > 1:
            return horizon_move(
                n,
                slip,
                target,
                q0,
                (b * q - c * f) / v,
                ts * b / v,
                lookahead * b / v,
                lookahead,
                ts,
                weight,
                q_max,
                dq,
            )
        reach = ts + lookahead
        gain = reach * b / v
        free = slip + reach * (b * q - c * f) / v
        h = 2.0 * (gain * gain + weight / (q_max * q_max))
        lin = 2.0 * gain * (free - target)
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
        f = tick_force(sig, c, ts)
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
            int(c[F.P_HORIZON]),
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
            int(params[D_HORIZON]),
        )
        return rate_limit(z / ts, params[D_RATE]) / params[D_K]

    return tick, step, move


LAW = Law(
    "mpc",
    (WHEEL, VEHICLE),
    lambda: (None, compiled()[0]),  # (start: at rest, tick)
    discrete=DISCRETE,
    ecu=EcuForm(lambda: compiled()[1], rate=True),
    c=CForm(EQUATIONS, C_STEP, helpers=(W.C_HELPERS, W.C_FORCE, C_SOLVER)),
    source=(
        "Petersen, Johansen, Kalkkuhl and Ludemann, ECC 2001 (constrained, gain-scheduled "
        "LQR/MPC of the linearised wheel slip); QP: controllers/slip_mpc_qp.py, horizon 1 in "
        "closed form, 2 .. 5 by a fixed-iteration interior point (docs/abs_laws.md)"
    ),
)
