"""Discrete (sampled) forms of the ABS controllers: what an ECU runs and what `export` ships.

Every law is one numba step function on explicit float vectors, called once per sample period
ts with the inputs as an ECU sees them; it updates `state` in place and returns the command u
(the actuator input, held until the next sample):

    u = step(state, inputs, params, table, grid)

`table` (n_out, n0, n1) and `grid` (lo0, step0, lo1, step1) are the ECU lookup table of the fuzzy
laws (`ecu_table`), ignored by the others. Names and order of the inputs, parameters and state
entries are declared once per law (`controllers.discrete_laws`); the C99 export prints the same
arithmetic in the same operation order, so that a C build without FMA contraction reproduces it
bit for bit. Nothing here contracts a*b + c into an fma (numba compiles without fastmath) or
reorders a sum.

The laws (e = target_slip - slip throughout):
- `pid` (design.md 4 in discrete time; Simulink's discrete PID, parallel form, forward-Euler
  integrator, backward-Euler derivative filter: stable at any ts, unlike a forward-Euler filter,
  which needs N ts < 2):
      xf_0 = e_0,  xf_k = (xf_k-1 + ts N e_k) / (1 + ts N)         (backward Euler, no kick)
      d_k = N (e_k - xf_k)                                           (filtered de/dt)
      u_k = kp e_k + ki z_k + kd d_k
      z_k+1 = z_k + ts e_k, unless (pressure_at_max and e_k > 0) or (pressure_at_min and e_k < 0)
- `fuzzy-pid` (Tian 2025): the same PID with kp, ki, kd scheduled every sample from the table at
  (ke e_k, kec d_k): kp = kp0 + ku_p T_kp(ke e_k, kec d_k), likewise ki, kd.
- `fuzzy-immune-pid` (Ding 2023 eqs. 6-10, the kernel's arithmetic): ec_k = (e_k - e_k-1) / ts
  (0 at k = 0), kp1 = k_immune (1 - eta T_f(ke e_k, kec ec_k)),
      u_k = u_k-1 + kp1 (e_k - e_k-1) + ki ts e_k + kd (e_k - 2 e_k-1 + e_k-2) / ts,
  starting from rest (u = 0, e = 0 before k = 0, no derivative term at k = 0); after k = 0,
  e_k-1 = e_k-2 = e_0 (the kernel's start, where the slip is 0 at the first sample).
- `threshold` (design.md 4's rule-based ABS, the kernel's phases): aw_k = (w_k - w_k-1) R / ts
  (0 at k = 0), then the phase machine build -> hold -> dump -> recover -> slow build, with
  u = +amplitude (build), 0 (hold, recover), -amplitude (dump), slow_fraction amplitude (slow).

Lookup (fuzzy laws): a uniform grid of `fuzzy_table_points` nodes per input over the rule base's
universes, values exact Mamdani inference at the nodes (`chassistune.fuzzy.engine`), bilinear
interpolation, inputs clipped to the grid:
    t = (x - lo) / step, clipped to [0, n - 1];  i = min(floor(t), n - 2);  f = t - i
    T = (v[i, j] (1 - f1) + v[i, j + 1] f1) (1 - f0)
        + (v[i + 1, j] (1 - f1) + v[i + 1, j + 1] f1) f0       (in this order, no fma)
Default 49 points: 48 intervals put every set peak and every crossing of the built-in rule bases
on a grid line (deffao's integer peaks on [-3, 3], immune's quarter points on [-1, 1]). Largest
error against exact inference over 200,000 random points, as a fraction of the output range:
deffao 0.044, classic 0.063, immune 0.076 (at 97 points: 0.021, 0.028, 0.038; the error falls
like 1/n across the cells' remaining kinks). Tested in tests/export/test_discrete.py.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numba import njit
from numpy.typing import NDArray

from chassistune.controllers.discrete_laws import LAWS as LAWS  # the built-in declarations
from chassistune.controllers.discrete_laws import DiscreteLaw
from chassistune.controllers.immune_pid import incremental_pid_du
from chassistune.controllers.laws import registry
from chassistune.controllers.laws.dispatch import law_ecu_step
from chassistune.controllers.laws.forms import ECU_SIGNALS
from chassistune.controllers.switching import threshold_step as threshold_phase_step
from chassistune.controllers.switching import wheel_deceleration_sample
from chassistune.fuzzy.engine import evaluate
from chassistune.fuzzy.rulebase import RuleBase

DEFAULT_TABLE_POINTS = 49
"""`fuzzy_table_points`: nodes per input of the ECU lookup table (see the module docstring)."""


# parameter slots, per law (gains first, in registry order)
PID_KP, PID_KI, PID_KD, PID_N, PID_TARGET, PID_TS = range(6)
FP_KE, FP_KEC, FP_KUP, FP_KUI, FP_KUD, FP_KP0, FP_KI0, FP_KD0, FP_N, FP_TARGET, FP_TS = range(11)
IM_K, IM_ETA, IM_KI, IM_KD, IM_KE, IM_KEC, IM_TARGET, IM_TS = range(8)
TH_AMP, TH_DECEL, TH_ACCEL, TH_MARGIN, TH_SLOW, TH_TARGET, TH_TS, TH_RADIUS = range(8)

# state slots (N_STATE floats, enough for every law)
N_STATE = 4
ST_STARTED = 0  # every law: 0 before the first sample, 1 after
PS_INTEGRAL, PS_FILTER = 1, 2
IS_U, IS_E1, IS_E2 = 1, 2, 3
TS_PHASE, TS_W_PREV, TS_AW = 1, 2, 3

# input slots
IN_SLIP, IN_AT_MAX, IN_AT_MIN = 0, 1, 2
IN_WHEEL_SPEED = 1  # threshold: (slip, wheel_speed_rad_s)

INPUT_DESCRIPTIONS = {
    "slip": "wheel slip (v - w R) / v against the reference speed, in [0, 1]",
    "pressure_at_max": "1 while the brake pressure sits at its maximum q_max, else 0",
    "pressure_at_min": "1 while the brake pressure is 0, else 0",
    "wheel_speed_rad_s": "wheel angular speed (rad/s)",
}


def law(controller: str) -> DiscreteLaw | None:
    """The discrete law of a registered ABS controller, or None when it has no discrete form."""
    return registry.get(controller).discrete


def ecu_table(
    rb: RuleBase, points: int = DEFAULT_TABLE_POINTS
) -> tuple[NDArray[np.float64], NDArray[np.float64], tuple[NDArray[np.float64], ...]]:
    """The ECU lookup table of a two-input rule base: (table, grid, breakpoints).

    table (n_out, points, points): table[k, i, j] = output k at (bp[0][i], bp[1][j]), exact
    inference; grid = (lo0, step0, lo1, step1), what the interpolation reads; bp the breakpoints
    lo + i step of each input (as printed for lookup-table blocks).
    """
    if points < 2:
        raise ValueError(f"fuzzy_table_points must be at least 2, got {points}")
    grid = np.array([v for var in rb.inputs for v in (var.universe[0], var.span / (points - 1))])
    bp = tuple(grid[2 * a] + grid[2 * a + 1] * np.arange(points) for a in range(2))
    pts = np.stack(np.meshgrid(bp[0], bp[1], indexing="ij"), axis=-1).reshape(-1, 2)
    values = evaluate(rb, pts).reshape(points, points, -1)
    return np.ascontiguousarray(np.moveaxis(values, 2, 0)), grid, bp


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _locate(lo, step, n, x):
    """Cell index in [0, n - 2] and fraction of x on a uniform grid (clipped to it)."""
    t = (x - lo) / step
    if t < 0.0:
        t = 0.0
    if t > n - 1.0:
        t = n - 1.0
    i = int(t)
    if i > n - 2:
        i = n - 2
    return i, t - i


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def table_cell(table, grid, x0, x1):
    """(i, j, f0, f1): the cell of (x0, x1) and the fractions in it; i = -1 for a NaN input."""
    if x0 != x0 or x1 != x1:
        return -1, 0, np.nan, np.nan
    i, f0 = _locate(grid[0], grid[1], table.shape[1], x0)
    j, f1 = _locate(grid[2], grid[3], table.shape[2], x1)
    return i, j, f0, f1


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def table_value(table, k, cell):
    """Output k of the ECU table in a `table_cell`, bilinear (module docstring); NaN for NaN."""
    i, j, f0, f1 = cell
    if i < 0:
        return np.nan
    return (table[k, i, j] * (1.0 - f1) + table[k, i, j + 1] * f1) * (1.0 - f0) + (
        table[k, i + 1, j] * (1.0 - f1) + table[k, i + 1, j + 1] * f1
    ) * f0


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _filtered_derivative(state, e, n_filter, ts):
    """Backward-Euler derivative filter: xf_k = (xf_k-1 + ts N e_k) / (1 + ts N), d = N (e - xf)."""
    if state[ST_STARTED] == 0.0:
        state[PS_FILTER] = e
    else:
        a = ts * n_filter
        state[PS_FILTER] = (state[PS_FILTER] + a * e) / (1.0 + a)
    return n_filter * (e - state[PS_FILTER])


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _pid_output(state, inputs, e, d, kp, ki, kd, ts):
    """u = kp e + ki z + kd d, then the forward-Euler integral with conditional integration."""
    u = kp * e + ki * state[PS_INTEGRAL] + kd * d
    at_max = inputs[IN_AT_MAX] != 0.0
    at_min = inputs[IN_AT_MIN] != 0.0
    if not ((at_max and e > 0.0) or (at_min and e < 0.0)):
        state[PS_INTEGRAL] = state[PS_INTEGRAL] + ts * e
    state[ST_STARTED] = 1.0
    return u


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def pid_step(state, inputs, params, table, grid):
    """Discrete PID (module docstring, `pid`)."""
    e = params[PID_TARGET] - inputs[IN_SLIP]
    d = _filtered_derivative(state, e, params[PID_N], params[PID_TS])
    return _pid_output(
        state, inputs, e, d, params[PID_KP], params[PID_KI], params[PID_KD], params[PID_TS]
    )


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def fuzzy_pid_step(state, inputs, params, table, grid):
    """Discrete fuzzy self-tuning PID (module docstring, `fuzzy-pid`)."""
    e = params[FP_TARGET] - inputs[IN_SLIP]
    d = _filtered_derivative(state, e, params[FP_N], params[FP_TS])
    cell = table_cell(table, grid, params[FP_KE] * e, params[FP_KEC] * d)
    kp = params[FP_KP0] + params[FP_KUP] * table_value(table, 0, cell)
    ki = params[FP_KI0] + params[FP_KUI] * table_value(table, 1, cell)
    kd = params[FP_KD0] + params[FP_KUD] * table_value(table, 2, cell)
    return _pid_output(state, inputs, e, d, kp, ki, kd, params[FP_TS])


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def immune_step(state, inputs, params, table, grid):
    """Discrete fuzzy immune PID (module docstring, `fuzzy-immune-pid`)."""
    ts = params[IM_TS]
    e = params[IM_TARGET] - inputs[IN_SLIP]
    first = state[ST_STARTED] == 0.0
    ec = 0.0 if first else (e - state[IS_E1]) / ts
    f = table_value(table, 0, table_cell(table, grid, params[IM_KE] * e, params[IM_KEC] * ec))
    kp1 = params[IM_K] * (1.0 - params[IM_ETA] * f)
    if first:
        u = state[IS_U] + incremental_pid_du(kp1, params[IM_KI], 0.0, ts, e, 0.0, 0.0)
        state[IS_E2] = e
    else:
        u = state[IS_U] + incremental_pid_du(
            kp1, params[IM_KI], params[IM_KD], ts, e, state[IS_E1], state[IS_E2]
        )
        state[IS_E2] = state[IS_E1]
    state[IS_E1] = e
    state[IS_U] = u
    state[ST_STARTED] = 1.0
    return u


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def threshold_step(state, inputs, params, table, grid):
    """Sampled threshold ABS (module docstring, `threshold`): the kernel's phase machine
    (`controllers.switching`) fed the wheel acceleration over the last sample."""
    w = inputs[IN_WHEEL_SPEED]
    ts = params[TH_TS]
    if state[ST_STARTED] != 0.0:
        state[TS_AW] = wheel_deceleration_sample(w, state[TS_W_PREV], params[TH_RADIUS], ts)
    state[TS_W_PREV] = w
    state[ST_STARTED] = 1.0
    u, ph = threshold_phase_step(
        int(state[TS_PHASE]),
        inputs[IN_SLIP],
        params[TH_TARGET],
        state[TS_AW],
        params[TH_AMP],
        params[TH_DECEL],
        params[TH_ACCEL],
        params[TH_MARGIN],
        params[TH_SLOW],
    )
    state[TS_PHASE] = ph
    return u


def _steps_entry(laws_key: int) -> Any:
    """The compiled loop of `run_from` for the laws registered now, named by `laws_key`
    (`registry.fingerprint` as an integer: a closure variable, on which numba keys the disk
    cache; the law dispatch is generated from the registry when it compiles)."""

    def steps(kind, state, signals, params, table, grid):
        inputs = np.zeros(registry.ECU_INPUTS)
        out = np.empty(signals.shape[0])
        for k in range(signals.shape[0]):
            out[k] = law_ecu_step(laws_key, kind, state, inputs, signals[k], params, table, grid)
        return out

    return njit(cache=True, nogil=True, error_model="numpy")(steps)


_STEPS: dict[str, Any] = {}


def run_from(
    kind: int,
    state: NDArray[np.float64],
    inputs: NDArray[np.float64],
    params: NDArray[np.float64],
    table: NDArray[np.float64],
    grid: NDArray[np.float64],
) -> NDArray[np.float64]:
    """The commands u (m,) of the law of the registry's `kind` (its ECU form, the one step the
    ECU kernel runs) fed the input rows (m, n_inputs, in its inputs' order) from `state`
    (N_STATE floats, updated in place). ValueError for a kind no law holds or a law without an
    ECU form."""
    law = registry.by_kind(kind)
    if law.ecu is None:
        raise ValueError(f"control law {law.name!r} has no discrete form")
    rows = np.atleast_2d(inputs)
    signals = np.zeros((rows.shape[0], len(ECU_SIGNALS)))
    for j, name in enumerate(law.ecu.inputs):
        signals[:, ECU_SIGNALS[name]] = rows[:, j]
    key = registry.fingerprint()
    if key not in _STEPS:
        _STEPS[key] = _steps_entry(int(key[:15], 16))
    return np.asarray(_STEPS[key](kind, state, signals, params, table, grid))


def discrete_step(
    kind: int,
    state: NDArray[np.float64],
    inputs: NDArray[np.float64],
    params: NDArray[np.float64],
    table: NDArray[np.float64],
    grid: NDArray[np.float64],
) -> float:
    """One sample of the law of the registry's `kind`: the command u; `state` is updated in
    place (`run_from`)."""
    return float(run_from(kind, state, inputs, params, table, grid)[0])


def run_vectors(
    kind: int,
    inputs: NDArray[np.float64],
    params: NDArray[np.float64],
    table: NDArray[np.float64],
    grid: NDArray[np.float64],
) -> NDArray[np.float64]:
    """The commands u (m,) of a law started from rest and fed the input rows (m, n_inputs)."""
    return run_from(kind, np.zeros(N_STATE), inputs, params, table, grid)


def no_table() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A placeholder (table, grid) for the laws without a lookup table."""
    return np.zeros((1, 2, 2)), np.array([0.0, 1.0, 0.0, 1.0])
