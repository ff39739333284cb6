"""Fuzzy immune PID (Ding 2023 eqs. 6-10; design.md 4): an incremental PID whose proportional gain
follows an immune feedback law.

    kp1 = k_immune (1 - eta f(ke e, kec ec))                            (eq. 9, f: rule base)
    u_k = u_k-1 + kp1 (e_k - e_k-1) + ki ts e_k + kd (e_k - 2 e_k-1 + e_k-2) / ts   (eq. 10)

with ec = (e_k - e_k-1) / ts. The controller starts from rest (u = 0 and e = 0 before the first
sample) without a derivative kick: the first sample adds kp1 e + ki ts e only (ec = 0).
Explicit state: (u_k-1, e_k-1, e_k-2), held by the caller; call at each sample instant.

Step functions (numba, inline="always"; the surface lookup is inlined, no call):

    immune_gain(table, e, ec, ke, kec, k_immune, eta) -> kp1
    incremental_pid_du(kp1, ki, kd, ts, e0, e1, e2) -> du                   (branch-free)
    immune_pid_step(table, e, e1, e2, u_prev, ts, first, k_immune, eta, ki, kd, ke, kec) -> u

    table: `CompiledSurface.table` of a rule base with inputs (e, ec) and one output;
    e, e1, e2: float, errors at samples k, k-1, k-2; u_prev: float, the last command;
    ts: float, sample period (s); first: bool, the first sample of the run.
"""

from __future__ import annotations

from numba import njit

from chassistune._branchfree import select
from chassistune.fuzzy.surface import surface_output


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def immune_gain(table, e, ec, ke, kec, k_immune, eta):
    """Immune proportional gain kp1 = k_immune (1 - eta f(ke e, kec ec)) (Ding 2023 eq. 9)."""
    return k_immune * (1.0 - eta * surface_output(table, 0, ke * e, kec * ec))


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def incremental_pid_du(kp1, ki, kd, ts, e0, e1, e2):
    """Control increment of the discrete PID (fuzzy-immune-abs eq. 10 as design.md 4 reads it)."""
    return kp1 * (e0 - e1) + ki * ts * e0 + kd * (e0 - 2.0 * e1 + e2) / ts


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def immune_pid_step(table, e, e1, e2, u_prev, ts, first, k_immune, eta, ki, kd, ke, kec):
    """Next command u_k of the fuzzy immune PID (Ding 2023 eqs. 9-10), from rest at `first`."""
    ec = select(first, 0.0, (e - e1) / ts)
    kp1 = immune_gain(table, e, ec, ke, kec, k_immune, eta)
    e1_ = select(first, 0.0, e1)
    e2_ = select(first, 0.0, e2)
    return u_prev + incremental_pid_du(kp1, ki, select(first, 0.0, kd), ts, e, e1_, e2_)
