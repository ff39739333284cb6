"""Fuzzy self-tuning PID (deffao-vehicle-abs section 3, Fig. 3; design.md 4): a PID's gain schedule.

The inputs e and de/dt are scaled by the quantization factors `ke`, `kec` into the rule base's
universe (and clipped to it); its three outputs (deffao: magnitudes in [0, 1]; classic: signed
deltas on [-3, 3]) are scaled by `ku_p`, `ku_i`, `ku_d` and added to the base gains:
kp = kp0 + ku_p out_kp, and likewise ki, kd. No clipping: with `classic` and large `ku_*` the
gains can turn negative. The scheduled gains feed `controllers.pid.pid_step` until the next sample.

Step function (numba, inline="always"; the surface lookup is inlined, no call):

    fuzzy_pid_gains(table, e, de, ke, kec, ku_p, ku_i, ku_d, kp0, ki0, kd0) -> (kp, ki, kd)

    table: `CompiledSurface.table` of a rule base with inputs (e, ec) and outputs (kp, ki, kd) or
    (dkp, dki, dkd); e: float, error; de: float, its (filtered) rate; the rest float gains.
    NaN inputs give NaN gains. Bitwise equal to `surface_lookup` followed by the scaling.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from chassistune.fuzzy.surface import cell_output, surface_cell


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def fuzzy_pid_gains(table, e, de, ke, kec, ku_p, ku_i, ku_d, kp0, ki0, kd0):
    """Scheduled (kp, ki, kd) at (e, de) (deffao-vehicle-abs Fig. 3)."""
    x0 = ke * e
    x1 = kec * de
    if x0 != x0 or x1 != x1:
        return np.nan, np.nan, np.nan
    b, i, j, o, row, f0, f1 = surface_cell(table, x0, x1)
    return (
        kp0 + ku_p * cell_output(table, b, i, j, o, row, f0, f1, 0),
        ki0 + ku_i * cell_output(table, b, i, j, o, row, f0, f1, 1),
        kd0 + ku_d * cell_output(table, b, i, j, o, row, f0, f1, 2),
    )
