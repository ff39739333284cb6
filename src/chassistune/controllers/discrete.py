"""Discrete (sampled) forms of the ABS controllers: what an ECU runs and what `export` ships.

Every law's discrete form is one numba step function on explicit float vectors, called once per
sample period ts with the inputs as an ECU sees them; it updates `state` (N_STATE floats) in
place and returns the command u (the actuator input, held until the next sample):

    u = step(state, inputs, params, table, grid)

A law's step is its module's (`controllers.laws`, `EcuForm.step`: `laws.pid` the discrete PID,
`laws.threshold` the sampled phase machine); `run_from` runs any law's through the registry's
dispatch. `table` (n_out, n0, n1) and `grid` (lo0, step0, lo1, step1) are the ECU lookup table
of the fuzzy laws (`ecu_table`), ignored by the others. Names and order of the inputs,
parameters and state entries are declared once per law (`controllers.discrete_laws`); the C99
export prints the same arithmetic in the same operation order, so that a C build without FMA
contraction reproduces it bit for bit. Nothing here contracts a*b + c into an fma (numba
compiles without fastmath) or reorders a sum.

The fuzzy laws' steps (e = target_slip - slip throughout):
- `fuzzy-pid` (Tian 2025): the same PID with kp, ki, kd scheduled every sample from the table at
  (ke e_k, kec d_k): kp = kp0 + ku_p T_kp(ke e_k, kec d_k), likewise ki, kd.
- `fuzzy-immune-pid` (Ding 2023 eqs. 6-10, the kernel's arithmetic): ec_k = (e_k - e_k-1) / ts
  (0 at k = 0), kp1 = k_immune (1 - eta T_f(ke e_k, kec ec_k)),
      u_k = u_k-1 + kp1 (e_k - e_k-1) + ki ts e_k + kd (e_k - 2 e_k-1 + e_k-2) / ts,
  starting from rest (u = 0, e = 0 before k = 0, no derivative term at k = 0); after k = 0,
  e_k-1 = e_k-2 = e_0 (the kernel's start, where the slip is 0 at the first sample).

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

from chassistune.controllers.discrete_laws import DiscreteLaw
from chassistune.controllers.immune_pid import incremental_pid_du
from chassistune.controllers.laws import pid, registry
from chassistune.controllers.laws.dispatch import law_ecu_step
from chassistune.controllers.laws.forms import ECU_SIGNALS
from chassistune.fuzzy.engine import evaluate
from chassistune.fuzzy.rulebase import RuleBase

DEFAULT_TABLE_POINTS = 49
"""`fuzzy_table_points`: nodes per input of the ECU lookup table (see the module docstring)."""


# parameter slots of the fuzzy laws (gains first, in registry order)
FP_KE, FP_KEC, FP_KUP, FP_KUI, FP_KUD, FP_KP0, FP_KI0, FP_KD0, FP_N, FP_TARGET, FP_TS = range(11)
IM_K, IM_ETA, IM_KI, IM_KD, IM_KE, IM_KEC, IM_TARGET, IM_TS = range(8)

# state slots (N_STATE floats, enough for every law)
N_STATE = 4
ST_STARTED = 0  # every law: 0 before the first sample, 1 after
IS_U, IS_E1, IS_E2 = 1, 2, 3

IN_SLIP = 0  # the fuzzy laws' first input

_filtered_derivative, _pid_output, _ = pid.ecu_forms()  # the fuzzy PID's, the PID's own

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


_steps = registry.per_fingerprint(_steps_entry)


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
    for j, name in enumerate(law.ecu_inputs):
        signals[:, ECU_SIGNALS[name]] = rows[:, j]
    return np.asarray(_steps()(kind, state, signals, params, table, grid))


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
