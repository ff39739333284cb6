"""Events inside a step of the vehicle run: the end position, heading and lateral offset and the
trace's last row are taken at the stop, and each wheel's lock time where it locks, not at the end
of the step."""

from __future__ import annotations

import math

import numpy as np
import pytest

from chassistune.scenarios.abs_vehicle import PLANT
from chassistune.sim import abs_vehicle_layout as VL

END_METRICS = (VL.M_XSTOP, VL.M_PSI_END, VL.M_Y_END)


def raw_run(road: str, controller: str, **params: object) -> np.ndarray:
    sc = PLANT.scenario(None, road, controller, params)
    return sc.raw(sc.gains_array(None)[None, :], workers=1)[0]


@pytest.fixture(scope="module")
def straight_stop():
    sc = PLANT.scenario(None, "dry-concrete", "none")
    return sc.plant_params, sc.trace(sc.gains_array(None))


def test_straight_stop_position_is_the_path_length_at_the_stop(straight_stop):
    """In a straight line X is the path length: both at the stop (the step's end lies up to
    v_stop dt = 2 mm further)."""
    _pp, tr = straight_stop
    m = tr.metrics
    assert m["stopped"]
    assert m["stop_x_m"] == pytest.approx(m["stop_distance_m"], abs=1e-5)


def test_trace_last_row_is_the_stop(straight_stop):
    pp, tr = straight_stop
    s, m = tr.signals, tr.metrics
    assert s["time_s"][-1] == m["stop_time_s"] and s["distance_m"][-1] == m["stop_distance_m"]
    assert s["x_m"][-1] == m["stop_x_m"] and s["speed_m_s"][-1] == pp.v_stop_m_s
    assert math.hypot(s["vx_m_s"][-1], s["vy_m_s"][-1]) == pytest.approx(pp.v_stop_m_s, abs=1e-9)


def test_end_position_heading_and_offset_agree_with_a_tenth_of_the_step():
    """Split-mu without ABS, steering fixed (the car spins: yaw, lateral slip, Newton loads): the
    end metrics at dt 1 ms against dt 0.1 ms, within a hundredth of the distance the car covers
    in a step."""
    coarse = raw_run("split-mu", "none", steering="fixed")
    fine = raw_run("split-mu", "none", steering="fixed", dt_s=1e-4)
    assert coarse[VL.M_STATUS] == fine[VL.M_STATUS] == VL.STATUS_STOPPED
    x, psi, y = np.abs(coarse[list(END_METRICS)] - fine[list(END_METRICS)])
    assert x < 1e-4 and psi < 1e-4 and y < 2e-5, (x, psi, y)


def test_lock_times_converge_as_the_step_halves():
    """No ABS on dry concrete (rears lock near 0.111 s, fronts near 0.164 s): against dt/8, the
    lock times' error at dt 1 ms is below 1 % of the step and at least halves with each halving
    (the end of the locking step was up to a step late and did not converge)."""
    dt = 1e-3
    t1, t2, t4, t8 = (
        raw_run("dry-concrete", "none", dt_s=dt / k)[VL.M_LOCK_T : VL.M_LOCK_T + 4]
        for k in (1, 2, 4, 8)
    )
    e1, e2, e4 = (np.abs(t - t8) for t in (t1, t2, t4))
    assert np.all(e1 < 0.01 * dt), e1
    assert np.all(e2 < 0.5 * e1) and np.all(e4 < 0.5 * e2), (e1, e2, e4)
