"""The bilinear lookup of the fuzzy laws' ECU table (`controllers.discrete.ecu_table`), in the
operation order of the `controllers.discrete` docstring, which the C export prints the same:
`table_cell` locates the inputs on the grid (clipped to it), `table_value` interpolates one
output in that cell. Compiled code only (numba, inlined: no call)."""

from __future__ import annotations

import numpy as np
from numba import njit


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
