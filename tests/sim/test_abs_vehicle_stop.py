"""Where a vehicle run ends: the end position, heading and lateral offset and the trace's last row
are taken at the stop (inside the last step), not at the end of that step."""

from __future__ import annotations

import math

import numpy as np
import pytest

from chassistune.scenarios.abs_vehicle import PLANT
from chassistune.sim import abs_vehicle_kernel as K

END_METRICS = (K.M_XSTOP, K.M_PSI_END, K.M_Y_END)


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
    """Split-mu without ABS (the car spins: yaw, lateral slip, Newton loads): the end metrics at
    dt 1 ms against dt 0.1 ms, within a hundredth of the distance the car covers in a step."""
    coarse = raw_run("split-mu", "none")
    fine = raw_run("split-mu", "none", dt_s=1e-4)
    assert coarse[K.M_STATUS] == fine[K.M_STATUS] == K.STATUS_STOPPED
    x, psi, y = np.abs(coarse[list(END_METRICS)] - fine[list(END_METRICS)])
    assert x < 1e-4 and psi < 1e-4 and y < 2e-5, (x, psi, y)
