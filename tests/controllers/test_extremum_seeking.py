"""Extremum-seeking slip control (controllers/laws/extremum_seeking.py, docs/abs_laws.md 4): the
ideal wheel kernel runs it as its scalar reference (tests/controllers/literature_laws_reference.py,
the published scheme in a plain loop at RK4 steps of 1 ms); started far below the peak it finds
the peak slip online without knowing the road (the scenario's target slip, the road's optimum,
does not reach it); from its registry defaults it stops within 1.5 adhesion bounds (single wheel
in the realistic ECU: dry concrete, ice; vehicle: dry concrete, mu-jump) and within 1.3 on
`burckhardt-snow`; the realistic ECU's batch row is its single run. Wild gains, conformance and
the C replay are the registry-wide tests (tests/export, tests/scenarios/test_check_plant.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from literature_laws_reference import (
    DRY_CONCRETE,
    ICE,
    LAWS,
    assert_batch_rows_are_single_runs,
    closed_loop,
)

from chassistune.controllers.laws import extremum_seeking as es
from chassistune.scenarios.registry import get_plant

LAW = es.LAW.name
ROADS = {"dry-concrete": DRY_CONCRETE, "ice": ICE}
TS_S = 0.005
DISTANCE_RTOL = 1e-6
"""Measured: 6e-9 on dry concrete, 2.5e-7 on ice (the law's sine is a polynomial within 1e-15 of
the reference's math.sin, which 30 s of ice braking amplify)."""
SLIP_ATOL = 1e-8
"""On the slip at every sample instant above `COMPARED_ABOVE_M_S` (measured: 1e-10 on ice)."""
COMPARED_ABOVE_M_S = 3.0
"""Below it, on ice from 27.8 s, the slow wheel amplifies the reference's clock (t summed in
steps, 1e-11 s off k dt by then) to 0.03 in slip in the last second."""
SINE_ATOL = 1e-12
"""The law's sine against numpy's, phases up to 1200 rad (measured: 3e-16 over one period, the
reduction's rounding growing with the phase to 1.6e-13 at 1200 rad)."""

FAR_START = 0.05
"""theta at the start, a quarter of the peak slip 0.2 of the two roads below."""
PEAK_ROADS = ("dry-concrete", "wet-asphalt")
"""Two roads whose curves peak at slip 0.2 (mu_peak 0.9 and 0.78)."""
FOUND_FROM_S, FOUND_UNTIL_S = 1.5, 3.5
"""The window in which the slip, averaged over each dither period, stays near the peak."""
PEAK_TOL = 0.03
"""Measured: the period means lie in 0.19 .. 0.222 on both roads."""


def _wheel(road: str, params: dict[str, object]):
    return get_plant("abs-wheel").scenario(None, road, LAW, params, 0)


@pytest.mark.parametrize("road", ROADS)
def test_the_ideal_kernel_runs_the_law_as_its_reference(road: str) -> None:
    sc = _wheel(road, {"ts_s": TS_S})
    step, gains = LAWS[LAW]
    ref = closed_loop(step, gains, ROADS[road], ts_s=TS_S, dt_s=sc.plant_params.dt_s)
    g = sc.gains_array(None)
    m = sc.metrics(g[None, :])
    assert m["status"][0] == "stopped" and ref.stopped
    assert abs(m["stop_distance_m"][0] / ref.distance_m - 1.0) < DISTANCE_RTOL
    trace = sc.trace(g).signals
    slip = trace["slip"]
    ticks = np.arange(0, len(slip), round(TS_S / sc.plant_params.dt_s))
    ticks = ticks[trace["vehicle_speed_m_s"][ticks] > COMPARED_ABOVE_M_S]
    n = min(len(ticks), len(ref.slip))
    assert n > 400 and np.ptp(ref.slip[:n]) > 0.1
    assert np.max(np.abs(slip[ticks[:n]] - ref.slip[:n])) < SLIP_ATOL


def test_the_laws_sine_is_the_sine() -> None:
    from numba import njit

    sine = es.sine_form()

    @njit
    def run(xs):
        out = np.empty_like(xs)
        for i in range(xs.size):
            out[i] = sine(xs[i])
        return out

    phases = np.linspace(0.0, 20.0 * 60.0, 20001)  # the largest omega over a minute
    assert np.max(np.abs(run(phases) - np.sin(phases))) < SINE_ATOL


@pytest.mark.parametrize("road", PEAK_ROADS)
def test_started_far_below_the_peak_it_finds_the_peak_without_knowing_the_road(road: str) -> None:
    runs = [_wheel(road, {"ts_s": TS_S, "target_slip": s}) for s in (0.05, 0.45)]
    assert runs[0].tire.slip_opt == 0.2 and runs[0].target_slip != runs[1].target_slip
    traces = [sc.trace(sc.gains_array({"start": FAR_START})).signals for sc in runs]
    for name in ("slip", "vehicle_speed_m_s"):  # the scenario's target slip does not reach the law
        assert np.array_equal(traces[0][name], traces[1][name])
    t, slip = traces[0]["time_s"], traces[0]["slip"]
    assert np.mean(slip[(t >= 0.5) & (t < 1.0)]) < 0.15  # it starts far below the peak
    period = 2.0 * math.pi / next(g.default for g in es.GAINS if g.name == "dither_rad_s")
    starts = np.arange(FOUND_FROM_S, FOUND_UNTIL_S - period + 1e-9, period / 2.0)
    means = np.array([np.mean(slip[(t >= a) & (t < a + period)]) for a in starts])
    assert len(means) >= 5 and t[-1] > FOUND_UNTIL_S
    assert np.all(np.abs(means - 0.2) < PEAK_TOL), means


def test_the_law_reads_no_target_slip() -> None:
    law = es.LAW
    assert not law.needs_target and law.discrete is not None
    assert "target_slip" not in law.discrete.params + law.discrete.inputs


def test_the_realistic_ecus_batch_row_is_its_single_run() -> None:
    sc = _wheel("ice", {"ecu": "realistic"})
    assert_batch_rows_are_single_runs(sc)


@pytest.mark.parametrize(
    ("plant", "road", "params", "bounds"),
    [
        ("abs-wheel", "dry-concrete", {"ecu": "realistic"}, 1.5),
        ("abs-wheel", "ice", {"ecu": "realistic"}, 1.5),
        ("abs-wheel", "burckhardt-snow", {"ecu": "realistic"}, 1.3),
        ("abs-vehicle", "dry-concrete", {}, 1.5),
        ("abs-vehicle", "mu-jump", {}, 1.5),
    ],
)
def test_from_its_defaults_the_law_stops_within_its_bound(
    plant: str, road: str, params: dict[str, object], bounds: float
) -> None:
    sc = get_plant(plant).scenario(None, road, LAW, params, 0)
    m = sc.metrics(sc.gains_array(None)[None, :])
    assert m["status"][0] == "stopped"
    assert m["stop_distance_m"][0] <= bounds * sc.bound_distance_m
