"""Discrete (sampled) forms of the ABS controllers: what an ECU runs and what `export` ships.

Every law's discrete form is one numba step function on explicit float vectors, called once per
sample period ts with the inputs as an ECU sees them; it updates `state` (N_STATE floats) in
place and returns the command u (the actuator input, held until the next sample):

    u = step(state, inputs, params, table, grid)

A law's step is its module's (`controllers.laws`, `EcuForm.step`: `laws.pid` the discrete PID,
`laws.threshold` the sampled phase machine, `laws.fuzzy_pid` and `laws.fuzzy_immune_pid` the
fuzzy laws, which read the lookup table below through `controllers.discrete_lookup`), and so
are the names and order of its inputs, parameters and state entries (`Law.discrete`, a
`DiscreteLaw`); `run_from` runs any law's through the registry's dispatch. `table` (n_out, n0,
n1) and `grid` (lo0, step0, lo1, step1) are the ECU lookup table of the fuzzy laws
(`ecu_table`), ignored by the others. The C99 export prints the same arithmetic in the same
operation order (each law's `CForm`), so that a C build without FMA contraction reproduces it
bit for bit. Nothing here contracts a*b + c into an fma (numba compiles without fastmath) or
reorders a sum.

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

from chassistune._rows import read_rows
from chassistune.controllers.laws import registry
from chassistune.controllers.laws.dispatch import law_ecu_step
from chassistune.controllers.laws.forms import ECU_SIGNALS
from chassistune.controllers.laws.registry import DiscreteLaw
from chassistune.fuzzy.engine import evaluate
from chassistune.fuzzy.rulebase import RuleBase

DEFAULT_TABLE_POINTS = 49
"""`fuzzy_table_points`: nodes per input of the ECU lookup table (see the module docstring)."""


N_STATE = registry.slots("discrete_state")
"""Floats of a law's state vector: the most any registered law's `DiscreteLaw.state` holds."""
ECU_INPUTS = registry.slots("ecu_inputs")
"""Floats of a law's input vector: the most inputs any registered law reads."""
_NO_SIGNALS = (0.0,) * len(ECU_SIGNALS)
"""The shape of the signal tuple a law's ECU form reads its inputs from (`forms.ECU_SIGNALS`),
as the ECU kernel hands it: one compilation of the dispatch serves both."""

INPUT_DESCRIPTIONS = {
    "slip": "wheel slip (v - w R) / v against the reference speed, in [0, 1]",
    "pressure_at_max": "1 while the brake pressure sits at its maximum q_max, else 0",
    "pressure_at_min": "1 while the brake pressure is 0, else 0",
    "wheel_speed_rad_s": "wheel angular speed (rad/s)",
    "reference_speed_m_s": "reference speed the slip is taken against (m/s)",
    "pressure": "brake pressure (the pressure sensor or the valve model)",
    "pressure_prev": "brake pressure at the last sample",
    "wheel_speed_prev_rad_s": "wheel angular speed at the last sample (rad/s)",
    "time_s": "time of the sample since the brake applied (s)",
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


def _steps_entry(laws_key: int) -> Any:
    """The compiled loop of `run_from` for the laws registered now, named by `laws_key`
    (`registry.fingerprint` as an integer: a closure variable, on which numba keys the disk
    cache; the law dispatch is generated from the registry when it compiles)."""

    def steps(kind, state, signals, params, table, grid):
        inputs = np.zeros(ECU_INPUTS)
        out = np.empty(signals.shape[0])
        for k in range(signals.shape[0]):
            sig = read_rows(signals[k], 0, 1, _NO_SIGNALS)
            out[k] = law_ecu_step(laws_key, kind, state, inputs, sig, params, table, grid)
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
