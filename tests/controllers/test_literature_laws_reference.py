"""The scalar references of the five literature laws (literature_laws_reference.py) obey the
physics of a stop from their default gains, and extremum seeking finds the peak on its own."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from literature_laws_reference import (
    DRY_CONCRETE,
    ICE,
    LAWS,
    SLDEMO_TABLE,
    ExtremumSeeking,
    Measured,
    Wheel,
    bound_m,
    closed_loop,
    extremum_seeking_step,
    locked_m,
)

ROADS = {"dry-concrete": DRY_CONCRETE, "ice": ICE}
NEEDS_TARGET = {"sliding-mode", "adrc", "mpc"}
"""Laws regulating slip to a target: run with the road's optimal slip (the oracle setting)."""

RATIO_MEASURED = {
    ("sliding-mode", "dry-concrete"): 1.155,
    ("sliding-mode", "ice"): 1.013,
    ("adrc", "dry-concrete"): 1.096,
    ("adrc", "ice"): 1.009,
    ("mixed-slip-deceleration", "dry-concrete"): 1.171,
    ("mixed-slip-deceleration", "ice"): 1.070,
    ("extremum-seeking", "dry-concrete"): 1.154,
    ("extremum-seeking", "ice"): 1.026,
    ("mpc", "dry-concrete"): 1.081,
    ("mpc", "ice"): 1.006,
}
"""Stop distance over the adhesion bound from the default gains (docs/abs_laws.md)."""


@pytest.mark.parametrize("road_name", list(ROADS))
@pytest.mark.parametrize("law", list(LAWS))
def test_stop_respects_physics(law: str, road_name: str) -> None:
    road = ROADS[road_name]
    step, gains = LAWS[law]
    if law in NEEDS_TARGET:
        gains = dataclasses.replace(gains, target=road.slip_opt)
    stop = closed_loop(step, gains, road)
    assert stop.finite and stop.stopped
    assert np.all(np.isfinite(stop.slip))
    assert stop.slip_min >= 0.0 and stop.slip_max <= 1.0
    assert bound_m(road) < stop.distance_m < locked_m(road)
    ratio = stop.distance_m / bound_m(road)
    assert ratio == pytest.approx(RATIO_MEASURED[law, road_name], abs=2e-3)


def test_the_law_sees_no_road() -> None:
    """What a law is handed names no road and no curve: only sensor readings and the wheel."""
    fields = {f.name for f in dataclasses.fields(Measured)}
    assert fields == {
        "t_s",
        "slip",
        "wheel_speed_rad_s",
        "wheel_speed_prev_rad_s",
        "pressure",
        "pressure_prev",
        "v_ref_m_s",
        "ts_s",
        "wheel",
    }
    known = {f.name for f in dataclasses.fields(Wheel)}
    known |= {f.name for _, gains in LAWS.values() for f in dataclasses.fields(gains)}
    assert not any(word in name for name in known for word in ("mu", "road", "peak", "opt"))


ES_START = 0.05
ES_CASES = {
    # road, (peak slip, tolerance, from time s, until time s)
    "dry-concrete": (DRY_CONCRETE, 0.2, 0.04, 1.5, 3.0),
    "sldemo-table": (SLDEMO_TABLE, 0.2, 0.04, 1.5, 3.0),
    "ice": (ICE, 0.1, 0.03, 4.0, 12.0),
}


@pytest.mark.parametrize("case", list(ES_CASES))
def test_extremum_seeking_finds_the_peak(case: str) -> None:
    """Started at 0.05, the estimate theta holds still while the brake applies (hold_s) and then
    stays within the tolerance of the peak from the stated time on, on curves peaking at 0.2
    (a kink, and sldemo's rounder table) and at 0.1 (ice), with the same gains."""
    road, peak, tol, t_from, t_to = ES_CASES[case]
    gains = dataclasses.replace(ExtremumSeeking(), start=ES_START)
    stop = closed_loop(extremum_seeking_step, gains, road, t_max_s=t_to)
    theta = np.array([s[0] for s in stop.law_state])
    assert np.all(theta[stop.t_s < gains.hold_s] == ES_START)
    window = (stop.t_s >= t_from) & (stop.t_s <= t_to)
    assert window.sum() > 100
    assert np.abs(theta[window] - peak).max() <= tol
    assert math.isfinite(stop.distance_m)
