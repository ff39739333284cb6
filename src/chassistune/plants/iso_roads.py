"""ISO 8608 random road profiles as filtered white noise (design.md 3.4, iabc-suspension eq. 3,
corrected).

Displacement PSD of class X (one-sided, spatial frequency n in cycles/m):

    Gd(n) = Gq (n / n0)^-2,   n0 = 0.1 cycles/m                               (ISO 8608)

Generated in time at speed v by the first-order filter

    z0' = -2 pi f0 z0 + b w(t),   b = 2 pi n0 sqrt(Gq v)                       (2)

driven by white noise w of intensity W = 1/2 (one-sided PSD 1), whose spatial PSD is
Gq n0^2 / (n^2 + (f0 / v)^2): ISO 8608 above the cut-off f0. Discrete w_k ~ N(0, W / dt) is held
over each step. Noise comes only from numpy.random.default_rng(seed), so one seed gives one road
realization, shared by every candidate of a run (common random numbers).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from chassistune._rng import make_rng
from chassistune.errors import InputError
from chassistune.params import positive

N0_CYCLES_PER_M = 0.1
NOISE_INTENSITY = 0.5
"""W of the white noise w in eq. (2): one-sided PSD 1 (Simulink's noise power 1 would be 2x)."""

_POS = {"positive": True}


@dataclass(frozen=True)
class RoadParams:
    """Road and travel: class coefficient Gq = Gd(n0), speed, cut-off of the road filter."""

    gq_m3: float = field(default=64e-6, metadata=_POS)
    speed_m_s: float = field(default=20.0, metadata=positive(1.0, 70.0))
    cutoff_hz: float = field(default=0.1, metadata=positive(0.001, 10.0))
    n0_cycles_per_m: float = field(default=N0_CYCLES_PER_M, metadata=_POS)

    @property
    def gain(self) -> float:
        """b of eq. (2), m / s^(1/2)."""
        return 2.0 * math.pi * self.n0_cycles_per_m * math.sqrt(self.gq_m3 * self.speed_m_s)

    @property
    def pole_rad_s(self) -> float:
        """2 pi f0 of eq. (2)."""
        return 2.0 * math.pi * self.cutoff_hz


def iso_psd(n: np.ndarray, gq_m3: float, n0: float = N0_CYCLES_PER_M) -> np.ndarray:
    """ISO 8608 displacement PSD Gd(n) = Gq (n/n0)^-2, m^3, n in cycles/m."""
    return gq_m3 * (np.asarray(n, dtype=np.float64) / n0) ** -2


def filter_psd(n: np.ndarray, road: RoadParams) -> np.ndarray:
    """Spatial displacement PSD of eq. (2): Gq n0^2 / (n^2 + (f0/v)^2), m^3."""
    n = np.asarray(n, dtype=np.float64)
    nc = road.cutoff_hz / road.speed_m_s
    return road.gq_m3 * road.n0_cycles_per_m**2 / (n**2 + nc**2)


def white_noise(seed: int, n_steps: int, dt_s: float) -> np.ndarray:
    """w_k ~ N(0, W/dt), W = 1/2, from `make_rng(seed)`: the run's noise."""
    rng = make_rng(seed)
    return rng.standard_normal(n_steps) * math.sqrt(NOISE_INTENSITY / dt_s)


def road_profile(road: RoadParams, noise: np.ndarray, dt_s: float) -> np.ndarray:
    """Road displacement z0 at t = 0, dt, ..., len(noise) dt (m), exact step of eq. (2).

    z[k+1] = a z[k] + b (1 - a) / lambda w[k], a = exp(-lambda dt), starting at rest.
    """
    from scipy.signal import lfilter

    lam = road.pole_rad_s
    a = math.exp(-lam * dt_s)
    g = road.gain * (-math.expm1(-lam * dt_s)) / lam
    z = np.zeros(len(noise) + 1)
    z[1:] = lfilter([g], [1.0, -a], noise)
    return z


def validate_road(road: RoadParams) -> None:
    """Checks beyond the field metadata: a class coefficient Gq of at most 1 m^3."""
    if road.gq_m3 > 1.0:
        raise InputError(
            "params.gq_m3", f"must be at most 1 m^3 (ISO class H is 2.6e-4), got {road.gq_m3:g}"
        )
