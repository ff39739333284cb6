"""Compiled gain laws of the fuzzy controllers, for the closed-loop kernels to call per step.

All take the `table` of a `CompiledSurface` (see `surface.py`) and scalars, allocate nothing, and
can be called from any `@njit` function.

- Fuzzy self-tuning PID (seed 003 section 3, Fig. 3; DESIGN 4): the inputs e and de/dt are scaled
  by the quantization factors `ke`, `kec` into the universe (and clipped to it); the rule base
  outputs (deffao: magnitudes in [0, 1]; classic: signed deltas dkp, dki, dkd on [-3, 3]) are scaled
  by `ku_p`, `ku_i`, `ku_d` and added to the base gains: kp = kp0 + ku_p * out_kp, and likewise for
  ki and kd. No clipping of the gains: with `classic` and large `ku_*` they can turn negative.
- Fuzzy immune PID (seed 004 eqs. 6-10; DESIGN 4): kp1 = k_immune (1 - eta f(e, ec)) with f the
  output of the `immune` rule base at (ke e, kec ec) (eq. 9), and the incremental law
  du = kp1 (e_k - e_k-1) + ki ts e_k + kd (e_k - 2 e_k-1 + e_k-2) / ts (eq. 10, DESIGN 4's reading).
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import NDArray

from chassistune.fuzzy.surface import SurfaceTable, surface_lookup, surface_value


@njit(cache=True, nogil=True)
def fuzzy_pid_gains(
    table: SurfaceTable,
    e: float,
    de: float,
    ke: float,
    kec: float,
    ku_p: float,
    ku_i: float,
    ku_d: float,
    kp0: float,
    ki0: float,
    kd0: float,
    out: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """Write the scheduled gains kp, ki, kd into out[0:3] (seed 003 Fig. 3; DESIGN 4).

    `table` must have three outputs in the order kp, ki, kd (deffao) or dkp, dki, dkd (classic).
    """
    surface_lookup(table, ke * e, kec * de, out)
    out[0] = kp0 + ku_p * out[0]
    out[1] = ki0 + ku_i * out[1]
    out[2] = kd0 + ku_d * out[2]


@njit(cache=True, nogil=True)
def immune_gain(
    table: SurfaceTable, e: float, ec: float, ke: float, kec: float, k_immune: float, eta: float
) -> float:  # pragma: no cover - compiled
    """Immune proportional gain kp1 = k_immune (1 - eta f(ke e, kec ec)) (seed 004 eq. 9)."""
    return k_immune * (1.0 - eta * surface_value(table, 0, ke * e, kec * ec))


@njit(cache=True, nogil=True)
def incremental_pid_du(
    kp1: float, ki: float, kd: float, ts: float, e0: float, e1: float, e2: float
) -> float:  # pragma: no cover - compiled
    """Control increment of the discrete PID (seed 004 eq. 10 as DESIGN 4 reads it).

    e0, e1, e2 are the errors at samples k, k-1, k-2; ts the controller's sample period.
    """
    return kp1 * (e0 - e1) + ki * ts * e0 + kd * (e0 - 2.0 * e1 + e2) / ts
