"""Adhesion utilisation `r13h_epsilon` of UN Regulation 13-H, Annex 6, Appendix 2, on `abs-wheel`.

The regulation's test (Appendix 2; the same text as Annex XI Appendix 2 of EU 2015/68):
- 1.1.1-1.1.3: the coefficient of adhesion k is the quotient of the maximum braking force
  without locking the wheels and the dynamic axle load: one axle braked from 50 km/h, the
  anti-lock system inoperative between 40 and 20 km/h, tests at increments of line pressure,
  each with a constant input force, z = 0.566 / t with t the time from 40 to 20 km/h; wheel lock
  may occur below 20 km/h; k_M from the highest z (t_min, or the mean of three times within
  1.05 t_min).
- 1.2: z_AL = 0.849 / t_m with t_m the mean time from 45 to 15 km/h of three stops from 55 km/h
  with the anti-lock system fully cycling.
- epsilon = z_AL / k_M; the anti-lock system passes with epsilon >= 0.75 (Annex 6, 5.2); an
  epsilon above 1.00 calls for the coefficient of adhesion to be measured again.
(0.849 and 0.566 are 30 km/h and 20 km/h over g = 9.81 m/s^2, in s.)

Where the single-wheel model departs from the vehicle test (docs/ecu.md): one wheel carries the
whole quarter mass, so the "axle" is that wheel, the dynamic load is constant (no load transfer,
no pitch: k = z_m directly, without 1.1.4-1.1.5's rolling resistance and load-transfer terms),
and a simulated stop is deterministic, so the three repeats coincide and t_m = t_min. A constant
input force is the `none` controller with the pressure capped (`q_max`): the brake ramps to the
cap in 0.15 s (design.md 3.1) and holds it. The pressure search evaluates a grid of caps per round
(one kernel call each through the scenario API: a batched search needs the kernel change
described in docs/ecu.md) and refines between the best cap that does not lock and the next one.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from chassistune.errors import InputError
from chassistune.params import ImplausibleValue, to_float
from chassistune.scenarios.base import Scenario, Trace
from chassistune.scenarios.registry import get_plant

KMH = 1.0 / 3.6
Z_AL_COEF = 0.849
"""z_AL = 0.849 / t_m, t_m in s from 45 to 15 km/h (Annex 6 Appendix 2, 1.2)."""
Z_M_COEF = 0.566
"""z = 0.566 / t, t in s from 40 to 20 km/h (Annex 6 Appendix 2, 1.1.3)."""
EPSILON_REQUIRED = 0.75
ABS_START_M_S, ABS_HI_M_S, ABS_LO_M_S = 55.0 * KMH, 45.0 * KMH, 15.0 * KMH
K_START_M_S, K_HI_M_S, K_LO_M_S = 50.0 * KMH, 40.0 * KMH, 20.0 * KMH
_END_MARGIN_M_S = 1.0 * KMH
"""Each run ends (v_stop) this far below the window's lower speed."""
_NO_HOPELESS = {"hopeless_factor": 1e6, "t_max_s": 600.0}
"""No early stop: a weak constant pressure is slow but valid."""


@dataclass(frozen=True)
class AdhesionCoefficient:
    """k_M of 1.1 for one road: the highest z over constant pressures without wheel lock."""

    k_m: float
    t_min_s: float
    pressure: float
    """The cap (preset's pressure unit) of the best non-locking run."""
    lock_pressure: float
    """The lowest cap found to lock above 20 km/h (inf: none up to the preset's q_max)."""
    runs: int


@dataclass(frozen=True)
class R13hResult:
    """epsilon = z_AL / k_M of one controller on one road."""

    epsilon: float
    z_al: float
    t_abs_s: float
    """Time from 45 to 15 km/h with ABS (inf when it locked or did not get there)."""
    abs_locked: bool
    adhesion: AdhesionCoefficient

    @property
    def passed(self) -> bool:
        return self.epsilon >= EPSILON_REQUIRED


def _trace(
    preset: str | None,
    road: str | None,
    controller: str,
    params: Mapping[str, object],
    gains: Mapping[str, object] | None = None,
    seed: int = 0,
) -> tuple[Scenario, Trace]:
    """One abs-wheel run through the scenario API: (scenario, trace)."""
    sc = get_plant("abs-wheel").scenario(preset, road, controller, params, seed)
    g = sc.gains_array({k: to_float(v, f"gains.{k}") for k, v in (gains or {}).items()})
    return sc, sc.trace(g)


def window_time_s(time_s: np.ndarray, speed_m_s: np.ndarray, v_hi: float, v_lo: float) -> float:
    """Time between the first crossings of v_hi and v_lo downwards (linear interpolation of the
    trace); inf when the speed never falls to v_lo."""
    t_hi = _crossing(time_s, speed_m_s, v_hi)
    t_lo = _crossing(time_s, speed_m_s, v_lo)
    return t_lo - t_hi


