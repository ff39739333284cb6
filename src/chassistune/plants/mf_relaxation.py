"""Transient slip: the first-order relaxation-length model (Pacejka 2012, sec. 7.2.1, the
single-contact-point model, sigma dkappa'/dt + |V| kappa' = |V| kappa with the kinematic slip
kappa = -V_sx / |V|).

The lagged slip kappa' (longitudinal, or the lateral slip alpha' alike) follows the kinematic slip
with the time constant sigma / |V|: the tire must roll its relaxation length sigma for the force
to build up. The forces are then evaluated at kappa' instead of kappa. sigma = 0 is the static
tire (kappa' = kappa).
"""

from __future__ import annotations

import math

import numba


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def lagged_slip_rate_per_s(
    slip: float, lagged_slip: float, speed_m_s: float, relaxation_length_m: float
) -> float:
    """dkappa'/dt = (|V| / sigma) (kappa - kappa'), for sigma > 0."""
    return abs(speed_m_s) / relaxation_length_m * (slip - lagged_slip)


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def lagged_slip_after(
    slip: float, lagged_slip: float, speed_m_s: float, relaxation_length_m: float, dt_s: float
) -> float:
    """kappa' after dt_s with kappa and V held: the exact solution
    kappa + (kappa' - kappa) exp(-|V| dt / sigma); sigma = 0 gives kappa itself."""
    if relaxation_length_m == 0.0:
        return slip
    return slip + (lagged_slip - slip) * math.exp(-abs(speed_m_s) * dt_s / relaxation_length_m)