def _crossing(t: np.ndarray, v: np.ndarray, level: float) -> float:
    below = np.nonzero(v <= level)[0]
    if below.size == 0:
        return float("inf")
    j = int(below[0])
    if j == 0:
        return float(t[0])
    return float(t[j - 1] + (t[j] - t[j - 1]) * (v[j - 1] - level) / (v[j - 1] - v[j]))


def _locked_above(trace_signals: Mapping[str, np.ndarray], v_min: float, lock_ratio: float) -> bool:
    v = trace_signals["vehicle_speed_m_s"]
    w = trace_signals["wheel_speed_m_s"]
    above = v > v_min
    return bool(np.any(w[above] < lock_ratio * v[above]))


def _constant_pressure_run(
    preset: str | None,
    road: str | None,
    params: Mapping[str, object],
    cap: float,
    lock_ratio: float,
) -> tuple[float, bool]:
    """(t from 40 to 20 km/h, locked above 20 km/h) for one constant pressure cap (a cap of the
    search, not the user's: below the plausible range of q_max without a warning)."""
    run_params = {
        **params,
        **_NO_HOPELESS,
        "v0_m_s": K_START_M_S,
        "v_stop_m_s": K_LO_M_S - _END_MARGIN_M_S,
        "q_max": cap,
    }
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ImplausibleValue)
        _, tr = _trace(preset, road, "none", run_params)
    locked = _locked_above(tr.signals, K_LO_M_S, lock_ratio)
    return window_time_s(
        tr.signals["time_s"], tr.signals["vehicle_speed_m_s"], K_HI_M_S, K_LO_M_S
    ), locked


def adhesion_coefficient(
    preset: str | None = None,
    road: str | None = None,
    params: Mapping[str, object] | None = None,
    grid: int = 12,
    rounds: int = 4,
) -> AdhesionCoefficient:
    """k_M by a search over constant pressure caps in (0, q_max] (1.1.3): a grid of `grid`
    caps, then `rounds` grids over one spacing either side of the best cap so far (z is not
    monotone in the cap: past the static limit the wheel slides slowly over the peak and may
    not lock above 20 km/h, at a lower z). While every cap locks, the next grid covers
    (0, lowest locking cap). Raises InputError when no cap keeps the wheel rolling."""
    if grid < 2 or rounds < 0:
        raise InputError("grid", f"need grid >= 2 and rounds >= 0, got {grid}, {rounds}")
    base = dict(params or {})
    sc = get_plant("abs-wheel").scenario(preset, road, "none", {**base, **_NO_HOPELESS})
    q_max = float(sc.params()["q_max"])
    lock_ratio = float(sc.params()["lock_ratio"])
    lo, hi = 0.0, q_max
    best_t, best_p, lock_p, runs = float("inf"), float("nan"), float("inf"), 0
    for _ in range(rounds + 1):
        caps = np.linspace(lo, hi, grid + 1)
        caps = caps[caps > 0.0]
        for cap in caps:
            t, locked = _constant_pressure_run(preset, road, base, float(cap), lock_ratio)
            runs += 1
            if locked:
                lock_p = min(lock_p, float(cap))
            elif t < best_t:
                best_t, best_p = t, float(cap)
        step = (hi - lo) / grid
        if np.isfinite(best_t):
            lo, hi = max(best_p - step, 0.0), min(best_p + step, q_max)
        else:
            lo, hi = 0.0, min(lock_p, q_max)
    if not np.isfinite(best_t):
        raise InputError(
            "road",
            f"every constant pressure cap up to {q_max:g} tried locks the wheel above 20 km/h",
        )
    return AdhesionCoefficient(Z_M_COEF / best_t, best_t, best_p, lock_p, runs)


def r13h_epsilon(
    controller: str,
    preset: str | None = None,
    road: str | None = None,
    gains: Mapping[str, object] | None = None,
    params: Mapping[str, object] | None = None,
    adhesion: AdhesionCoefficient | None = None,
    seed: int = 0,
) -> R13hResult:
    """epsilon = z_AL / k_M (Annex 6 Appendix 2) of `controller` with `gains` on `road`.

    The ABS stop starts at 55 km/h and is timed from 45 to 15 km/h (1.2); a wheel locked above
    15 km/h counts as not cycling (epsilon 0, `abs_locked`). Pass `adhesion` to reuse k_M of
    the same preset, road and params.
    """
    base = dict(params or {})
    adhesion = adhesion or adhesion_coefficient(preset, road, base)
    sc, tr = _trace(
        preset,
        road,
        controller,
        {
            **base,
            **_NO_HOPELESS,
            "v0_m_s": ABS_START_M_S,
            "v_stop_m_s": ABS_LO_M_S - _END_MARGIN_M_S,
        },
        gains,
        seed,
    )
    locked = _locked_above(tr.signals, ABS_LO_M_S, float(sc.params()["lock_ratio"]))
    t_abs = window_time_s(
        tr.signals["time_s"], tr.signals["vehicle_speed_m_s"], ABS_HI_M_S, ABS_LO_M_S
    )
    z_al = 0.0 if locked else Z_AL_COEF / t_abs
    return R13hResult(z_al / adhesion.k_m, z_al, t_abs, locked, adhesion)
